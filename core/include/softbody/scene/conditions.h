// Loads and boundary conditions as the user states them: each names a set of the body's points
// and what happens to it (held, moved, pushed, pulled), in SI units, as a function of time.
// What a stepper needs from them (held components, forces at a state, reactions) is
// boundary_conditions.h; this file only describes and validates.
#pragma once

#include "softbody/common/geometry.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace softbody
{

enum class ConditionKind
{
  Fixed,      ///< the chosen components of the set's points stay at their rest values
  Prescribed, ///< the set moves rigidly: a translation and a rotation about a point, over time
  Force,      ///< a force [N] on the set (a total spread over it, or one per point)
  Pressure,   ///< a pressure [Pa] on the body's boundary faces whose corners are all in the set
  Pull        ///< a spring [N/m] from the set's centroid to a target point
};

/// The kind's name as the filters' ConditionType calls it ("Fixed", "Prescribed Motion", ...).
const char* conditionKindName(ConditionKind kind);

/// How a Force condition's force is shared between the set's points.
enum class ForceSpread
{
  ByMass,  ///< the total force, shared in proportion to the points' masses (a body force)
  ByArea,  ///< the total force, shared in proportion to the set's boundary-face area (a traction)
  PerPoint ///< the force on every point of the set
};

enum class TimeProfileShape
{
  Constant,  ///< 1 at every time
  Ramp,      ///< 0 at t = 0 rising linearly to 1 at t = duration, then 1
  Sinusoid,  ///< sin(2 pi t / duration): duration is the period
  Keyframes  ///< piecewise linear through (times, factors); the end values held outside
};

/// The factor s(t) a condition's load or motion is scaled by.
struct TimeProfile
{
  TimeProfileShape shape = TimeProfileShape::Constant;
  double duration = 1.0; ///< Ramp: rise time; Sinusoid: period [s]
  std::vector<double> times;   ///< Keyframes: increasing times [s]
  std::vector<double> factors; ///< Keyframes: the factor at each time
  bool operator==(const TimeProfile&) const = default;

  double at(double t) const;
  double rate(double t) const;         ///< ds/dt [1/s] (a kink takes the later side)
  double acceleration(double t) const; ///< d2s/dt2 [1/s^2] (0 along linear pieces)
};

struct Condition
{
  std::string name; ///< quoted in every message about it
  ConditionKind kind = ConditionKind::Fixed;
  /// The set: indices of body points (any order; repeats are refused).
  std::vector<std::int32_t> points;
  /// Fixed and Prescribed: which of x, y, z are held (a roller holds one). The others are free.
  std::array<bool, 3> heldAxes{ true, true, true };

  // Prescribed: at time t a rest point X is at c + R(s angle) (X - c) + s translation, with
  // s = profile.at(t), R a rotation about `rotationAxis` through c = rotationCenter.
  Vec3 translation{ 0.0, 0.0, 0.0 }; ///< [m]
  Vec3 rotationAxis{ 0.0, 0.0, 1.0 };
  Vec3 rotationCenter{ 0.0, 0.0, 0.0 }; ///< [m]
  double rotationAngle = 0.0;           ///< [rad]

  Vec3 force{ 0.0, 0.0, 0.0 }; ///< Force [N], scaled by the profile
  ForceSpread spread = ForceSpread::ByMass;
  /// Pressure [Pa], scaled by the profile: each face is pushed along its outward normal by
  /// pressure times its area (positive inflates, like a gas inside; negative presses in).
  /// The faces follow the body: the force is evaluated on the deformed faces.
  double pressure = 0.0;
  Vec3 pullTarget{ 0.0, 0.0, 0.0 }; ///< Pull [m]
  double pullStiffness = 0.0;        ///< Pull [N/m], scaled by the profile

  TimeProfile profile; ///< scales the motion (Prescribed) or the load; unused by Fixed
  bool operator==(const Condition&) const = default;

  bool holds() const { return kind == ConditionKind::Fixed || kind == ConditionKind::Prescribed; }
};

/// Refuses what no simulation can use, quoting the value given and naming the condition:
/// points outside 0 .. pointCount-1 or repeated, non-finite values, a Fixed or Prescribed
/// condition holding no component, a zero rotation axis with a nonzero angle, a negative
/// stiffness, a profile without a positive duration or with keyframes out of order; and two
/// conditions holding the same component of a point to different motions (naming the point).
/// Adds a warning per condition whose set is empty.
void validateConditions(const std::vector<Condition>& conditions, std::size_t pointCount,
  std::vector<std::string>& warnings);

} // namespace softbody
