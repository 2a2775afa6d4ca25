// A scene shared by the convergence test and the convergence benchmark: a cloth without gravity
// stretched uniformly far from rest, then one PBD step, recording the residual after every
// iteration (the thesis's solver comparison).
#pragma once

#include "softbody/pbd/cloth.h"
#include "softbody/pbd/pbd_simulation.h"

#include <memory>

namespace softbody::scenes
{

/// The cloth of `spec`, its particles scaled by `stretch` about the origin, after one step of
/// 1/60 s with the residual recorded after each iteration (convergence().residualHistory).
inline std::unique_ptr<PbdSimulation> stretchedClothAfterOneStep(
  const ClothSpec& spec, PbdSettings settings, double stretch = 16.0)
{
  settings.gravity.setZero();
  auto sim = std::make_unique<PbdSimulation>(makeCloth(spec), settings);
  DynamicState stretched = sim->state();
  for (Vec3& p : stretched.positions)
  {
    p *= stretch;
  }
  sim->restoreState(stretched);
  sim->setRecordResidualsEveryStep(true);
  sim->step(1.0 / 60.0);
  return sim;
}

} // namespace softbody::scenes
