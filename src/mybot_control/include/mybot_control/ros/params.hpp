// ROS-side helpers shared by the control nodes: limit and PID blocks in upstream formats and
// wheel geometry from the URDF, read with mybot_common's ParamReader (one clear ParamError naming
// the parameter). Kept out of the pure library on purpose.
#pragma once

#include <ros/ros.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "mybot_common/ros/node_main.h"
#include "mybot_common/ros/params.h"
#include "mybot_control/pid.hpp"
#include "mybot_control/speed_limiter.hpp"

namespace mybot_control
{

// The workspace's one parameter reader, parameter error and node main (mybot_common).
using mybot_common::ParamError;
using mybot_common::ParamReader;
using mybot_common::runNode;

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
