#include "softbody/material/material.h"

#include "softbody/common/errors.h"
#include "softbody/common/validation.h"
#include "softbody/material/elastic_laws.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace softbody
{
namespace
{

// Smallest Poisson ratio a central-force spring network can represent (lambda = mu).
constexpr double kNetworkPoissonRatio = 0.25;

struct EnergyConstants
{
  double distancePerVolume = 0.0; ///< k_D,e = distancePerVolume * V_e  [Pa]
  double volumePerVolume = 0.0;   ///< k_V,t = volumePerVolume * V_t    [Pa]
};

EnergyConstants physicalEnergyConstants(const PhysicalMaterial& material)
{
  const double nu = std::max(material.poissonRatio, kNetworkPoissonRatio);
  const double e = material.youngsModulus;
  const double mu = e / (2.0 * (1.0 + nu));
  const double lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  return { 15.0 * mu, lambda - mu };
}

/// Above this nu linear tets lock: their volume constraint leaves too few motions.
constexpr double kLockingPoissonRatio = 0.45;

void validateContinuum(const MaterialSettings& material, std::vector<std::string>& warnings)
{
  if (material.mode != MaterialMode::Physical)
  {
    throw InvalidInputError(std::string("MaterialModel ") + materialModelName(material.model) +
      " takes YoungsModulus and PoissonRatio: set MaterialMode to Physical (the Raw constants "
      "are the spring network's).");
  }
  const PhysicalMaterial& m = material.physical;
  check::positive("YoungsModulus", m.youngsModulus, "Pa");
  check::positive("Density", m.density, "kg/m^3");
  check::nonNegative("DampingTime", m.dampingTime, "s", "undamped");
  check::inRange("PoissonRatio", m.poissonRatio, -1.0, 0.5, true, true);
  if (material.volumetric == VolumetricFormulation::NodalAverage)
  {
    if (m.poissonRatio < 0.0)
    {
      throw InvalidInputError("VolumetricFormulation Nodal Average is for nearly incompressible materials "
        "(PoissonRatio up to 0.5); PoissonRatio " + check::quote(m.poissonRatio) +
        " is auxetic, whose volume term would soften the points: use VolumetricFormulation Per Tet.");
    }
  }
  else if (m.poissonRatio > kLockingPoissonRatio)
  {
    std::ostringstream message;
    message << "PoissonRatio " << m.poissonRatio << " is nearly incompressible: linear tets "
            << "lock (the body responds stiffer than the material, most in bending). Use "
            << "VolumetricFormulation Nodal Average, which does not lock, or refine the mesh "
            << "where it bends.";
    warnings.push_back(message.str());
  }
}

std::string cellRefusal(const char* name, std::size_t cell, const std::string& rule, double value)
{
  return std::string(name) + " of cell " + std::to_string(cell) + " must be " + rule + ", got " +
    check::quote(value) + ".";
}

} // namespace

void validateCells(const MaterialSettings& material, std::size_t tetCount,
  std::vector<std::string>& warnings)
{
  const CellMaterial& c = material.cells;
  if (c.empty())
  {
    return;
  }
  if (material.mode != MaterialMode::Physical)
  {
    throw InvalidInputError("Per-cell YoungsModulus, PoissonRatio or Density arrays need "
                            "MaterialMode Physical (the Raw constants are uniform).");
  }
  const auto checkSize = [&](const char* name, const std::vector<double>& values) {
    if (!values.empty() && values.size() != tetCount)
    {
      throw InvalidInputError(std::string("The per-cell ") + name + " has " +
        std::to_string(values.size()) + " values for " + std::to_string(tetCount) + " tets.");
    }
  };
  checkSize("YoungsModulus", c.youngsModulus);
  checkSize("PoissonRatio", c.poissonRatio);
  checkSize("Density", c.density);
  const bool continuum = isContinuum(material.model);
  std::size_t raised = 0, locking = 0, first = 0;
  for (std::size_t t = 0; t < tetCount; ++t)
  {
    if (!c.youngsModulus.empty() && !(c.youngsModulus[t] > 0.0 && std::isfinite(c.youngsModulus[t])))
    {
      throw InvalidInputError(cellRefusal("YoungsModulus", t, "> 0 Pa", c.youngsModulus[t]));
    }
    if (!c.density.empty() && !(c.density[t] > 0.0 && std::isfinite(c.density[t])))
    {
      throw InvalidInputError(cellRefusal("Density", t, "> 0 kg/m^3", c.density[t]));
    }
    if (c.poissonRatio.empty())
    {
      continue;
    }
    const double nu = c.poissonRatio[t];
    if (continuum ? !(nu > -1.0 && nu < 0.5) : !(nu >= 0.0 && nu < 0.5))
    {
      throw InvalidInputError(cellRefusal("PoissonRatio", t, continuum ? "in (-1, 0.5)" : "in [0, 0.5)", nu));
    }
    const bool nodal = material.volumetric == VolumetricFormulation::NodalAverage;
    const bool said = continuum ? nu > kLockingPoissonRatio && !nodal : nu < kNetworkPoissonRatio;
    first = said && raised + locking == 0 ? t : first;
    (continuum ? locking : raised) += said ? 1 : 0;
  }
  if (raised > 0)
  {
    warnings.push_back("PoissonRatio is below " + check::quote(kNetworkPoissonRatio) + " in " +
      std::to_string(raised) + " cells (the first: cell " + std::to_string(first) + ", " +
      check::quote(c.poissonRatio[first]) + "), the smallest a mass-spring network can represent; " +
      check::quote(kNetworkPoissonRatio) + " is used there.");
  }
  if (locking > 0)
  {
    warnings.push_back("PoissonRatio is nearly incompressible in " + std::to_string(locking) +
      " cells (the first: cell " + std::to_string(first) + ", " + check::quote(c.poissonRatio[first]) +
      "): linear tets lock there (respond stiffer than the material). Use VolumetricFormulation "
      "Nodal Average, which does not lock, or refine the mesh there.");
  }
}

const char* materialModelName(MaterialModel model)
{
  if (!isContinuum(model))
  {
    return "Spring Network";
  }
  return withElasticLaw(model, [](auto law) { return decltype(law)::kName; });
}

void validateMaterial(const MaterialSettings& material, std::vector<std::string>& warnings,
  std::size_t tetCount)
{
  validateCells(material, tetCount, warnings);
  if (isContinuum(material.model))
  {
    validateContinuum(material, warnings);
  }
  else if (material.volumetric == VolumetricFormulation::NodalAverage)
  {
    throw InvalidInputError(std::string("VolumetricFormulation Nodal Average averages a continuum model's "
      "volume term at the points; MaterialModel ") + materialModelName(material.model) +
      " has none: choose Corotated or Stable Neo-Hookean, or VolumetricFormulation Per Tet.");
  }
  else if (material.mode == MaterialMode::Physical)
  {
    const PhysicalMaterial& m = material.physical;
    check::positive("YoungsModulus", m.youngsModulus, "Pa");
    check::positive("Density", m.density, "kg/m^3");
    check::nonNegative("DampingTime", m.dampingTime, "s", "undamped");
    check::inRange("PoissonRatio", m.poissonRatio, 0.0, 0.5, false, true);
    if (m.poissonRatio < kNetworkPoissonRatio)
    {
      std::ostringstream message;
      message << "PoissonRatio " << m.poissonRatio << " is below " << kNetworkPoissonRatio
              << ", the smallest a mass-spring network can represent; " << kNetworkPoissonRatio
              << " is used.";
      warnings.push_back(message.str());
    }
  }
  else
  {
    const RawConstants& r = material.raw;
    check::nonNegative("DistanceStiffness", r.distanceStiffness, "J");
    check::nonNegative("DistanceDamping", r.distanceDamping, "J s");
    check::nonNegative("VolumeStiffness", r.volumeStiffness, "J");
    check::nonNegative("VolumeDamping", r.volumeDamping, "J s");
    check::positive("TotalMass", r.totalMass, "kg");
  }
  check::nonNegative("MaxInverseMass", material.maxInverseMass, "1/kg", "off");
}

std::vector<double> tetMasses(const MaterialSettings& material, const std::vector<double>& restVolume)
{
  std::vector<double> masses(restVolume.size());
  for (std::size_t t = 0; t < restVolume.size(); ++t)
  {
    masses[t] = material.physicalOf(t).density * restVolume[t];
  }
  return masses;
}

double totalMassOf(const MaterialSettings& material, double restVolume)
{
  return material.mode == MaterialMode::Physical ? material.physical.density * restVolume
                                                 : material.raw.totalMass;
}

ElementConstants computeElementConstants(const Topology& topology,
  const std::vector<Vec3>& restPositions, const MaterialSettings& material,
  std::vector<std::string>& warnings)
{
  validateMaterial(material, warnings, topology.tets.size());
  const std::size_t edgeCount = topology.edges.size();
  const std::size_t tetCount = topology.tets.size();

  ElementConstants c;
  c.restLength.resize(edgeCount);
  c.springStiffness.resize(edgeCount);
  c.springDamping.resize(edgeCount);
  c.restVolume.resize(tetCount);
  c.volumeStiffness.resize(tetCount);
  c.volumeDamping.resize(tetCount);

  // A continuum model keeps only the network's geometry (rest lengths and volumes: the stretch
  // check, strain limit and volume ratios use them) and its damping time; its stiffness lives
  // in tet_elasticity.h's constants, so no spring here can stiffen it.
  const bool physical = material.mode == MaterialMode::Physical;
  const bool network = physical && !isContinuum(material.model);
  const EnergyConstants perVolume =
    network ? physicalEnergyConstants(material.physical) : EnergyConstants{};
  // Per-cell moduli: each tet's share of an edge's spring carries that tet's moduli.
  const bool perCell =
    network && !(material.cells.youngsModulus.empty() && material.cells.poissonRatio.empty());
  std::vector<EnergyConstants> tetPerVolume(perCell ? tetCount : 0);
  for (std::size_t t = 0; t < tetPerVolume.size(); ++t)
  {
    tetPerVolume[t] = physicalEnergyConstants(material.physicalOf(t));
  }

  // Volume attributed to each edge: a sixth of each tet around it (per cell: that volume times
  // the tet's distance constant, so edgeVolume holds k_D directly).
  std::vector<double> edgeVolume(edgeCount, 0.0);
  for (std::size_t t = 0; t < tetCount; ++t)
  {
    const Tet& tet = topology.tets[t];
    c.restVolume[t] = signedTetVolume(
      restPositions[tet[0]], restPositions[tet[1]], restPositions[tet[2]], restPositions[tet[3]]);
    const double share = perCell ? tetPerVolume[t].distancePerVolume : 1.0;
    for (int k = 0; k < 6; ++k)
    {
      edgeVolume[topology.tetEdges.items[6 * t + k]] += perCell ? share * c.restVolume[t] / 6.0
                                                                : c.restVolume[t] / 6.0;
    }
  }
  const double beta = material.physical.dampingTime;

  for (std::size_t e = 0; e < edgeCount; ++e)
  {
    const Edge& edge = topology.edges[e];
    const double l0 = (restPositions[edge.b] - restPositions[edge.a]).norm();
    c.restLength[e] = l0;
    const double kD = perCell ? edgeVolume[e]
      : physical              ? perVolume.distancePerVolume * edgeVolume[e]
                              : material.raw.distanceStiffness;
    const double kDd = physical ? beta * kD : material.raw.distanceDamping;
    c.springStiffness[e] = kD / (l0 * l0);
    c.springDamping[e] = kDd / (l0 * l0);
  }
  for (std::size_t t = 0; t < tetCount; ++t)
  {
    const double v0 = c.restVolume[t];
    const double kV = perCell ? tetPerVolume[t].volumePerVolume * v0
      : physical              ? perVolume.volumePerVolume * v0
                              : material.raw.volumeStiffness;
    const double kVd = physical ? beta * kV : material.raw.volumeDamping;
    c.volumeStiffness[t] = kV / (v0 * v0);
    c.volumeDamping[t] = kVd / (v0 * v0);
    c.hasVolumeTerm = c.hasVolumeTerm || kV > 0.0 || kVd > 0.0;
  }

  if (physical)
  {
    c.minDampingTime = c.maxDampingTime = beta;
  }
  else
  {
    // Each element family has its own ratio k_d / k; an undefined ratio (k = 0) is ignored.
    const RawConstants& r = material.raw;
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
    auto include = [&](double k, double kd) {
      if (k > 0.0)
      {
        lo = std::min(lo, kd / k);
        hi = std::max(hi, kd / k);
      }
    };
    include(r.distanceStiffness, r.distanceDamping);
    include(r.volumeStiffness, r.volumeDamping);
    c.minDampingTime = std::isfinite(lo) ? lo : 0.0;
    c.maxDampingTime = hi;
  }
  return c;
}

} // namespace softbody
