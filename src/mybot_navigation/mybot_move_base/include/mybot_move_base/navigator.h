// move_base's state machine (PLANNING -> CONTROLLING -> CLEARING) with its parameter names,
// patience timers, oscillation check and recovery sequence, as a library with no ROS types:
// the node feeds time, pose and velocity, and sends the returned command.
#pragma once

#include <string>
#include <vector>

#include "mybot_move_base/costmap.h"
#include "mybot_move_base/local_planner.h"
#include "mybot_move_base/planner.h"

namespace mybot_navigation
{

struct NavigatorParams
{
  double planner_frequency = 0.0;     // Hz; 0 = plan on a new goal and when the controller asks
  double planner_patience = 5.0;      // s without a valid plan before recovery
  double controller_patience = 15.0;  // s without a valid command before recovery
  double oscillation_timeout = 0.0;   // s; 0 = no oscillation check
  double oscillation_distance = 0.5;  // m the robot must move to reset the oscillation timer
  int max_planning_retries = -1;      // -1 = unlimited (only planner_patience applies)
  bool recovery_behavior_enabled = true;
  bool clearing_rotation_allowed = true;
  double conservative_reset_dist = 3.0;  // m; obstacles farther than this are cleared first
  // Back-up recovery (not in move_base's defaults): distance and speed.
  double backup_distance = 0.25;
  double backup_speed = 0.1;
};

std::string validate(const NavigatorParams& p);

enum class NavState
{
  Idle,
  Planning,
  Controlling,
  Clearing,
  Succeeded,
  Aborted
};

const char* toString(NavState s);

struct NavOutput
{
  NavState state = NavState::Idle;
  Velocity2D cmd;
  bool new_plan = false;  // the global plan changed this step
  std::string message;    // reason when aborted, recovery name while clearing
  LocalResult local;      // the controller's result when it ran
};

class Navigator
{
public:
  Navigator(const NavigatorParams& params, Costmap& global_costmap, Costmap& local_costmap,
            const GlobalPlanner& planner, LocalPlanner& controller);

  // Starts a new goal. A goal outside the map or inside an obstacle aborts at once with the
  // reason (returned; empty when accepted).
  std::string setGoal(const Pose2D& goal, double now, const Pose2D& pose);
  // Stops pursuing the goal; the next step commands zero velocity.
  void cancel();

  NavOutput step(double now, const Pose2D& pose, const Velocity2D& vel);

  NavState state() const { return state_; }
  const std::vector<Pose2D>& globalPlan() const { return plan_; }
  const Pose2D& goal() const { return goal_; }
  const std::string& abortReason() const { return reason_; }
  int recoveriesRun() const { return recoveries_run_; }

private:
  enum class Trigger
  {
    Planning,
    Controlling,
    Oscillation
  };
  enum class Recovery
  {
    ConservativeReset,
    Rotate,
    AggressiveReset,
    BackUp
  };
  bool plan(double now, const Pose2D& pose, NavOutput& out);
  void startRecovery(double now, const Pose2D& pose, Trigger trigger);
  // Runs the current recovery; true when it has finished.
  bool runRecovery(const Pose2D& pose, const Velocity2D& vel, NavOutput& out);
  // Whether a rotate or back-up recovery may move the robot to `p`.
  bool clearForRecovery(const Pose2D& p) const;
  void abort(const std::string& reason);

  NavigatorParams params_;
  Costmap& global_;
  Costmap& local_;
  const GlobalPlanner& planner_;
  LocalPlanner& controller_;
  std::vector<Recovery> recoveries_;

  NavState state_ = NavState::Idle;
  Pose2D goal_;
  std::vector<Pose2D> plan_;
  std::string reason_;
  double last_valid_plan_ = 0.0, last_valid_control_ = 0.0, last_plan_time_ = 0.0;
  double last_oscillation_reset_ = 0.0;
  Pose2D oscillation_pose_;
  int planning_retries_ = 0;
  size_t recovery_index_ = 0;
  Trigger trigger_ = Trigger::Planning;
  int recoveries_run_ = 0;
  // Recovery progress
  bool recovery_started_ = false;
  Pose2D recovery_start_;
  std::vector<Point2D> recovery_footprint_;  // empty unless the recovery started in contact
  double rotated_ = 0.0, last_theta_ = 0.0;
};

}  // namespace mybot_navigation
