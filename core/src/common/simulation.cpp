#include "softbody/common/simulation.h"

#include "softbody/common/errors.h"

namespace softbody
{

void Simulation::setObstacles(std::vector<ObstacleSurface> obstacles, double /*endTime*/)
{
  if (!obstacles.empty())
  {
    throw InvalidInputError("This simulation method cannot collide with obstacles; use a CPU method.");
  }
}

} // namespace softbody
