#include "controllers.h"

#include <mybot_common/ros/params.h>

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

bool ControllerContext::boolean(const std::string& param, bool def) const
{
  return readOrFail(*this, param, def);
}

std::string ControllerContext::string(const std::string& param, const std::string& def) const
{
  return readOrFail(*this, param, def);
}

const std::map<std::string, ControllerFactory>& controllerTypes()
{
  using I = Interface;
  static const std::map<std::string, ControllerFactory> types = {
      {"joint_state_controller/JointStateController", makeJointStateController},
      {"diff_drive_controller/DiffDriveController", makeDiffDriveController},
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
      {"effort_controllers/JointVelocityController", [](auto& c) { return makePidController(c, I::EFFORT, false); }},
      {"velocity_controllers/JointPositionController", [](auto& c) { return makePidController(c, I::VELOCITY, true); }},
      {"effort_controllers/JointGroupPositionController",
       [](auto& c) { return makePidGroupPositionController(c, I::EFFORT); }},
  };
  return types;
}

}  // namespace mybot_ros_control
