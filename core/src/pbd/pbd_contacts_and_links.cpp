// PbdSimulation: what happens at the floor (projection each iteration, then restitution and
// Coulomb friction on the velocities) and to the links after a step (plastic flow, breaking).
#include "softbody/pbd/pbd_simulation.h"

#include "softbody/common/parallel.h"
#include "softbody/common/stepping.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace softbody
{

void PbdSimulation::projectFloor()
{
  const FloorPlane& floor = Settings.floor;
  parallelFor(Predicted.size(), 1024, [&](std::size_t i) {
    const Projection<1> p =
      projectPlane(Predicted[i], InverseMass[i], floor.origin, floor.normal, Settings.particleRadius);
    if (p.dLambda != 0.0)
    {
      Predicted[i] += p.dx[0];
      InContact[i] = 1;
      FloorPush[i] += p.dx[0].dot(floor.normal);
    }
  });
}

void PbdSimulation::applyContactResponse(double h)
{
  ScopedStageTimer timer(Plan, Stage::ContactResponse);
  const Vec3& n = Settings.floor.normal;
  // Below this approach speed a contact is resting: bouncing it would make bodies jitter.
  const double restingSpeed = 2.0 * Settings.gravity.norm() * h;
  parallelFor(State.positions.size(), 1024, [&](std::size_t i) {
    if (!InContact[i])
    {
      return;
    }
    Vec3& v = State.velocities[i];
    const double incoming = VelocityBefore[i].dot(n); // < 0 when approaching
    double normal = v.dot(n);
    Vec3 tangential = v - normal * n;
    if (incoming < -restingSpeed)
    {
      normal = std::max(normal, -Settings.restitution * incoming);
    }
    // Coulomb: the tangential speed drops by at most mu times the normal impulse per unit mass.
    // That impulse is the normal speed change plus what the floor pushed beyond stopping this
    // particle: the weight of the particles above it, carried down by the constraints (the
    // floor's corrections over the iterations, FloorPush / h). Without that term a body with
    // more than one layer of particles gets the friction of its bottom layer's weight only.
    const double carried = std::max(0.0, FloorPush[i] / h + incoming);
    const double normalChange = std::max(0.0, normal - incoming) + carried;
    const double speed = tangential.norm();
    if (speed > 0.0)
    {
      tangential *= std::max(0.0, 1.0 - Settings.friction * normalChange / speed);
    }
    v = tangential + normal * n;
  });
}

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
