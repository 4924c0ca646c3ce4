// controller_manager for gazebo_lite: loads controllers from the parameter server
// (<namespace>/<controller>/type and its parameters), starts and stops them, and runs the
// running ones at the control period, inside the simulator. Its services have the names and
// fields of controller_manager's (types in mybot_gazebo_lite, which Debian's ROS lacks).
#pragma once

#include "mybot_ros_control/ros/controller.h"

#include <mybot_gazebo_lite/ListControllerTypes.h>
#include <mybot_gazebo_lite/ListControllers.h>
#include <mybot_gazebo_lite/LoadController.h>
#include <mybot_gazebo_lite/ReloadControllerLibraries.h>
#include <mybot_gazebo_lite/SwitchController.h>
#include <mybot_gazebo_lite/UnloadController.h>

namespace mybot_ros_control
{

class ControllerManager
{
public:
  ControllerManager(RobotHWSim& hw, const mybot_gazebo_lite::PluginContext& plugin, const ros::NodeHandle& root);
  // One control period: every running controller, in load order.
  void update(double t, double dt);
  // reset_world / reset_simulation: running controllers stop and start again (as upstream).
  void restart(double t);

  // The service bodies (also called directly by tests). Each returns "" or why it failed.
  std::string load(const std::string& name);
  std::string unload(const std::string& name);
  std::string switchControllers(const std::vector<std::string>& start, const std::vector<std::string>& stop,
                                int strictness);

private:
  enum class State
  {
    INITIALIZED,
    RUNNING,
    STOPPED
  };
  struct Entry
  {
    std::string name, type;
    std::unique_ptr<Controller> controller;
    State state = State::INITIALIZED;
  };
  Entry* find(const std::string& name);
  bool onLoad(mybot_gazebo_lite::LoadController::Request& req, mybot_gazebo_lite::LoadController::Response& res);
  bool onUnload(mybot_gazebo_lite::UnloadController::Request& req, mybot_gazebo_lite::UnloadController::Response& res);
  bool onSwitch(mybot_gazebo_lite::SwitchController::Request& req, mybot_gazebo_lite::SwitchController::Response& res);
  bool onList(mybot_gazebo_lite::ListControllers::Request& req, mybot_gazebo_lite::ListControllers::Response& res);
  bool onListTypes(mybot_gazebo_lite::ListControllerTypes::Request& req,
                   mybot_gazebo_lite::ListControllerTypes::Response& res);
  bool onReload(mybot_gazebo_lite::ReloadControllerLibraries::Request& req,
                mybot_gazebo_lite::ReloadControllerLibraries::Response& res);

  RobotHWSim& hw_;
  const mybot_gazebo_lite::PluginContext& plugin_;
  ros::NodeHandle root_;
  std::vector<Entry> entries_;
  std::vector<ros::ServiceServer> services_;
};

}  // namespace mybot_ros_control
