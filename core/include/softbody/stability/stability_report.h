// Mesh quality as the mass-spring model sees it: per-tet shape (dihedral angles, slivers,
// inverted and degenerate tets) and what the mesh does to the simulation (inverse-mass spread,
// largest stable explicit step, and how much an inverse-mass truncation would raise it).
//
// The mass-spring thesis plots three histograms per mesh (inverse mass, tet volume, edge
// length) because the lightest points and the smallest elements set the stable step:
// h ~ 2 / w_max with w_max^2 <= max_i w_i * (stiffness around i). This report computes them
// with the model's own code (buildTopology, computeElementConstants, distributeMass,
// highestFrequencyBound, stableTimeStep), so its numbers are the simulation's numbers.
#pragma once

#include "softbody/integrators/integrator.h"
#include "softbody/material/material.h"
#include "softbody/mesh/tet_mesh.h"

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace softbody
{

/// Default sliver threshold [degrees]. A sliver has four well-spread points nearly in a plane:
/// its edges look fine but a dihedral angle is near 0 (or 180), so its volume gradients are
/// huge compared to its volume and the volume term's stiffness k_V / V0^2 explodes. 5 degrees
/// is well below what quality meshers guarantee (TetGen's default bound is about 5-10 degrees
/// after optimization; a regular tet has 70.5), so only tets no mesher would keep are flagged.
constexpr double kSliverDihedralDegrees = 5.0;

/// Counts over fixed, equal-width bins covering [min, max] of the finite values.
struct Histogram
{
  double min = 0.0;                ///< lower edge of the first bin
  double max = 0.0;                ///< upper edge of the last bin
  std::vector<double> binCenters;  ///< one per bin
  std::vector<std::size_t> counts; ///< one per bin; they sum to the number of finite values
};

/// Histogram with `binCount` (>= 1) bins over the range of the finite values (non-finite ones
/// are not counted). All values equal: the range is widened around them so the bins stay
/// ordered; no values: all counts are 0 over [0, 1].
Histogram makeHistogram(const std::vector<double>& values, std::size_t binCount);

struct MeshQualitySettings
{
  double sliverDihedralDegrees = kSliverDihedralDegrees; ///< min dihedral below this: sliver
  std::size_t binCount = 32;                             ///< bins of each histogram
  /// Mass the suggested inverse-mass truncation may add, as a fraction of the body's mass (>= 0).
  double truncationMassBudget = 0.01;
};

/// Everything the quality filter shows. Per-tet arrays follow the input tet order, per-point
/// arrays the input point order.
struct MassSpringQualityReport
{
  // Per tet. Tets with bad indices or non-finite points have NaN geometry and no flags.
  std::vector<double> signedVolume;      ///< [m^3], input orientation
  std::vector<double> minDihedralDegrees;
  std::vector<char> inverted;            ///< negative volume and not degenerate
  std::vector<char> degenerate;          ///< |V| <= kDegenerateRelativeVolume * mean |V|
  std::vector<char> sliver;              ///< not degenerate, min dihedral below the threshold

  // Per point: as the simulation would distribute it, untruncated. 0 for points in no usable
  // tet (degenerate tets get no mass: the simulation refuses them, see prepareTetMesh).
  std::vector<double> inverseMass;       ///< [1/kg]

  /// Unique edges of the tets with valid indices and finite points.
  std::vector<double> edgeLength;        ///< [m]

  Histogram inverseMassHistogram;        ///< over points with inverse mass > 0
  Histogram volumeHistogram;             ///< signed volume, over tets with computable volume
  Histogram edgeLengthHistogram;

  TetMeshReport mesh;                    ///< inspectTetMesh's counts (invalid, inverted, ...)
  std::size_t invertedTets = 0;
  std::size_t degenerateTets = 0;
  std::size_t sliverTets = 0;
  double minDihedralDegreesOverall = 0.0; ///< smallest over non-degenerate tets; NaN if none
  double sliverThresholdDegrees = 0.0;

  double totalMass = 0.0;               ///< [kg] untruncated
  double highestFrequency = 0.0;        ///< bound on w_max [rad/s], untruncated
  double stableTimeStep = 0.0;          ///< [s] for the integrator, untruncated; 0: none stable

  /// [1/kg]: the lowest inverse-mass cap (MaxInverseMass) that adds at most
  /// truncationMassBudget of the body's mass. Lighter points set the stable step
  /// (w_max^2 <= max_i w_i * stiffness around i), so among caps that keep the mass within the
  /// budget this one gives the largest step; a lower cap would only buy step with more mass.
  double suggestedMaxInverseMass = 0.0;
  std::size_t truncatedPoints = 0;      ///< points that truncation at the suggestion changes
  double truncatedTotalMass = 0.0;      ///< [kg] after truncation (>= totalMass)
  double truncatedHighestFrequency = 0.0;
  double truncatedStableTimeStep = 0.0; ///< [s]
  /// truncatedStableTimeStep / stableTimeStep; 1 when neither is stable.
  double stableStepGain = 1.0;

  std::vector<std::string> warnings;    ///< from the material checks and mesh preparation
};

/// Computes the report. Inverted tets are measured and counted, and their masses computed on a
/// re-oriented copy (as the simulation's Reorient policy does); degenerate tets and tets with
/// bad indices or non-finite points are counted and left out of masses and step estimates.
/// Throws InvalidInputError only for out-of-range material parameters or settings.
MassSpringQualityReport computeMassSpringQuality(const TetMesh& mesh,
  const MaterialSettings& material, Integrator integrator,
  const MeshQualitySettings& settings = MeshQualitySettings());

} // namespace softbody
