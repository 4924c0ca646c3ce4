// ROS-side helpers shared by the control nodes: typed, validated parameter reading (one
// clear ParamError naming the parameter), limit and PID blocks in upstream formats, and
// wheel geometry from the URDF. Kept out of the pure library on purpose.
#pragma once

#include <ros/ros.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "mybot_common/node_main.h"
#include "mybot_common/params.h"
#include "mybot_control/pid.hpp"
#include "mybot_control/speed_limiter.hpp"

namespace mybot_control
{

// The workspace's one parameter error and node main (mybot_common).
using mybot_common::ParamError;
using mybot_common::runNode;

class ParamReader
{
public:
  explicit ParamReader(const ros::NodeHandle& nh) : nh_(nh) {}

  const ros::NodeHandle& nh() const { return nh_; }
  // Fully resolved name, for messages.
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

// diff_drive_controller's per-axis block, e.g. prefix "linear/x/": has_velocity_limits,
// min_velocity (default -max), max_velocity, has_acceleration_limits, min/max_acceleration,
// has_deceleration_limits, max_deceleration (ros2_control's name), has_jerk_limits, min/max_jerk.
SpeedLimits loadSpeedLimits(const ParamReader& params, const std::string& prefix);

// PID block in the PID tuner's YAML (control_toolbox names + output_min/max, f, d_filter_tau,
// angle_wrap, schedule list). `required` = the block must exist.
PidConfig loadPid(const ParamReader& params, const std::string& name, bool required, const PidConfig& defaults = {});

// Wheel geometry from a URDF string: distance between the two wheel joints (joint origins
// composed up to the root link) and each wheel link's collision radius (cylinder or sphere).
struct WheelGeometry
{
  double separation = 0.0;
  double left_radius = 0.0;
  double right_radius = 0.0;
};
// Throws ParamError naming the joint/link when something is missing.
WheelGeometry wheelGeometryFromUrdf(const std::string& urdf_xml, const std::string& left_joint,
                                    const std::string& right_joint);

// Reads wheel_separation / wheel_radius, taking the ones not set from `robot_description`
// (searched up from the node's namespace), then applies diff_drive_controller's
// wheel_separation_multiplier / left_/right_wheel_radius_multiplier.
WheelGeometry loadWheelGeometry(const ParamReader& params, const std::string& left_joint,
                                const std::string& right_joint, bool need_separation, bool need_radius);

}  // namespace mybot_control
