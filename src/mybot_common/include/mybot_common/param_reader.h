// Strict ROS parameter reading with ranges and lists, as an object over one NodeHandle: every
// failure throws mybot_common::ParamError naming the parameter (a path inside a parameter, such as
// "topics[0].priority", is kept as written). The function form for single values is params.h;
// mybot_control builds its limit, PID and wheel-geometry blocks on this. Header-only.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <ros/ros.h>
#include <XmlRpcValue.h>

#include "mybot_common/params.h"

namespace mybot_common
{

class ParamReader
{
public:
  explicit ParamReader(const ros::NodeHandle& nh) : nh_(nh) {}

  const ros::NodeHandle& nh() const { return nh_; }
  // The resolved name for messages. A path inside a parameter ("topics[0].priority") or a key
  // that is no valid graph name ("topics/my-joy") is kept as written after the namespace: roscpp's
  // resolveName would throw InvalidNameException and abort the node instead of naming it.
  std::string full(const std::string& name) const;
  bool has(const std::string& name) const { return nh_.hasParam(name); }

  double number(const std::string& name, double default_value) const;
  double requiredNumber(const std::string& name) const;
  double positive(const std::string& name, double default_value) const;     // > 0
  double nonNegative(const std::string& name, double default_value) const;  // >= 0
  bool boolean(const std::string& name, bool default_value) const;
  std::string string(const std::string& name, const std::string& default_value) const;
  std::vector<double> numbers(const std::string& name, std::size_t size) const;  // required
  [[noreturn]] void fail(const std::string& name, const std::string& why) const;

private:
  bool numberOf(const XmlRpc::XmlRpcValue& v, double& out) const;
  ros::NodeHandle nh_;
};

inline std::string ParamReader::full(const std::string& name) const
{
  const auto cut = name.find_first_of("[.");
  const std::string head = name.substr(0, cut), rest = cut == std::string::npos ? "" : name.substr(cut);
  try
  {
    return nh_.resolveName(head) + rest;
  }
  catch (const ros::InvalidNameException&)
  {
    const std::string ns = nh_.getNamespace();
    return (ns == "/" ? "" : ns) + "/" + name;
  }
}

inline void ParamReader::fail(const std::string& name, const std::string& why) const
{
  throw ParamError("parameter " + full(name) + " " + why);
}

inline bool ParamReader::numberOf(const XmlRpc::XmlRpcValue& v, double& out) const
{
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble)
    out = static_cast<double>(const_cast<XmlRpc::XmlRpcValue&>(v));
  else if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
    out = static_cast<int>(const_cast<XmlRpc::XmlRpcValue&>(v));
  else
    return false;
  return std::isfinite(out);
}

inline double ParamReader::number(const std::string& name, double default_value) const
{
  XmlRpc::XmlRpcValue v;
  if (!nh_.getParam(name, v))
    return default_value;
  double out;
  if (!numberOf(v, out))
    fail(name, "must be a finite number");
  return out;
}

inline double ParamReader::requiredNumber(const std::string& name) const
{
  if (!nh_.hasParam(name))
    fail(name, "is required but not set");
  return number(name, 0.0);
}

inline double ParamReader::positive(const std::string& name, double default_value) const
{
  const double v = number(name, default_value);
  if (!(v > 0.0))
    fail(name, "must be > 0 (got " + std::to_string(v) + ")");
  return v;
}

inline double ParamReader::nonNegative(const std::string& name, double default_value) const
{
  const double v = number(name, default_value);
  if (!(v >= 0.0))
    fail(name, "must be >= 0 (got " + std::to_string(v) + ")");
  return v;
}

inline bool ParamReader::boolean(const std::string& name, bool default_value) const
{
  XmlRpc::XmlRpcValue v;
  if (!nh_.getParam(name, v))
    return default_value;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeBoolean)
    fail(name, "must be true or false");
  return static_cast<bool>(v);
}

inline std::string ParamReader::string(const std::string& name, const std::string& default_value) const
{
  XmlRpc::XmlRpcValue v;
  if (!nh_.getParam(name, v))
    return default_value;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeString)
    fail(name, "must be a string");
  return static_cast<std::string>(v);
}

inline std::vector<double> ParamReader::numbers(const std::string& name, std::size_t size) const
{
  XmlRpc::XmlRpcValue v;
  if (!nh_.getParam(name, v))
    fail(name, "is required: a list of " + std::to_string(size) + " numbers");
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray || static_cast<std::size_t>(v.size()) != size)
    fail(name, "must be a list of " + std::to_string(size) + " numbers");
  std::vector<double> out(size);
  for (std::size_t k = 0; k < size; ++k)
    if (!numberOf(v[static_cast<int>(k)], out[k]))
      fail(name, "element " + std::to_string(k) + " must be a finite number");
  return out;
}

}  // namespace mybot_common
