// Strict ROS parameter reading, shared by the C++ nodes: a value of the wrong type stops the node
// with one message naming the parameter, instead of roscpp's param() silently using the default
// (`_max_step_size:=abc`, `_real_time_factor:=fast`). Header-only; the one part of mybot_common
// that uses ROS.
#pragma once

#include <cstdlib>
#include <string>

#include <ros/ros.h>
#include <XmlRpcValue.h>

namespace mybot_common
{

// Stops the node with one message naming the parameter (exit code 1).
[[noreturn]] inline void fatalParam(const std::string& node, const ros::NodeHandle& nh, const std::string& name,
                                    const std::string& why)
{
  ROS_FATAL("%s: parameter %s: %s", node.c_str(), nh.resolveName(name).c_str(), why.c_str());
  ros::shutdown();
  std::exit(1);
}

// Reads an optional parameter; a value of the wrong type is fatal rather than silently ignored.
template <typename T>
T readParam(const std::string& node, const ros::NodeHandle& nh, const std::string& name, const T& def)
{
  T v = def;
  if (nh.hasParam(name) && !nh.getParam(name, v))
    fatalParam(node, nh, name, "has the wrong type");
  return v;
}

// doubles also accept integers written without a decimal point.
template <>
inline double readParam<double>(const std::string& node, const ros::NodeHandle& nh, const std::string& name,
                                const double& def)
{
  if (!nh.hasParam(name))
    return def;
  XmlRpc::XmlRpcValue v;
  nh.getParam(name, v);
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble)
    return static_cast<double>(v);
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
    return static_cast<int>(v);
  fatalParam(node, nh, name, "must be a number");
}

// ints are whole numbers: roscpp's getParam would round 2.5 to 3 without a word.
template <>
inline int readParam<int>(const std::string& node, const ros::NodeHandle& nh, const std::string& name, const int& def)
{
  if (!nh.hasParam(name))
    return def;
  XmlRpc::XmlRpcValue v;
  nh.getParam(name, v);
  if (v.getType() != XmlRpc::XmlRpcValue::TypeInt)
    fatalParam(node, nh, name, "must be a whole number");
  return static_cast<int>(v);
}

}  // namespace mybot_common
