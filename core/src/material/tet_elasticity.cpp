#include "softbody/material/tet_elasticity.h"

#include "softbody/common/errors.h"
#include "softbody/common/validation.h"

#include <Eigen/LU>

namespace softbody
{

TetElasticConstants computeTetElasticConstants(const Topology& topology,
  const std::vector<Vec3>& restPositions, const MaterialSettings& material,
  std::vector<std::string>& warnings)
{
  validateMaterial(material, warnings, topology.tets.size());
  if (!isContinuum(material.model))
  {
    throw InvalidInputError(std::string("computeTetElasticConstants: ") +
      materialModelName(material.model) + " is not a continuum model");
  }
  const std::size_t tetCount = topology.tets.size();
  TetElasticConstants c;
  c.model = material.model;
  c.shapeGradients.resize(tetCount);
  c.restVolume.resize(tetCount);
  c.linear.resize(tetCount);
  c.law.resize(tetCount);
  c.dampingTime.assign(tetCount, material.physical.dampingTime);
  for (std::size_t t = 0; t < tetCount; ++t)
  {
    const PhysicalMaterial m = material.physicalOf(t);
    c.linear[t] = lameFromYoung(m.youngsModulus, m.poissonRatio);
    c.law[t] = withElasticLaw(
      material.model, [&](auto lawType) { return decltype(lawType)::fromLinear(c.linear[t]); });
    const Tet& tet = topology.tets[t];
    const Vec3& x0 = restPositions[tet[0]];
    Mat3 shape;
    shape << restPositions[tet[1]] - x0, restPositions[tet[2]] - x0, restPositions[tet[3]] - x0;
    c.restVolume[t] = shape.determinant() / 6.0;
    // Rows of the inverse rest shape are g_1..g_3 (F = Ds Dm^-1). The mesh checks refuse
    // degenerate tets before this, so the inverse exists.
    const Mat3 inverse = shape.inverse();
    std::array<Vec3, 4>& g = c.shapeGradients[t];
    g[1] = inverse.row(0).transpose();
    g[2] = inverse.row(1).transpose();
    g[3] = inverse.row(2).transpose();
    g[0] = -(g[1] + g[2] + g[3]);
  }
  if (material.volumetric == VolumetricFormulation::NodalAverage)
  {
    c.nodalPressure = true;
    std::vector<double> lambda(tetCount);
    for (std::size_t t = 0; t < tetCount; ++t)
    {
      lambda[t] = c.law[t].lambda;
      const double nu = material.physicalOf(t).poissonRatio;
      if (nu < 0.0)
      {
        throw InvalidInputError("VolumetricFormulation Nodal Average is for nearly incompressible materials: "
          "PoissonRatio of cell " + std::to_string(t) + " is " + check::quote(nu) +
          " (auxetic), whose volume term would soften the points. Use VolumetricFormulation Per Tet.");
      }
    }
    c.nodal = computeNodalPressureConstants(topology, c.restVolume, lambda);
  }
  return c;
}

} // namespace softbody
