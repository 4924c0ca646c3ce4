// The main() of every C++ node of the workspace:
//   int main(int argc, char** argv) { return mybot_common::runNode(argc, argv, "amcl", [] { ...; ros::spin(); }); }
// A bad parameter (ParamError, thrown by the node's constructor) becomes one fatal line naming it
// and exit code 1, the same for every node. Header-only.
#pragma once

#include <cstdint>
#include <string>

#include <ros/ros.h>

#include "mybot_common/ros/params.h"

namespace mybot_common
{

template <typename Body>
int runNode(int argc, char** argv, const std::string& name, Body body, std::uint32_t init_options = 0)
{
  ros::init(argc, argv, name, init_options);
  // Outlives the node's handles: when the last NodeHandle goes (as when the constructor throws),
  // roscpp shuts down and would swallow the fatal message below.
  ros::NodeHandle keep_alive;
  try
  {
    body();
  }
  catch (const ParamError& e)
  {
    ROS_FATAL("%s: %s", ros::this_node::getName().c_str(), e.what());
    ros::shutdown();
    return 1;
  }
  return 0;
}

}  // namespace mybot_common
