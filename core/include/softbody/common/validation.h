// Checks of user settings, in one place and one wording: each throws InvalidInputError that
// names the setting (by its property name), the rule and the value the user gave, e.g.
// "EndTime must be > 0 s, got -1." Nothing is clamped here: a value is accepted or refused.
#pragma once

#include "softbody/common/geometry.h"

#include <string>

namespace softbody::check
{

/// Formats a value the way every message quotes it (shortest round-trip-ish, nan and inf).
std::string quote(double value);
std::string quote(const Vec3& value);

/// value > 0 and finite.
void positive(const char* name, double value, const char* unit = "");
/// value >= 0 and finite; `zeroMeans` (e.g. "off", "automatic") is said in the message.
void nonNegative(const char* name, double value, const char* unit = "", const char* zeroMeans = nullptr);
/// lo <= value <= hi (each end closed unless said open), and finite.
void inRange(const char* name, double value, double lo, double hi, bool loOpen = false, bool hiOpen = false);
/// value >= minimum.
void atLeast(const char* name, long long value, long long minimum);
/// Every component finite.
void finite(const char* name, const Vec3& value);
/// Finite and not the zero vector.
void nonZeroDirection(const char* name, const Vec3& value);
/// An enumeration value out of its list: "<name> must be one of <choices>, got <value>."
[[noreturn]] void badChoice(const char* name, long long value, const char* choices);

} // namespace softbody::check
