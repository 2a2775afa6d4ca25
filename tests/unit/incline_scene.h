// What the friction tests on an incline share: the tilt that makes the slope, and the downhill
// motion of a body's centre of mass between two times (any stepper, through Simulation).
#pragma once

#include "softbody/common/simulation.h"

#include <cmath>
#include <vector>

namespace softbody::test
{

/// Rotation by `angle` about +y: the +z normal tilts toward -x, so downhill is +x.
inline Vec3 tilt(const Vec3& p, double angle)
{
  return Vec3(std::cos(angle) * p.x() + std::sin(angle) * p.z(), p.y(),
    -std::sin(angle) * p.x() + std::cos(angle) * p.z());
}

/// The mass-weighted mean of `values` (one per point of `sim`; points of inverse mass 0 are
/// infinitely heavy, so none may be pinned).
inline Vec3 massWeightedMean(const Simulation& sim, const std::vector<Vec3>& values)
{
  Vec3 sum = Vec3::Zero();
  double mass = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    const double m = 1.0 / sim.inverseMasses()[i];
    sum += m * values[i];
    mass += m;
  }
  return sum / mass;
}

struct Slide
{
  double acceleration = 0.0; ///< downhill, of the centre of mass, between t1 and t2 [m/s^2]
  double travel = 0.0;       ///< downhill from t1 to t2 [m]
};

/// Advances `sim` to t1 and then to t2, measuring the downhill slide of the slope tilted by
/// `angle` in between.
inline Slide slideBetween(Simulation& sim, double angle, double t1, double t2)
{
  const Vec3 downhill = tilt(Vec3::UnitX(), angle);
  sim.advance(t1);
  const Vec3 start = massWeightedMean(sim, sim.positions());
  const double v1 = massWeightedMean(sim, sim.velocities()).dot(downhill);
  sim.advance(t2);
  const double v2 = massWeightedMean(sim, sim.velocities()).dot(downhill);
  return Slide{ (v2 - v1) / (t2 - t1), (massWeightedMean(sim, sim.positions()) - start).dot(downhill) };
}

} // namespace softbody::test
