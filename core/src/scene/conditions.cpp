#include "softbody/scene/conditions.h"

#include "softbody/common/errors.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace softbody
{
namespace
{

std::string quoted(const Condition& c)
{
  return "Condition '" + c.name + "' (" + conditionKindName(c.kind) + ")";
}

bool finite(const Vec3& v)
{
  return v.allFinite();
}

void refuse(const Condition& c, const std::string& what)
{
  throw InvalidInputError(quoted(c) + ": " + what);
}

void validateProfile(const Condition& c)
{
  const TimeProfile& p = c.profile;
  if ((p.shape == TimeProfileShape::Ramp || p.shape == TimeProfileShape::Sinusoid) &&
      !(p.duration > 0.0 && std::isfinite(p.duration)))
  {
    std::ostringstream s;
    s << "the profile's time (ramp duration or period) must be positive and finite, but it is "
      << p.duration << " s.";
    refuse(c, s.str());
  }
  if (p.shape != TimeProfileShape::Keyframes)
  {
    return;
  }
  if (p.times.empty() || p.times.size() != p.factors.size())
  {
    std::ostringstream s;
    s << "keyframes need one factor per time and at least one key, but there are "
      << p.times.size() << " times and " << p.factors.size() << " factors.";
    refuse(c, s.str());
  }
  for (std::size_t k = 0; k < p.times.size(); ++k)
  {
    if (!std::isfinite(p.times[k]) || !std::isfinite(p.factors[k]) ||
        (k > 0 && !(p.times[k] > p.times[k - 1])))
    {
      std::ostringstream s;
      s << "keyframe " << k << " (time " << p.times[k] << " s, factor " << p.factors[k]
        << ") is not finite or not after the previous key; keyframe times must increase.";
      refuse(c, s.str());
    }
  }
}

void validateValues(const Condition& c)
{
  std::ostringstream s;
  switch (c.kind)
  {
    case ConditionKind::Fixed:
      break;
    case ConditionKind::Prescribed:
      if (!finite(c.translation) || !finite(c.rotationAxis) || !finite(c.rotationCenter) ||
          !std::isfinite(c.rotationAngle))
      {
        refuse(c, "its translation, rotation axis, center and angle must be finite.");
      }
      if (c.rotationAngle != 0.0 && !(c.rotationAxis.norm() > 0.0))
      {
        s << "it rotates by " << c.rotationAngle * 180.0 / std::numbers::pi
          << " degrees about a zero axis; give the rotation axis a direction.";
        refuse(c, s.str());
      }
      break;
    case ConditionKind::Force:
      if (!finite(c.force))
      {
        s << "the force (" << c.force.x() << ", " << c.force.y() << ", " << c.force.z()
          << ") N is not finite.";
        refuse(c, s.str());
      }
      break;
    case ConditionKind::Pressure:
      if (!std::isfinite(c.pressure))
      {
        s << "the pressure " << c.pressure << " Pa is not finite.";
        refuse(c, s.str());
      }
      break;
    case ConditionKind::Pull:
      if (!finite(c.pullTarget) || !(c.pullStiffness >= 0.0) || !std::isfinite(c.pullStiffness))
      {
        s << "the pull needs a finite target and a stiffness >= 0 N/m, but the stiffness is "
          << c.pullStiffness << " N/m.";
        refuse(c, s.str());
      }
      break;
  }
  if (c.holds() && !c.heldAxes[0] && !c.heldAxes[1] && !c.heldAxes[2])
  {
    refuse(c, "it holds none of the components x, y, z; hold at least one.");
  }
}

/// Two holds of the same component of a point agree only when both keep it at rest.
bool sameHold(const Condition& a, const Condition& b)
{
  return a.kind == ConditionKind::Fixed && b.kind == ConditionKind::Fixed;
}

} // namespace

const char* conditionKindName(ConditionKind kind)
{
  switch (kind)
  {
    case ConditionKind::Fixed:
      return "Fixed";
    case ConditionKind::Prescribed:
      return "Prescribed Motion";
    case ConditionKind::Force:
      return "Force";
    case ConditionKind::Pressure:
      return "Pressure";
    case ConditionKind::Pull:
      return "Pull";
  }
  return "?";
}

double TimeProfile::at(double t) const
{
  switch (shape)
  {
    case TimeProfileShape::Constant:
      return 1.0;
    case TimeProfileShape::Ramp:
      return std::clamp(t / duration, 0.0, 1.0);
    case TimeProfileShape::Sinusoid:
      return std::sin(2.0 * std::numbers::pi * t / duration);
    case TimeProfileShape::Keyframes:
    {
      if (t <= times.front())
      {
        return factors.front();
      }
      if (t >= times.back())
      {
        return factors.back();
      }
      const std::size_t k = static_cast<std::size_t>(
        std::upper_bound(times.begin(), times.end(), t) - times.begin());
      const double u = (t - times[k - 1]) / (times[k] - times[k - 1]);
      return factors[k - 1] + u * (factors[k] - factors[k - 1]);
    }
  }
  return 1.0;
}

double TimeProfile::rate(double t) const
{
  switch (shape)
  {
    case TimeProfileShape::Constant:
      return 0.0;
    case TimeProfileShape::Ramp:
      return t >= 0.0 && t < duration ? 1.0 / duration : 0.0;
    case TimeProfileShape::Sinusoid:
    {
      const double w = 2.0 * std::numbers::pi / duration;
      return w * std::cos(w * t);
    }
    case TimeProfileShape::Keyframes:
    {
      if (t < times.front() || t >= times.back())
      {
        return 0.0;
      }
      const std::size_t k = static_cast<std::size_t>(
        std::upper_bound(times.begin(), times.end(), t) - times.begin());
      return (factors[k] - factors[k - 1]) / (times[k] - times[k - 1]);
    }
  }
  return 0.0;
}

double TimeProfile::acceleration(double t) const
{
  if (shape != TimeProfileShape::Sinusoid)
  {
    return 0.0;
  }
  const double w = 2.0 * std::numbers::pi / duration;
  return -w * w * std::sin(w * t);
}

void validateConditions(const std::vector<Condition>& conditions, std::size_t pointCount,
  std::vector<std::string>& warnings)
{
  // For each point and component, the first condition holding it.
  std::vector<std::array<std::int32_t, 3>> heldBy;
  std::vector<char> seen(pointCount, 0);
  for (std::size_t ci = 0; ci < conditions.size(); ++ci)
  {
    const Condition& c = conditions[ci];
    validateValues(c);
    validateProfile(c);
    if (c.points.empty())
    {
      warnings.push_back(quoted(c) + " selects no points of the body and does nothing. Check its "
                                     "region or array.");
      continue;
    }
    for (std::int32_t p : c.points)
    {
      if (p < 0 || static_cast<std::size_t>(p) >= pointCount)
      {
        std::ostringstream s;
        s << "its point index " << p << " is not a point of the body (0 .. " << pointCount - 1
          << ").";
        refuse(c, s.str());
      }
      if (seen[static_cast<std::size_t>(p)])
      {
        std::ostringstream s;
        s << "it names point " << p << " twice.";
        refuse(c, s.str());
      }
      seen[static_cast<std::size_t>(p)] = 1;
    }
    for (std::int32_t p : c.points)
    {
      seen[static_cast<std::size_t>(p)] = 0;
    }
    if (!c.holds())
    {
      continue;
    }
    if (heldBy.empty())
    {
      heldBy.assign(pointCount, { -1, -1, -1 });
    }
    for (std::int32_t p : c.points)
    {
      for (int axis = 0; axis < 3; ++axis)
      {
        if (!c.heldAxes[static_cast<std::size_t>(axis)])
        {
          continue;
        }
        std::int32_t& first = heldBy[static_cast<std::size_t>(p)][static_cast<std::size_t>(axis)];
        if (first >= 0 && !sameHold(conditions[static_cast<std::size_t>(first)], c))
        {
          std::ostringstream s;
          s << "point " << p << " is also held by condition '"
            << conditions[static_cast<std::size_t>(first)].name << "' along " << "xyz"[axis]
            << ", to a different motion. A component can follow one condition only: take the "
               "point out of one of the two sets.";
          refuse(c, s.str());
        }
        if (first < 0)
        {
          first = static_cast<std::int32_t>(ci);
        }
      }
    }
  }
}

} // namespace softbody
