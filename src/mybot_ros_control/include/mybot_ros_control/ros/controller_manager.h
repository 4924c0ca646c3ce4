// controller_manager for gazebo_lite: loads controllers from the parameter server
// (<namespace>/<controller>/type and its parameters), starts and stops them, and runs the
// running ones at the control period, inside the simulator. Its services have the names and
// types of controller_manager's (controller_manager_msgs, from controller_manager_msgs_compat:
// Debian's ROS lacks it).
#pragma once

#include "mybot_ros_control/ros/controller.h"

#include <controller_manager_msgs/ListControllerTypes.h>
#include <controller_manager_msgs/ListControllers.h>
#include <controller_manager_msgs/LoadController.h>
#include <controller_manager_msgs/ReloadControllerLibraries.h>
#include <controller_manager_msgs/SwitchController.h>
#include <controller_manager_msgs/UnloadController.h>

namespace mybot_ros_control
{

class ControllerManager
{
public:
  ControllerManager(RobotHWSim& hw, const mybot_gazebo_lite::PluginContext& plugin, const ros::NodeHandle& root);
  // One control period: every running controller, in load order; one switched on while the world
  // was paused starts first (see switchControllers).
  void update(double t, double dt);
  // reset_world / reset_simulation: running controllers stop and start again (as upstream).
  void restart(double t);

  // The service bodies (also called directly by tests). Each returns "" or why it failed.
  std::string load(const std::string& name);
  std::string unload(const std::string& name);
  // Upstream switches in its control loop. Running, that is a step away: a controller starts now,
  // from the joints as they are. Paused, time stands: it starts at the first control period once
  // time moves, from the joints as they are then, so it holds them where spawn_model -J put them
  // whichever of the spawner and spawn_model came first (upstream's call blocks until then; this
  // one returns and lists the controller running).
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
    bool start_pending = false;  // RUNNING, switched on while paused: its starting() is due at the next update
  };
  Entry* find(const std::string& name);
  // A service's full name, which starts the log line saying why a call to it failed.
  std::string service(const std::string& name) const;
  bool onLoad(controller_manager_msgs::LoadController::Request& req,
              controller_manager_msgs::LoadController::Response& res);
  bool onUnload(controller_manager_msgs::UnloadController::Request& req,
                controller_manager_msgs::UnloadController::Response& res);
  bool onSwitch(controller_manager_msgs::SwitchController::Request& req,
                controller_manager_msgs::SwitchController::Response& res);
  bool onList(controller_manager_msgs::ListControllers::Request& req,
              controller_manager_msgs::ListControllers::Response& res);
  bool onListTypes(controller_manager_msgs::ListControllerTypes::Request& req,
                   controller_manager_msgs::ListControllerTypes::Response& res);
  bool onReload(controller_manager_msgs::ReloadControllerLibraries::Request& req,
                controller_manager_msgs::ReloadControllerLibraries::Response& res);

  RobotHWSim& hw_;
  const mybot_gazebo_lite::PluginContext& plugin_;
  ros::NodeHandle root_;
  std::vector<Entry> entries_;
  std::vector<ros::ServiceServer> services_;
};

}  // namespace mybot_ros_control
