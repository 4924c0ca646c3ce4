// When a gripper_action_controller goal ends, as ros_controllers decides it. No ROS.
//
// A goal commands one joint to a position. It is
//   - reached once the joint is closer to that position than goal_tolerance;
//   - stalled once the joint has not moved faster than stall_velocity_threshold for longer than
//     stall_timeout: the fingers closed on an object (or a limit) short of the command. Upstream
//     ends such a goal aborted, with `stalled` set, and keeps commanding the position with the
//     goal's max_effort: that is how a gripper holds what it grasped.
// Reaching is checked first: a joint at rest within the tolerance has reached, not stalled.
#pragma once

namespace mybot_ros_control
{

struct GripperGoalParams
{
  double goal_tolerance = 0.01;             // joint units (m or rad)
  double stall_velocity_threshold = 0.001;  // joint units / s
  double stall_timeout = 1.0;               // s
};

enum class GripperGoalState
{
  MOVING,
  REACHED,
  STALLED
};

class GripperGoalMonitor
{
public:
  explicit GripperGoalMonitor(const GripperGoalParams& params = {}) : params_(params) {}

  // A goal starts at time t (s): the joint counts as moving from then on.
  void start(double t) { last_movement_ = t; }

  // The joint at `position`, moving at `velocity`, at time t, against the commanded `target`. A
  // time before the last movement (a simulation reset) restarts the stall clock there.
  GripperGoalState update(double t, double target, double position, double velocity);

  const GripperGoalParams& params() const { return params_; }

private:
  GripperGoalParams params_;
  double last_movement_ = 0.0;
};

}  // namespace mybot_ros_control
