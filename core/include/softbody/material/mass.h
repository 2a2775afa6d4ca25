// Distribution of a body's mass over its points, with optional inverse-mass truncation.
#pragma once

#include "softbody/material/material.h"

#include <cstddef>
#include <vector>

namespace softbody
{

struct PointMasses
{
  std::vector<double> mass;        ///< [kg], after truncation; 0 for points in no tet
  std::vector<double> inverseMass; ///< [1/kg]; 0 for pinned points and points in no tet
  std::size_t truncatedCount = 0;  ///< points whose inverse mass was truncated
  double totalMass = 0.0;          ///< sum of mass (>= requested when truncation applied)
};

/// Distributes `totalMass` over the points of `topology` in proportion to the chosen volume
/// measure, then truncates inverse masses above `maxInverseMass` (0: no truncation).
/// `pinned` (empty or one flag per point) gives inverse mass 0 without changing the mass.
PointMasses distributeMass(const Topology& topology, const std::vector<double>& restVolume,
  double totalMass, MassDistribution scheme, double maxInverseMass,
  const std::vector<char>& pinned);

} // namespace softbody
