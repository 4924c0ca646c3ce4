// Sampling-based local controller after dwa_local_planner (Fox et al. 1997): samples (vx, vy,
// vtheta) in the dynamic window, forward-simulates each for sim_time, rejects colliding
// trajectories and scores the rest with DWA's cost terms and parameter names. Adds rotation in
// place towards the path for non-holonomic robots and base_local_planner's latched
// stop-and-rotate at the goal. No ROS types.
#pragma once

#include <string>
#include <vector>

#include "mybot_move_base/costmap.h"

namespace mybot_navigation
{

struct Velocity2D
{
  double vx = 0.0, vy = 0.0, wz = 0.0;
};

// How far a footprint that already touches an obstacle may be shrunk for escaping (m): about a
// cell plus the footprint padding (see Costmap::footprintClearing).
constexpr double kEscapeShrink = 0.06;

struct LocalPlannerParams
{
  // Velocity and acceleration limits (dwa_local_planner names and defaults).
  double max_vel_x = 0.55, min_vel_x = 0.0;
  double max_vel_y = 0.1, min_vel_y = -0.1;
  double max_vel_trans = 0.55, min_vel_trans = 0.1;
  double max_vel_theta = 1.0, min_vel_theta = 0.4;
  double acc_lim_x = 2.5, acc_lim_y = 2.5, acc_lim_theta = 3.2;
  // base_local_planner's switch: vy is sampled only for holonomic robots.
  bool holonomic_robot = false;
  // Forward simulation
  double sim_time = 1.7, sim_granularity = 0.025, angular_sim_granularity = 0.1;
  int vx_samples = 3, vy_samples = 10, vth_samples = 20;
  double controller_frequency = 20.0;  // sim_period = 1 / controller_frequency
  // Scoring
  double path_distance_bias = 32.0, goal_distance_bias = 24.0, occdist_scale = 0.01;
  double forward_point_distance = 0.325;
  // A holonomic robot's share of DWA's alignment costs (facing along the path): 0 keeps its
  // heading and strafes wherever the path goes, 1 scores it as a diff-drive robot. In between
  // it turns to drive forward (faster, laser ahead) on long stretches and strafes for offsets.
  double holonomic_align_scale = 0.0;
  double oscillation_reset_dist = 0.05, oscillation_reset_angle = 0.2;
  // Goal
  double xy_goal_tolerance = 0.1, yaw_goal_tolerance = 0.05;
  bool latch_xy_goal_tolerance = false;
  double trans_stopped_vel = 0.1, rot_stopped_vel = 0.1;
  // Rotate in place when the path direction is more than this off the heading (non-holonomic).
  double rotate_to_path_angle = 1.0;
};

std::string validate(const LocalPlannerParams& p);

enum class LocalStatus
{
  Moving,          // a velocity command towards the goal
  RotatingToGoal,  // within xy tolerance, turning to the goal heading
  GoalReached,     // within both tolerances and stopped
  NoValidTrajectory
};

struct LocalResult
{
  LocalStatus status = LocalStatus::NoValidTrajectory;
  Velocity2D cmd;
  std::vector<Pose2D> trajectory;  // the chosen trajectory (for rviz)
  double cost = 0.0;
  int valid_samples = 0;
  int samples = 0;
};

struct LocalWindow;  // local_planner.cpp: the part of the costmap one control step can reach

class LocalPlanner
{
public:
  explicit LocalPlanner(const LocalPlannerParams& params = LocalPlannerParams()) : params_(params) {}

  // A new global plan (map frame, same frame as the costmap and robot pose). Resets the goal
  // latch when the goal itself changed.
  void setPlan(const std::vector<Pose2D>& plan);
  const std::vector<Pose2D>& plan() const { return plan_; }

  // One control step: robot pose and measured velocity (robot frame).
  LocalResult computeVelocity(const Costmap& costmap, const Pose2D& pose, const Velocity2D& vel);

  bool isPositionReached(const Pose2D& pose) const;
  const LocalPlannerParams& params() const { return params_; }

  // Forward simulation of a constant velocity (exposed for tests).
  std::vector<Pose2D> simulate(const Pose2D& start, const Velocity2D& v) const;

private:
  double simPeriod() const { return 1.0 / params_.controller_frequency; }
  LocalResult rotateInPlace(const Costmap& cm, const Pose2D& pose, const Velocity2D& vel, double angle_error,
                            LocalStatus status) const;
  LocalResult stopWithAccLimits(const Costmap& cm, const Pose2D& pose, const Velocity2D& vel, LocalStatus status) const;
  void prunePlan(const Pose2D& pose);

  // The stages of computeVelocity, in order.
  // 1. Within xy_goal_tolerance: stop, then turn to the goal's heading.
  LocalResult arriveAtGoal(const Costmap& cm, const Pose2D& pose, const Velocity2D& vel, const Pose2D& goal);
  // 2. The window every trajectory can reach, with the distance maps to the local plan and goal.
  bool makeLocalWindow(const Costmap& cm, const Pose2D& pose, LocalWindow& window) const;
  // 3. A non-holonomic robot facing well away from the path turns in place first (true: `out` is set).
  bool turnTowardsPath(const Costmap& cm, const Pose2D& pose, const Velocity2D& vel, LocalResult& out) const;
  // 4. The oscillation flags are cleared once the robot has moved or turned enough.
  void resetOscillationFlags(const Pose2D& pose);
  // 5. DWA: sample the dynamic window, roll each velocity out, keep the cheapest admissible one.
  LocalResult sampleTrajectories(const Costmap& cm, const Pose2D& pose, const Velocity2D& vel,
                                 const LocalWindow& window, bool near_goal) const;
  //    Its parts: the admissible velocities around `centre` (every one sampled is counted);
  std::vector<Velocity2D> dynamicWindow(const Velocity2D& centre, bool honour_flags, int& n_samples) const;
  //    whether a rollout may be driven (getting out of a collision it starts in) and its worst
  //    cell cost;
  struct EscapeRule
  {
    bool start_in_collision = false;
    std::vector<Point2D> shrunk;  // the footprint shrunk just enough to clear the start, if any
  };
  struct Clearance
  {
    bool admissible = true;
    bool free = false;  // the footprint is (or came) clear of obstacles
    double occ = 0.0;   // the worst cell cost along it once free
  };
  Clearance checkClearance(const Costmap& cm, const Pose2D& start, const std::vector<Pose2D>& traj,
                           const EscapeRule& escape) const;
  //    and its cost: distances to the path and goal at its end and ahead of it, obstacles
  //    (false: its end is outside the window).
  bool trajectoryCost(const LocalWindow& window, const Pose2D& end, double occ, bool near_goal, double& cost) const;
  // 6. Remember the chosen rotation and strafe directions (the oscillation flags).
  void rememberDirection(const Velocity2D& cmd);

  LocalPlannerParams params_;
  std::vector<Pose2D> plan_;
  size_t plan_start_ = 0;  // plan poses before this one are behind the robot
  bool xy_latched_ = false;
  // Oscillation suppression (DWA's OscillationCostFunction, simplified): once a direction of
  // rotation or strafe has been chosen, the opposite sign is forbidden until the robot has moved.
  int forbid_rot_sign_ = 0, forbid_strafe_sign_ = 0;
  Pose2D osc_reference_;
  int last_rot_sign_ = 0, last_strafe_sign_ = 0;
};

}  // namespace mybot_navigation
