#include "mybot_common/checks.h"

#include <cmath>
#include <cstdio>

namespace mybot_common
{

std::string firstInvalid(std::initializer_list<NamedValue> values, double limit)
{
  char text[160];
  for (const NamedValue& v : values)
  {
    if (!std::isfinite(v.value))
    {
      std::snprintf(text, sizeof text, "%s is %g", v.name, v.value);
      return text;
    }
    if (std::fabs(v.value) > limit)
    {
      std::snprintf(text, sizeof text, "%s is %g, beyond +-%g", v.name, v.value, limit);
      return text;
    }
  }
  return "";
}

std::string formatNumber(double v)
{
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

std::string scanGeometryError(double angle_min, double angle_max, double angle_increment, std::size_t ranges)
{
  char text[256];
  if (!std::isfinite(angle_min) || !std::isfinite(angle_max) || !std::isfinite(angle_increment) ||
      angle_increment == 0.0 || (angle_max - angle_min) * angle_increment < 0.0)
  {
    std::snprintf(text, sizeof text,
                  "has angle_min %g, angle_max %g, angle_increment %g: not a sweep (finite angles and an increment "
                  "that steps from angle_min towards angle_max)",
                  angle_min, angle_max, angle_increment);
    return text;
  }
  const double steps = (angle_max - angle_min) / angle_increment;
  if (steps > 1e7)
  {
    std::snprintf(text, sizeof text,
                  "has %zu ranges where its angles (angle_min %g, angle_max %g, angle_increment %g) make %.3g", ranges,
                  angle_min, angle_max, angle_increment, steps + 1);
    return text;
  }
  const auto expected = static_cast<std::size_t>(std::llround(steps)) + 1;
  if (expected == ranges || expected == ranges + 1)
    return "";
  std::snprintf(text, sizeof text,
                "has %zu ranges where its angles (angle_min %g, angle_max %g, angle_increment %g) make %zu", ranges,
                angle_min, angle_max, angle_increment, expected);
  return text;
}

std::string scanRangeError(double range_min, double range_max)
{
  if (std::isfinite(range_min) && range_min >= 0.0 && range_max > range_min)
    return "";
  char text[160];
  std::snprintf(text, sizeof text,
                "has range_min %g, range_max %g: not a range (range_min finite and >= 0, range_max above it)",
                range_min, range_max);
  return text;
}

std::string scanError(double angle_min, double angle_max, double angle_increment, std::size_t ranges, double range_min,
                      double range_max)
{
  const std::string geometry = scanGeometryError(angle_min, angle_max, angle_increment, ranges);
  return geometry.empty() ? scanRangeError(range_min, range_max) : geometry;
}

}  // namespace mybot_common
