// What surrounds the bodies and is the same for every method: gravity, the floor and what is
// collided with. Each rule derived from these settings ("is the floor active?", "do bodies
// collide?") is decided here, once; steppers, planners and the filter ask, never re-derive.
#pragma once

#include "softbody/collision/collision_settings.h"
#include "softbody/common/floor_plane.h"
#include "softbody/common/geometry.h"

namespace softbody
{

/// How the steps are chosen.
enum class StepControl
{
  Fixed,          ///< the method's TimeStep, or its automatic step
  ErrorControlled ///< from a local error estimate, to errorTolerance (common/error_control.h)
};

struct Scene
{
  Vec3 gravity{ 0.0, 0.0, -9.81 }; ///< [m/s^2]
  /// The user's Floor switch. Whether anything touches the floor is floorActive().
  bool floorEnabled = false;
  FloorPlane floor;
  /// Floor, obstacles, bodies, self: what is detected, the margin, and how contacts respond.
  CollisionSettings collisions;
  /// The same for every method that integrates in time (Mass-Spring's dynamic integrators and
  /// XPBD); a method's own TimeStep > 0 is then the largest step.
  StepControl stepControl = StepControl::Fixed;
  /// Error-controlled steps: the error the steps may add over a simulated second [m].
  double errorTolerance = 1.0e-4;
  /// Error control judges each step by step doubling even where the integrator has an
  /// embedded estimate (integrators/local_error.h): three steps a try instead of one. Not a
  /// filter property: the lab measures the two against each other.
  bool stepDoubling = false;
  bool operator==(const Scene&) const = default;

  /// Collisions Off means nothing is collided with, the floor included.
  bool floorActive() const { return floorEnabled && collisions.on(); }
};

/// Refuses a non-finite gravity and, where the floor is active, a bad floor plane (quoting
/// the value given, by property name).
void validateScene(const Scene& scene);

} // namespace softbody
