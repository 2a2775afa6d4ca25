// Position corrections applied after each integration step: strain limiting and the floor.
#pragma once

#include "softbody/material.h"

#include <vector>

namespace softbody
{

/// Strain limiting (Provot 1995): springs longer than maxStretch * l0 are shortened back to
/// that length by moving both ends along the spring, in proportion to their inverse masses.
/// Parallel Jacobi iterations in gather form: each vertex moves by the mean of the corrections
/// its violated springs ask of it, so the result does not depend on the number of threads.
/// When `adjustVelocities`, v += dx / h for each moved point (the implicit velocity of
/// position-based integrators such as Verlet). Returns the number of springs found violated
/// in the first iteration.
struct StrainLimitScratch
{
  std::vector<Vec3> edgeCorrection; ///< correction for edge.a (edge.b gets -w_b/w_a of it)
};
std::size_t limitStrain(const Topology& topology, const ElementConstants& constants,
  const std::vector<double>& inverseMass, double maxStretch, int iterations,
  bool adjustVelocities, double h, std::vector<Vec3>& positions, std::vector<Vec3>& velocities,
  StrainLimitScratch& scratch);

/// A floor: the half-space (x - origin) . normal >= 0 is free space.
struct FloorPlane
{
  Vec3 origin{ 0.0, 0.0, 0.0 };
  Vec3 normal{ 0.0, 0.0, 1.0 }; ///< unit length (normalized by the simulation)
};

/// Projects penetrating points onto the plane and cancels their velocity into it (a perfectly
/// inelastic, frictionless contact). Pinned points (inverse mass 0) are left alone.
/// Returns the number of points projected.
std::size_t resolveFloorContacts(const FloorPlane& floor, const std::vector<double>& inverseMass,
  std::vector<Vec3>& positions, std::vector<Vec3>& velocities);

} // namespace softbody
