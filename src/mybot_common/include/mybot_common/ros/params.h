// Strict ROS parameter reading, the one reader of the C++ nodes: a value of the wrong type or out
// of range throws (nodelets) or stops the node (readParam, fatalParam) with one message naming the
// parameter, instead of roscpp's param() silently using the default (`_max_step_size:=abc`,
// `_real_time_factor:=fast`) or rounding `2.5` to a whole number. Header-only; the one part of
// mybot_common that uses ROS (with node_main.h).
//
//   ParamReader p(pnh);                                  // an object over one NodeHandle
//   const double rate = p.positive("rate", 50.0);        // ranges, required values, lists
//   const int n = readParam<int>("amcl", pnh, "max_particles", 5000);  // one value, fatal
#pragma once

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <ros/ros.h>
#include <XmlRpcValue.h>

namespace mybot_common
{

// "parameter /node/name why". Nodelets throw it (they must not end their manager's process);
// nodes stop with it (readParam, fatalParam).
struct ParamError : std::runtime_error
{
  explicit ParamError(const std::string& what) : std::runtime_error(what) {}
};

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

  double number(const std::string& name, double default_value) const;  // ints accepted
  double requiredNumber(const std::string& name) const;
  double positive(const std::string& name, double default_value) const;     // > 0
  double nonNegative(const std::string& name, double default_value) const;  // >= 0
  int integer(const std::string& name, int default_value) const;            // whole numbers only
  bool boolean(const std::string& name, bool default_value) const;
  std::string string(const std::string& name, const std::string& default_value) const;
  std::vector<double> numbers(const std::string& name, std::size_t size) const;  // required
  // One optional value by type (double, int, bool, std::string): readParamOrThrow.
  template <typename T>
  T get(const std::string& name, const T& default_value) const;
  // The same, then `ok(value)` must hold, else "is invalid: must be <requirement>".
  template <typename T, typename Check>
  T checked(const std::string& name, const T& default_value, Check ok, const std::string& requirement) const
  {
    const T v = get<T>(name, default_value);
    if (!ok(v))
      fail(name, "is invalid: must be " + requirement);
    return v;
  }

  // "parameter <full name> <why>"; for the empty name, the parameters of the namespace.
  std::string message(const std::string& name, const std::string& why) const;
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

inline std::string ParamReader::message(const std::string& name, const std::string& why) const
{
  if (name.empty())
    return "parameters of " + nh_.getNamespace() + ": " + why;
  return "parameter " + full(name) + " " + why;
}

inline void ParamReader::fail(const std::string& name, const std::string& why) const
{
  throw ParamError(message(name, why));
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

inline int ParamReader::integer(const std::string& name, int default_value) const
{
  XmlRpc::XmlRpcValue v;
  if (!nh_.getParam(name, v))
    return default_value;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeInt)
    fail(name, "must be a whole number");
  return static_cast<int>(v);
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

template <typename T>
T ParamReader::get(const std::string& name, const T& default_value) const
{
  if constexpr (std::is_same_v<T, double>)
    return number(name, default_value);
  else if constexpr (std::is_same_v<T, int>)
    return integer(name, default_value);
  else if constexpr (std::is_same_v<T, bool>)
    return boolean(name, default_value);
  else
  {
    static_assert(std::is_same_v<T, std::string>, "ParamReader::get reads double, int, bool or std::string");
    return string(name, default_value);
  }
}

// Reads an optional parameter; a value of the wrong type throws ParamError.
template <typename T>
T readParamOrThrow(const ros::NodeHandle& nh, const std::string& name, const T& def)
{
  return ParamReader(nh).get<T>(name, def);
}

// Stops the node with one message naming the parameter (exit code 1).
[[noreturn]] inline void fatalParam(const std::string& node, const ros::NodeHandle& nh, const std::string& name,
                                    const std::string& why)
{
  ROS_FATAL("%s: %s", node.c_str(), ParamReader(nh).message(name, why).c_str());
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
