// Action servers of controllers that run inside the simulator (joint_trajectory_controller's
// follow_joint_trajectory, gripper_action_controller's gripper_cmd).
#pragma once

#include <mybot_gazebo_lite/ros/sim_plugin.h>
#include <mybot_lockstep/ros/action_server.h>
#include <ros/ros.h>

#include <cmath>
#include <string>

namespace mybot_ros_control
{

// The simulator runs its controllers, not a lockstep participant: goals and cancels are counted
// inputs of the simulator (as every command topic), and the controller publishes the status array
// from its update (publishStatusNow, at kActionStatusPeriod) instead of on a timer.
struct SimActionWiring
{
  const mybot_gazebo_lite::PluginContext* plugin;
  template <class M, class F>
  ros::Subscriber subscribe(ros::NodeHandle& nh, const std::string& topic, uint32_t queue_size, F cb) const
  {
    return mybot_gazebo_lite::subscribeCommand<M>(*plugin, nh, topic, cb, queue_size);
  }
  template <class F>
  mybot_lockstep::Timer timer(ros::NodeHandle&, double, F) const
  {
    return {};
  }
};

template <class Action>
using SimActionServer = mybot_lockstep::ActionServer<Action, SimActionWiring>;

constexpr double kActionStatusPeriod = 0.2;  // actionlib's status_frequency, 5 Hz

// The next multiple of `period` after t: a rate's ticks fall on the same sim times in every run.
inline double nextTick(double t, double period)
{
  return std::floor(t / period + 1.0 + 1e-9) * period;
}

}  // namespace mybot_ros_control
