// What a loader refuses: the LoadError's message, "(accepted)" when it loads.
#pragma once

#include "mybot_gazebo_lite/model.h"

#include <functional>
#include <string>

namespace mybot_gazebo_lite
{
inline std::string loadErrorOf(const std::function<void()>& load)
{
  try
  {
    load();
  }
  catch (const LoadError& e)
  {
    return e.what();
  }
  return "(accepted)";
}
}  // namespace mybot_gazebo_lite
