#include "controllers.h"

#include <mybot_common/ros/params.h>

#include <cmath>

namespace mybot_ros_control
{

void ControllerContext::fail(const std::string& field, const std::string& why) const
{
  throw ControllerError("controller '" + name + "' (" + type +
                        "): " + (field.empty() ? std::string() : "parameter " + nh.resolveName(field) + ": ") + why);
}

SimJoint& ControllerContext::joint(const std::string& param, const std::string& j, Interface i) const
{
  SimJoint* sj = hw->joint(j);
  if (!sj)
  {
    std::string known;
    for (const auto& x : hw->joints())
      known += (known.empty() ? "" : ", ") + x.name;
    fail(param, "joint '" + j +
                    "' has no <transmission> in the URDF (joints with one: " + (known.empty() ? "none" : known) + ")");
  }
  if (!sj->has(i))
  {
    std::string has;
    for (Interface x : sj->interfaces)
      has += (has.empty() ? "" : ", ") + interfaceName(x);
    fail(param, "joint '" + j + "' does not offer " + interfaceName(i) + " (its <transmission> declares " + has + ")");
  }
  return *sj;
}

std::string ControllerContext::requiredString(const std::string& param) const
{
  if (!nh.hasParam(param))
    fail(param, "required parameter missing");
  return string(param, "");
}

std::vector<std::string> ControllerContext::stringList(const std::string& param, bool required) const
{
  XmlRpc::XmlRpcValue v;
  if (!nh.getParam(param, v))
  {
    if (required)
      fail(param, "required parameter missing");
    return {};
  }
  if (v.getType() == XmlRpc::XmlRpcValue::TypeString)
    return {static_cast<std::string>(v)};
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray)
    fail(param, "expected a list of joint names");
  std::vector<std::string> out;
  for (int k = 0; k < v.size(); ++k)
  {
    if (v[k].getType() != XmlRpc::XmlRpcValue::TypeString)
      fail(param, "element " + std::to_string(k) + " is not a string");
    out.push_back(static_cast<std::string>(v[k]));
  }
  if (out.empty() && required)
    fail(param, "the list is empty");
  return out;
}

// The typed reads: mybot_common's reader, its message in this controller's error.
template <typename T>
static T readOrFail(const ControllerContext& c, const std::string& param, const T& def)
{
  try
  {
    return mybot_common::readParamOrThrow<T>(c.nh, param, def);
  }
  catch (const mybot_common::ParamError& e)
  {
    c.fail("", e.what());
  }
}

double ControllerContext::number(const std::string& param, double def) const
{
  return readOrFail(*this, param, def);
}

double ControllerContext::positive(const std::string& param, double def) const
{
  const double v = number(param, def);
  if (!(v > 0.0) || !std::isfinite(v))
    fail(param, "must be a finite number > 0, got " + std::to_string(v));
  return v;
}

double ControllerContext::nonNegative(const std::string& param, double def) const
{
  const double v = number(param, def);
  if (!(v >= 0.0) || !std::isfinite(v))
    fail(param, "must be a finite number >= 0, got " + std::to_string(v));
  return v;
}

bool ControllerContext::boolean(const std::string& param, bool def) const
{
  return readOrFail(*this, param, def);
}

std::string ControllerContext::string(const std::string& param, const std::string& def) const
{
  return readOrFail(*this, param, def);
}

// control_toolbox::Pid's parameters under `ns` ("pid" or "<joint>/pid").
mybot_control::PidConfig readPid(const ControllerContext& c, const std::string& ns, bool angle_wrap)
{
  if (!c.nh.hasParam(ns + "/p"))
    c.fail(ns + "/p", "required parameter missing (the PID needs at least p)");
  mybot_control::PidConfig cfg;
  cfg.p = c.number(ns + "/p", 0.0);
  cfg.i = c.number(ns + "/i", 0.0);
  cfg.d = c.number(ns + "/d", 0.0);
  const double clamp = std::abs(c.number(ns + "/i_clamp", 0.0));
  // control_toolbox: i_clamp bounds the integral term symmetrically; 0 = no integral term.
  cfg.i_clamp_max = c.number(ns + "/i_clamp_max", clamp);
  cfg.i_clamp_min = c.number(ns + "/i_clamp_min", -clamp);
  cfg.angle_wrap = angle_wrap;
  const std::string bad = cfg.validate(c.nh.resolveName(ns) + "/");
  if (!bad.empty())
    c.fail("", bad);
  return cfg;
}

const std::map<std::string, ControllerFactory>& controllerTypes()
{
  using I = Interface;
  static const std::map<std::string, ControllerFactory> types = {
      {"joint_state_controller/JointStateController", makeJointStateController},
      {"diff_drive_controller/DiffDriveController", makeDiffDriveController},
      {"ackermann_steering_controller/AckermannSteeringController", makeAckermannSteeringController},
      {"four_wheel_steering_controller/FourWheelSteeringController", makeFourWheelSteeringController},
      {"position_controllers/JointPositionController", [](auto& c) { return makeForwardController(c, I::POSITION); }},
      {"velocity_controllers/JointVelocityController", [](auto& c) { return makeForwardController(c, I::VELOCITY); }},
      {"effort_controllers/JointEffortController", [](auto& c) { return makeForwardController(c, I::EFFORT); }},
      {"position_controllers/JointGroupPositionController",
       [](auto& c) { return makeForwardGroupController(c, I::POSITION); }},
      {"velocity_controllers/JointGroupVelocityController",
       [](auto& c) { return makeForwardGroupController(c, I::VELOCITY); }},
      {"effort_controllers/JointGroupEffortController",
       [](auto& c) { return makeForwardGroupController(c, I::EFFORT); }},
      {"effort_controllers/JointPositionController", [](auto& c) { return makePidController(c, I::EFFORT, true); }},
      {"position_controllers/JointTrajectoryController",
       [](auto& c) { return makeTrajectoryController(c, I::POSITION); }},
      {"velocity_controllers/JointTrajectoryController",
       [](auto& c) { return makeTrajectoryController(c, I::VELOCITY); }},
      {"effort_controllers/JointTrajectoryController", [](auto& c) { return makeTrajectoryController(c, I::EFFORT); }},
      {"position_controllers/GripperActionController",
       [](auto& c) { return makeGripperActionController(c, I::POSITION); }},
      {"effort_controllers/GripperActionController", [](auto& c) { return makeGripperActionController(c, I::EFFORT); }},
      {"effort_controllers/JointVelocityController", [](auto& c) { return makePidController(c, I::EFFORT, false); }},
      {"velocity_controllers/JointPositionController", [](auto& c) { return makePidController(c, I::VELOCITY, true); }},
      {"effort_controllers/JointGroupPositionController",
       [](auto& c) { return makePidGroupPositionController(c, I::EFFORT); }},
  };
  return types;
}

}  // namespace mybot_ros_control
