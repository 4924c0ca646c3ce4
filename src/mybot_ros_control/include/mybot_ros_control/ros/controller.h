// The controllers a controller_manager loads, with ros_controllers' types, parameter names,
// topics and behaviour, running inside the simulator at the control period.
#pragma once

#include "mybot_ros_control/robot_hw_sim.h"

#include <mybot_gazebo_lite/ros/sim_plugin.h>
#include <ros/ros.h>

#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace mybot_ros_control
{

// A controller that cannot be loaded; what() names the controller and the field.
struct ControllerError : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

struct ControllerContext
{
  std::string name, type;
  RobotHWSim* hw;
  const mybot_gazebo_lite::PluginContext* plugin;  // the robot, tf, lockstep
  ros::NodeHandle root_nh;                         // the controller manager's namespace
  ros::NodeHandle nh;                              // <namespace>/<controller name>

  [[noreturn]] void fail(const std::string& field, const std::string& why) const;
  // A joint of the hardware that offers `i`; fails naming the parameter otherwise.
  SimJoint& joint(const std::string& param, const std::string& name, Interface i) const;
  // A string parameter that must be there.
  std::string requiredString(const std::string& param) const;
  // A list of joint names (a YAML list; a single string is a list of one).
  std::vector<std::string> stringList(const std::string& param, bool required) const;
  double number(const std::string& param, double def) const;
  // A number that must be finite and > 0 (a rate, a period, a size), or >= 0 (a tolerance, a
  // duration); fails naming the parameter and the value read.
  double positive(const std::string& param, double def) const;
  double nonNegative(const std::string& param, double def) const;
  bool boolean(const std::string& param, bool def) const;
  std::string string(const std::string& param, const std::string& def) const;
};

class Controller
{
public:
  virtual ~Controller() = default;
  virtual void starting(double /*t*/) {}
  virtual void update(double t, double dt) = 0;
  virtual void stopping(double /*t*/) {}
  // hardware interface -> the joints this controller commands through it (resources).
  const std::map<std::string, std::vector<std::string>>& claimed() const { return claimed_; }

protected:
  std::map<std::string, std::vector<std::string>> claimed_;
};

using ControllerFactory = std::function<std::unique_ptr<Controller>(const ControllerContext&)>;
// Every controller type by its ros_controllers name ("diff_drive_controller/DiffDriveController").
const std::map<std::string, ControllerFactory>& controllerTypes();

}  // namespace mybot_ros_control
