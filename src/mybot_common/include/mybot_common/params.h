// Strict ROS parameter reading, shared by the C++ nodes: a value of the wrong type stops the node
// with one message naming the parameter, instead of roscpp's param() silently using the default
// (`_max_step_size:=abc`, `_real_time_factor:=fast`). Header-only; the one part of mybot_common
// that uses ROS.
#pragma once

#include <cstdlib>
#include <stdexcept>
#include <string>

#include <ros/ros.h>
#include <XmlRpcValue.h>

namespace mybot_common
{

// "parameter /node/name: why". Nodelets throw it (they must not end their manager's process);
// nodes stop with it (readParam, fatalParam).
struct ParamError : std::runtime_error
{
  ParamError(const ros::NodeHandle& nh, const std::string& name, const std::string& why)
      : std::runtime_error("parameter " + nh.resolveName(name) + ": " + why)
  {
  }
  // A message already naming the parameter (readers that resolve names themselves).
  explicit ParamError(const std::string& what) : std::runtime_error(what) {}
};

// Reads an optional parameter; a value of the wrong type throws ParamError.
template <typename T>
T readParamOrThrow(const ros::NodeHandle& nh, const std::string& name, const T& def)
{
  T v = def;
  if (nh.hasParam(name) && !nh.getParam(name, v))
    throw ParamError(nh, name, "has the wrong type");
  return v;
}

// doubles also accept integers written without a decimal point.
template <>
inline double readParamOrThrow<double>(const ros::NodeHandle& nh, const std::string& name, const double& def)
{
  if (!nh.hasParam(name))
    return def;
  XmlRpc::XmlRpcValue v;
  nh.getParam(name, v);
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble)
    return static_cast<double>(v);
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
    return static_cast<int>(v);
  throw ParamError(nh, name, "must be a number");
}

// ints are whole numbers: roscpp's getParam would round 2.5 to 3 without a word.
template <>
inline int readParamOrThrow<int>(const ros::NodeHandle& nh, const std::string& name, const int& def)
{
  if (!nh.hasParam(name))
    return def;
  XmlRpc::XmlRpcValue v;
  nh.getParam(name, v);
  if (v.getType() != XmlRpc::XmlRpcValue::TypeInt)
    throw ParamError(nh, name, "must be a whole number");
  return static_cast<int>(v);
}

// Stops the node with one message naming the parameter (exit code 1).
[[noreturn]] inline void fatalParam(const std::string& node, const ros::NodeHandle& nh, const std::string& name,
                                    const std::string& why)
{
  ROS_FATAL("%s: %s", node.c_str(), ParamError(nh, name, why).what());
  ros::shutdown();
  std::exit(1);
}

// readParamOrThrow for nodes: a value of the wrong type stops the node naming it.
template <typename T>
T readParam(const std::string& node, const ros::NodeHandle& nh, const std::string& name, const T& def)
{
  try
  {
    return readParamOrThrow<T>(nh, name, def);
  }
  catch (const ParamError& e)
  {
    ROS_FATAL("%s: %s", node.c_str(), e.what());
    ros::shutdown();
    std::exit(1);
  }
}

}  // namespace mybot_common
