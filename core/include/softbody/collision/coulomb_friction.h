// Coulomb friction on a velocity: the rule every velocity-level contact response shares
// (mass-spring contacts, the implicit integrators' floor).
#pragma once

#include "softbody/collision/collision_settings.h"
#include "softbody/common/geometry.h"

#include <algorithm>

namespace softbody
{

/// The change of a contact's tangential relative velocity `tangential` that friction makes,
/// given the normal push of the contact over the step as a speed (`normalPush` >= 0): the
/// contact sticks (the change cancels `tangential`) while |tangential| <= staticFriction x
/// push, and otherwise slides, losing dynamicFriction x push of its speed (never reversing).
/// `sticks` says which; without static friction nothing sticks.
inline Vec3 coulombFrictionChange(const Vec3& tangential, double normalPush, const CollisionSettings& settings,
  bool& sticks)
{
  const double slipSpeed = tangential.norm();
  sticks = settings.staticFriction > 0.0 && slipSpeed <= settings.staticFriction * normalPush;
  if (sticks)
  {
    return -tangential;
  }
  if (slipSpeed > 0.0)
  {
    return -std::min(1.0, settings.dynamicFriction * normalPush / slipSpeed) * tangential;
  }
  return Vec3::Zero();
}

} // namespace softbody
