#include "mybot_move_base/navigator.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace mybot_navigation
{

std::string validate(const NavigatorParams& p)
{
  std::ostringstream e;
  if (p.planner_frequency < 0.0)
    e << "planner_frequency must be >= 0 (got " << p.planner_frequency << ")";
  else if (p.planner_patience < 0.0 || p.controller_patience < 0.0)
    e << "planner_patience and controller_patience must be >= 0";
  else if (p.oscillation_timeout < 0.0 || p.oscillation_distance < 0.0)
    e << "oscillation_timeout and oscillation_distance must be >= 0";
  else if (p.conservative_reset_dist < 0.0)
    e << "conservative_reset_dist must be >= 0 (got " << p.conservative_reset_dist << ")";
  else if (p.backup_distance < 0.0 || !(p.backup_speed > 0.0))
    e << "backup_distance must be >= 0 and backup_speed > 0";
  return e.str();
}

const char* toString(NavState s)
{
  switch (s)
  {
    case NavState::Idle:
      return "idle";
    case NavState::Planning:
      return "planning";
    case NavState::Controlling:
      return "controlling";
    case NavState::Clearing:
      return "clearing";
    case NavState::Succeeded:
      return "succeeded";
    case NavState::Aborted:
      return "aborted";
  }
  return "?";
}

Navigator::Navigator(const NavigatorParams& params, Costmap& global_costmap, Costmap& local_costmap,
                     const GlobalPlanner& planner, LocalPlanner& controller)
    : params_(params), global_(global_costmap), local_(local_costmap), planner_(planner), controller_(controller)
{
  if (params_.recovery_behavior_enabled)
  {
    recoveries_.push_back(Recovery::ConservativeReset);
    if (params_.clearing_rotation_allowed)
      recoveries_.push_back(Recovery::Rotate);
    recoveries_.push_back(Recovery::AggressiveReset);
    if (params_.backup_distance > 0.0)
      recoveries_.push_back(Recovery::BackUp);
  }
}

void Navigator::abort(const std::string& reason)
{
  state_ = NavState::Aborted;
  reason_ = reason;
  plan_.clear();
  controller_.setPlan({});
}

std::string Navigator::setGoal(const Pose2D& goal, double now, const Pose2D& pose)
{
  goal_ = goal;
  reason_.clear();
  plan_.clear();
  recovery_index_ = 0;
  planning_retries_ = 0;
  last_valid_plan_ = last_valid_control_ = last_oscillation_reset_ = now;
  oscillation_pose_ = pose;
  // A NaN goal was "outside the map" only by luck of the int conversion, and a NaN heading was
  // never reached: the goal is refused naming the field.
  const std::string bad = poseError(goal);
  if (!bad.empty())
  {
    abort("the goal's " + bad);
    return reason_;
  }
  int gx, gy;
  if (!global_.worldToMap(goal.x, goal.y, gx, gy))
  {
    abort("goal (" + std::to_string(goal.x) + ", " + std::to_string(goal.y) + ") is outside the map");
    return reason_;
  }
  state_ = NavState::Planning;
  NavOutput scratch;
  if (!plan(now, pose, scratch) && state_ == NavState::Aborted)
    return reason_;
  return "";
}

void Navigator::cancel()
{
  state_ = NavState::Idle;
  plan_.clear();
  controller_.setPlan({});
}

bool Navigator::plan(double now, const Pose2D& pose, NavOutput& out)
{
  last_plan_time_ = now;
  const PlanResult r = planner_.makePlan(global_, pose, goal_);
  if (r.status == PlanStatus::Ok)
  {
    plan_ = r.path;
    controller_.setPlan(plan_);
    last_valid_plan_ = now;
    planning_retries_ = 0;
    out.new_plan = true;
    if (state_ == NavState::Planning)
      state_ = NavState::Controlling;
    return true;
  }
  if (r.status == PlanStatus::GoalOffMap || r.status == PlanStatus::GoalInObstacle)
  {
    std::ostringstream m;
    m << r.message << " (goal " << goal_.x << ", " << goal_.y << ")";
    abort(m.str());
    return false;
  }
  ++planning_retries_;
  return false;
}

void Navigator::startRecovery(double now, const Pose2D& pose, Trigger trigger)
{
  (void)now;
  trigger_ = trigger;
  if (recovery_index_ >= recoveries_.size())
  {
    switch (trigger)
    {
      case Trigger::Planning:
        abort("failed to find a valid plan, even after executing recovery behaviors");
        break;
      case Trigger::Controlling:
        abort("failed to find a valid control, even after executing recovery behaviors");
        break;
      case Trigger::Oscillation:
        abort("robot is oscillating, even after executing recovery behaviors");
        break;
    }
    return;
  }
  state_ = NavState::Clearing;
  recovery_started_ = false;
  recovery_start_ = pose;
  // Recoveries are most needed where the footprint already touches something (a shelf end the
  // robot rounded too tightly): there every check would fail at the start pose and nothing would
  // move. They move instead while the footprint, shrunk just enough to clear the start, stays clear.
  recovery_footprint_.clear();
  if (local_.footprintCost(pose) < 0)
    recovery_footprint_ = local_.footprintClearing(pose, kEscapeShrink);
}

bool Navigator::clearForRecovery(const Pose2D& p) const
{
  return recovery_footprint_.empty() ? local_.footprintCost(p) >= 0 : local_.polygonCost(p, recovery_footprint_) >= 0;
}

bool Navigator::runRecovery(const Pose2D& pose, const Velocity2D& vel, NavOutput& out)
{
  (void)vel;
  const Recovery rec = recoveries_[recovery_index_];
  const LocalPlannerParams& lp = controller_.params();
  switch (rec)
  {
    case Recovery::ConservativeReset:
    case Recovery::AggressiveReset:
    {
      // move_base's reset recoveries: conservative keeps obstacles within conservative_reset_dist,
      // aggressive keeps those within 4 circumscribed radii.
      const double keep =
          rec == Recovery::ConservativeReset ? params_.conservative_reset_dist : 4.0 * global_.circumscribedRadius();
      out.message = rec == Recovery::ConservativeReset ? "conservative_reset" : "aggressive_reset";
      global_.clearObstaclesOutside(pose.x, pose.y, keep);
      local_.clearObstaclesOutside(pose.x, pose.y, keep);
      global_.updateCosts();
      local_.updateCosts();
      return true;
    }
    case Recovery::Rotate:
    {
      out.message = "rotate_recovery";
      if (!recovery_started_)
      {
        recovery_started_ = true;
        rotated_ = 0.0;
        last_theta_ = pose.theta;
      }
      rotated_ += std::abs(wrapAngle(pose.theta - last_theta_));
      last_theta_ = pose.theta;
      const double left = 2.0 * M_PI - rotated_;
      if (left <= lp.yaw_goal_tolerance)
        return true;
      // rotate_recovery: as fast as allowed, slow enough to stop after a full turn.
      const double v = std::min(lp.max_vel_theta, std::max(lp.min_vel_theta, std::sqrt(2.0 * lp.acc_lim_theta * left)));
      // Stop early if the footprint would hit something while turning.
      for (double a = 0.0; a <= std::min(left, v * lp.sim_time); a += lp.angular_sim_granularity)
        if (!clearForRecovery({pose.x, pose.y, pose.theta + a}))
          return true;
      out.cmd.wz = v;
      return false;
    }
    case Recovery::BackUp:
    {
      out.message = "backup_recovery";
      if (!recovery_started_)
        recovery_started_ = true;
      const double done = std::hypot(pose.x - recovery_start_.x, pose.y - recovery_start_.y);
      if (done >= params_.backup_distance)
        return true;
      for (double d = 0.0; d <= 0.1 + params_.backup_speed * 0.5; d += local_.resolution())
      {
        const Pose2D p{pose.x - d * std::cos(pose.theta), pose.y - d * std::sin(pose.theta), pose.theta};
        if (!clearForRecovery(p))
          return true;  // blocked behind as well
      }
      out.cmd.vx = -params_.backup_speed;
      return false;
    }
  }
  return true;
}

NavOutput Navigator::step(double now, const Pose2D& pose, const Velocity2D& vel)
{
  NavOutput out;
  if (state_ == NavState::Idle || state_ == NavState::Succeeded || state_ == NavState::Aborted)
  {
    out.state = state_;
    out.message = reason_;
    return out;
  }
  // Broken odometry (an overflowed encoder count) puts the robot 1e308 m away: no command can be
  // worked out from there, not even a recovery's turn. Stop and say why.
  const std::string bad = poseError(pose);
  if (!bad.empty())
  {
    abort("the robot's pose " + bad + ": is the odometry broken?");
    out.state = state_;
    out.message = reason_;
    return out;
  }

  // Oscillation: the robot must keep moving by oscillation_distance within oscillation_timeout.
  if (std::hypot(pose.x - oscillation_pose_.x, pose.y - oscillation_pose_.y) >= params_.oscillation_distance)
  {
    last_oscillation_reset_ = now;
    oscillation_pose_ = pose;
    if (trigger_ == Trigger::Oscillation)
      recovery_index_ = 0;
  }

  if (state_ == NavState::Planning)
  {
    if (!plan(now, pose, out))
    {
      if (state_ == NavState::Aborted)
      {
        out.state = state_;
        out.message = reason_;
        return out;
      }
      const bool out_of_retries = params_.max_planning_retries >= 0 && planning_retries_ > params_.max_planning_retries;
      if (now - last_valid_plan_ > params_.planner_patience || out_of_retries)
        startRecovery(now, pose, Trigger::Planning);
    }
    else if (trigger_ == Trigger::Planning)
    {
      recovery_index_ = 0;
    }
  }
  else if (state_ == NavState::Controlling)
  {
    if (params_.planner_frequency > 0.0 && now - last_plan_time_ >= 1.0 / params_.planner_frequency)
      plan(now, pose, out);  // on failure keep following the previous plan
    if (state_ == NavState::Aborted)
    {
      out.state = state_;
      out.message = reason_;
      return out;
    }
    if (params_.oscillation_timeout > 0.0 && now - last_oscillation_reset_ > params_.oscillation_timeout)
    {
      last_oscillation_reset_ = now;
      startRecovery(now, pose, Trigger::Oscillation);
    }
    else
    {
      out.local = controller_.computeVelocity(local_, pose, vel);
      switch (out.local.status)
      {
        case LocalStatus::GoalReached:
          state_ = NavState::Succeeded;
          plan_.clear();
          break;
        case LocalStatus::Moving:
        case LocalStatus::RotatingToGoal:
          out.cmd = out.local.cmd;
          last_valid_control_ = now;
          if (trigger_ == Trigger::Controlling)
            recovery_index_ = 0;
          break;
        case LocalStatus::NoValidTrajectory:
          if (now - last_valid_control_ > params_.controller_patience)
            startRecovery(now, pose, Trigger::Controlling);
          else
            state_ = NavState::Planning;  // move_base replans when the controller fails
          break;
      }
    }
  }

  if (state_ == NavState::Clearing)
  {
    if (runRecovery(pose, vel, out))
    {
      ++recoveries_run_;
      ++recovery_index_;
      state_ = NavState::Planning;
      last_valid_plan_ = last_valid_control_ = last_oscillation_reset_ = now;
      oscillation_pose_ = pose;
      out.cmd = Velocity2D();
    }
  }
  out.state = state_;
  if (state_ == NavState::Aborted)
    out.message = reason_;
  return out;
}

}  // namespace mybot_navigation
