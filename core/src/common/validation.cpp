#include "softbody/common/validation.h"

#include "softbody/common/errors.h"

#include <cmath>
#include <sstream>

namespace softbody::check
{
namespace
{

// Messages are assembled with a stream: GCC 12 warns falsely (-Wrestrict, its bug 105329) on
// some chains of std::string additions at -O3.
[[noreturn]] void refuse(const char* name, const std::string& rule, const std::string& got)
{
  std::ostringstream message;
  message << name << " must be " << rule << ", got " << got << ".";
  throw InvalidInputError(message.str());
}

std::string withUnit(const char* text, const char* unit)
{
  std::ostringstream out;
  out << text;
  if (unit && *unit)
  {
    out << ' ' << unit;
  }
  return out.str();
}

} // namespace

std::string quote(double value)
{
  std::ostringstream out;
  out.precision(10);
  out << value;
  return out.str();
}

std::string quote(const Vec3& value)
{
  std::ostringstream out;
  out << "(" << quote(value.x()) << ", " << quote(value.y()) << ", " << quote(value.z()) << ")";
  return out.str();
}

void positive(const char* name, double value, const char* unit)
{
  if (!(value > 0.0) || !std::isfinite(value))
  {
    std::ostringstream rule;
    rule << withUnit("> 0", unit) << (std::isinf(value) ? " and finite" : "");
    refuse(name, rule.str(), quote(value));
  }
}

void nonNegative(const char* name, double value, const char* unit, const char* zeroMeans)
{
  if (!(value >= 0.0) || !std::isfinite(value))
  {
    std::ostringstream rule;
    rule << withUnit(">= 0", unit);
    if (zeroMeans)
    {
      rule << " (0 = " << zeroMeans << ")";
    }
    if (std::isinf(value))
    {
      rule << " and finite";
    }
    refuse(name, rule.str(), quote(value));
  }
}

void inRange(const char* name, double value, double lo, double hi, bool loOpen, bool hiOpen)
{
  const bool aboveLo = loOpen ? value > lo : value >= lo;
  const bool belowHi = hiOpen ? value < hi : value <= hi;
  if (!(aboveLo && belowHi))
  {
    std::ostringstream rule;
    rule << "in " << (loOpen ? "(" : "[") << quote(lo) << ", " << quote(hi) << (hiOpen ? ")" : "]");
    refuse(name, rule.str(), quote(value));
  }
}

void atLeast(const char* name, long long value, long long minimum)
{
  if (value < minimum)
  {
    refuse(name, ">= " + std::to_string(minimum), std::to_string(value));
  }
}

void finite(const char* name, const Vec3& value)
{
  if (!value.allFinite())
  {
    refuse(name, "finite", quote(value));
  }
}

void nonZeroDirection(const char* name, const Vec3& value)
{
  if (!value.allFinite() || !(value.norm() > 0.0))
  {
    refuse(name, "a finite, nonzero vector", quote(value));
  }
}

void badChoice(const char* name, long long value, const char* choices)
{
  std::ostringstream rule;
  rule << "one of " << choices;
  refuse(name, rule.str(), std::to_string(value));
}

} // namespace softbody::check
