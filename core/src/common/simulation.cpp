#include "softbody/common/simulation.h"

#include "softbody/common/errors.h"

#include <limits>

namespace softbody
{

void Simulation::setObstacles(std::vector<ObstacleSurface> obstacles, double /*endTime*/)
{
  if (!obstacles.empty())
  {
    throw InvalidInputError("This simulation method cannot collide with obstacles; use a CPU method.");
  }
}

double Simulation::elasticEnergy() const
{
  return std::numeric_limits<double>::quiet_NaN();
}

double Simulation::kineticEnergy() const
{
  const std::vector<double>& w = inverseMasses();
  const std::vector<Vec3>& v = velocities();
  double energy = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    energy += w[i] > 0.0 ? 0.5 * v[i].squaredNorm() / w[i] : 0.0;
  }
  return energy;
}

} // namespace softbody
