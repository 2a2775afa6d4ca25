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
  if (!State.impactSpeeds.empty())
  {
    applyBodyRestitution(h);
  }
}

void PbdSimulation::applyBodyRestitution(double h)
{
  // Restitution point by point is exact only where a body's points all hit at once (a flat
  // cloth, loose particles). A tet body hits with its bottom layer: those points leave at e v,
  // the constraints give that momentum back to the rest of the body, which still moves down,
  // and the body comes to rest over a few substeps whatever e is. So restitution also acts on
  // whole bodies: when a body first touches while its centre of mass approaches faster than
  // the resting speed, that speed I is recorded; when the body has left the floor again or has
  // stopped on it (two substeps in a row), its centre of mass gets the normal speed it lacks
  // to leave at e I. It only adds: a body that bounces by its own elasticity keeps it.
  const Vec3& n = Settings.floor.normal;
  const double restingSpeed = 2.0 * Settings.gravity.norm() * h;
  const double e = Settings.restitution;
  const std::size_t bodies = BodyFirstPoint.size();
  std::vector<double> mass(bodies, 0.0), before(bodies, 0.0), after(bodies, 0.0);
  std::vector<char> touching(bodies, 0), held(bodies, 0);
  for (std::size_t i = 0; i < State.positions.size(); ++i)
  {
    const std::int32_t b = BodyOf[i];
    if (InverseMass[i] == 0.0)
    {
      held[b] = 1;
      continue;
    }
    const double m = 1.0 / InverseMass[i];
    mass[b] += m;
    before[b] += m * VelocityBefore[i].dot(n);
    after[b] += m * State.velocities[i].dot(n);
    if (InContact[i])
    {
      touching[b] = 1;
    }
  }
  std::vector<double> boost(bodies, 0.0), impact(bodies, 0.0);
  for (std::size_t b = 0; b < bodies; ++b)
  {
    if (held[b] || mass[b] == 0.0)
    {
      continue;
    }
    const double vBefore = before[b] / mass[b], vAfter = after[b] / mass[b];
    double speed = State.impactSpeeds[BodyFirstPoint[b]];
    if (speed == 0.0 && touching[b] && vBefore < -restingSpeed)
    {
      speed = -vBefore;
    }
    if (speed != 0.0 && vAfter > -restingSpeed)
    {
      const double I = std::abs(speed);
      const bool left = !touching[b];
      const bool stopped = touching[b] && vAfter < restingSpeed;
      if (left || (stopped && speed < 0.0))
      {
        const double add = e * I - vAfter;
        boost[b] = add > 1e-6 * I ? add : 0.0;
        speed = 0.0;
      }
      else
      {
        speed = stopped ? -I : I; // stopped once: wait one substep (a rebound passes zero)
      }
    }
    impact[b] = speed;
  }
  for (std::size_t i = 0; i < State.positions.size(); ++i)
  {
    const std::int32_t b = BodyOf[i];
    State.impactSpeeds[i] = impact[b];
    if (boost[b] != 0.0 && InverseMass[i] > 0.0)
    {
      State.velocities[i] += boost[b] * n;
    }
  }
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
