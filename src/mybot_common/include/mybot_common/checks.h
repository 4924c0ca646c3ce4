// Checks of numbers that come from outside (service requests, topics, files) before they enter
// running state: one NaN in a pose spreads to every transform computed from it. No ROS.
#pragma once

#include <initializer_list>
#include <limits>
#include <string>

namespace mybot_common
{

struct NamedValue
{
  const char* name;  // as the user knows it: "initial_pose.position.x"
  double value;
};

// The first value that is not finite or whose magnitude exceeds `limit`, described for a
// message ("initial_pose.position.x is nan", "pose.position.y is 1e+30, beyond +-1e+06"), or ""
// when every value is fine.
std::string firstInvalid(std::initializer_list<NamedValue> values,
                         double limit = std::numeric_limits<double>::infinity());

}  // namespace mybot_common
