#include "mybot_ros_control/gripper_goal.h"

#include <cmath>

namespace mybot_ros_control
{

GripperGoalState GripperGoalMonitor::update(double t, double target, double position, double velocity)
{
  if (std::abs(target - position) < params_.goal_tolerance)
    return GripperGoalState::REACHED;
  // Strict comparisons, as upstream: a joint exactly at the threshold is at rest.
  if (std::abs(velocity) > params_.stall_velocity_threshold || t < last_movement_)
    last_movement_ = t;
  else if (t - last_movement_ > params_.stall_timeout)
    return GripperGoalState::STALLED;
  return GripperGoalState::MOVING;
}

}  // namespace mybot_ros_control
