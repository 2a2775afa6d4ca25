#include "softbody/massspring/floor_contact.h"

#include "softbody/common/parallel.h"

namespace softbody
{

std::size_t resolveFloorContacts(const FloorPlane& floor, const std::vector<double>& inverseMass,
  std::vector<Vec3>& positions, std::vector<Vec3>& velocities)
{
  // Each point is handled by one task; the count is an order-independent sum.
  return parallelReduce(
    positions.size(), 4096, std::size_t{ 0 },
    [&](std::size_t i) -> std::size_t {
      const double depth = (positions[i] - floor.origin).dot(floor.normal);
      if (depth >= 0.0 || inverseMass[i] == 0.0)
      {
        return 0;
      }
      positions[i] -= depth * floor.normal;
      const double normalSpeed = velocities[i].dot(floor.normal);
      if (normalSpeed < 0.0)
      {
        velocities[i] -= normalSpeed * floor.normal;
      }
      return 1;
    },
    [](std::size_t l, std::size_t r) { return l + r; });
}

} // namespace softbody
