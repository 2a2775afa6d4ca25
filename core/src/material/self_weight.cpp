#include "softbody/material/self_weight.h"

#include "softbody/mesh/components.h"

#include <algorithm>
#include <limits>
#include <sstream>

namespace softbody
{

SelfWeight selfWeightStrain(const TetMesh& mesh, const std::vector<double>& restVolume,
  const MaterialSettings& material, const Vec3& gravity)
{
  const double g = gravity.norm();
  if (material.mode != MaterialMode::Physical || !(g > 0.0) || mesh.tets.empty())
  {
    return {};
  }
  const Vec3 down = gravity / g;
  const Components bodies = tetComponents(mesh.points.size(), mesh.tets);

  struct Sums
  {
    double low = std::numeric_limits<double>::infinity();
    double high = -std::numeric_limits<double>::infinity();
    double volume = 0.0, densityVolume = 0.0, modulusVolume = 0.0;
  };
  std::vector<Sums> sums(static_cast<std::size_t>(bodies.count));
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
  {
    Sums& s = sums[static_cast<std::size_t>(bodies.ofCell[t])];
    for (std::int32_t v : mesh.tets[t])
    {
      const double along = mesh.points[static_cast<std::size_t>(v)].dot(down);
      s.low = std::min(s.low, along);
      s.high = std::max(s.high, along);
    }
    const PhysicalMaterial m = material.physicalOf(t);
    s.volume += restVolume[t];
    s.densityVolume += m.density * restVolume[t];
    s.modulusVolume += m.youngsModulus * restVolume[t];
  }
  SelfWeight worst;
  for (const Sums& s : sums)
  {
    if (!(s.volume > 0.0) || !(s.modulusVolume > 0.0))
    {
      continue;
    }
    SelfWeight body;
    body.height = s.high - s.low;
    body.density = s.densityVolume / s.volume;
    body.youngsModulus = s.modulusVolume / s.volume;
    body.strain = body.density * g * body.height / body.youngsModulus;
    worst = body.strain > worst.strain ? body : worst;
  }
  return worst;
}

std::string selfWeightWarning(const SelfWeight& weight)
{
  if (!(weight.strain >= kCollapsingSelfWeightStrain))
  {
    return "";
  }
  std::ostringstream message;
  message.precision(3);
  message << "The body cannot carry its own weight: " << weight.height << " m tall along gravity, density "
          << weight.density << " kg/m^3 and YoungsModulus " << weight.youngsModulus
          << " Pa strain it by rho g H / E = " << weight.strain
          << " where it is held (the floor or its fixed points), more than any strain the material "
             "resists, so it collapses under gravity (and may blow up) at any TimeStep. Check the "
             "mesh's units (millimetres read as metres make it 1000x taller), or take a YoungsModulus "
             "well above rho g H = "
          << weight.youngsModulus * weight.strain << " Pa (10x that strains it by 0.1).";
  return message.str();
}

} // namespace softbody
