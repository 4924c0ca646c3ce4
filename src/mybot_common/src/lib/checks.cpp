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

}  // namespace mybot_common
