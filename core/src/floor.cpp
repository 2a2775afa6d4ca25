#include "softbody/constraints.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

namespace softbody
{

std::size_t resolveFloorContacts(const FloorPlane& floor, const std::vector<double>& inverseMass,
  std::vector<Vec3>& positions, std::vector<Vec3>& velocities)
{
  // Each point is handled by one task; the count is an order-independent sum.
  return tbb::parallel_reduce(
    tbb::blocked_range<std::size_t>(0, positions.size(), 4096), std::size_t{ 0 },
    [&](const tbb::blocked_range<std::size_t>& r, std::size_t count) {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
      {
        const double depth = (positions[i] - floor.origin).dot(floor.normal);
        if (depth >= 0.0 || inverseMass[i] == 0.0)
        {
          continue;
        }
        positions[i] -= depth * floor.normal;
        const double normalSpeed = velocities[i].dot(floor.normal);
        if (normalSpeed < 0.0)
        {
          velocities[i] -= normalSpeed * floor.normal;
        }
        ++count;
      }
      return count;
    },
    [](std::size_t l, std::size_t r) { return l + r; });
}

} // namespace softbody
