// PbdSimulation: what happens to the links after a step (plastic flow, breaking).
#include "softbody/pbd/pbd_simulation.h"

#include "softbody/common/parallel.h"
#include "softbody/common/stepping.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace softbody
{

void PbdSimulation::updateLinks(double h)
{
  ScopedStageTimer timer(Plan, Stage::UpdateLinks);
  const std::vector<Vec3>& x = State.positions;
  const double breaking = Settings.breakingStrain;
  const double yield = Settings.plasticYield;
  const double flow = std::min(1.0, Settings.plasticCreep * h);
  parallelFor(Links.size(), 1024, [&](std::size_t c) {
    if (Links.broken[c])
    {
      return;
    }
    const double length = (x[Links.ends[c][0]] - x[Links.ends[c][1]]).norm();
    if (yield > 0.0)
    {
      // Inside the yield band the link is elastic; past it the rest length creeps toward the
      // length that would put it back on the band's edge.
      const double excess = length - Links.rest[c];
      const double band = yield * Links.rest[c];
      if (std::abs(excess) > band)
      {
        Links.rest[c] += flow * (excess - std::copysign(band, excess));
      }
    }
    if (breaking > 0.0 && std::abs(length - Links.originalRest[c]) > breaking * Links.originalRest[c])
    {
      Links.broken[c] = 1;
    }
  });
  if (breaking > 0.0)
  {
    markBrokenTets();
  }
}

void PbdSimulation::markBrokenTets()
{
  if (TetEdges.rowCount() == 0)
  {
    return;
  }
  parallelFor(Volumes.size(), 1024, [&](std::size_t t) {
    unsigned char broken = 0;
    for (std::int32_t k = TetEdges.offsets[t]; k < TetEdges.offsets[t + 1]; ++k)
    {
      broken |= Links.broken[static_cast<std::size_t>(TetEdges.items[static_cast<std::size_t>(k)])];
    }
    Volumes.broken[t] = broken;
  });
}

} // namespace softbody
