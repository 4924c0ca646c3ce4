#include "mybot_move_base/local_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "mybot_nav_common/costmap_distance.h"

namespace mybot_navigation
{

std::string validate(const LocalPlannerParams& p)
{
  std::ostringstream e;
  if (p.max_vel_x < p.min_vel_x)
    e << "max_vel_x (" << p.max_vel_x << ") must be >= min_vel_x (" << p.min_vel_x << ")";
  else if (p.holonomic_robot && p.max_vel_y < p.min_vel_y)
    e << "max_vel_y (" << p.max_vel_y << ") must be >= min_vel_y (" << p.min_vel_y << ")";
  else if (!(p.max_vel_trans > 0.0))
    e << "max_vel_trans must be > 0 (got " << p.max_vel_trans << ")";
  else if (!(p.max_vel_theta > 0.0) || p.min_vel_theta < 0.0 || p.min_vel_theta > p.max_vel_theta)
    e << "max_vel_theta must be > 0 and min_vel_theta in [0, max_vel_theta]";
  else if (!(p.acc_lim_x > 0.0) || !(p.acc_lim_theta > 0.0) || (p.holonomic_robot && !(p.acc_lim_y > 0.0)))
    e << "acc_lim_x, acc_lim_y and acc_lim_theta must be > 0";
  else if (!(p.sim_time > 0.0) || !(p.sim_granularity > 0.0) || !(p.angular_sim_granularity > 0.0))
    e << "sim_time, sim_granularity and angular_sim_granularity must be > 0";
  else if (p.vx_samples < 1 || p.vth_samples < 1 || (p.holonomic_robot && p.vy_samples < 1))
    e << "vx_samples, vy_samples and vth_samples must be >= 1";
  else if (!(p.controller_frequency > 0.0))
    e << "controller_frequency must be > 0 (got " << p.controller_frequency << ")";
  else if (!(p.xy_goal_tolerance > 0.0) || !(p.yaw_goal_tolerance > 0.0))
    e << "xy_goal_tolerance and yaw_goal_tolerance must be > 0";
  else if (p.path_distance_bias < 0 || p.goal_distance_bias < 0 || p.occdist_scale < 0)
    e << "path_distance_bias, goal_distance_bias and occdist_scale must be >= 0";
  else if (!(p.holonomic_align_scale >= 0.0 && p.holonomic_align_scale <= 1.0))
    e << "holonomic_align_scale must be in [0, 1] (got " << p.holonomic_align_scale << ")";
  return e.str();
}

namespace
{

double sign(double v)
{
  return v < 0.0 ? -1.0 : 1.0;
}

std::vector<double> samples(double lo, double hi, int n)
{
  std::vector<double> out;
  if (hi < lo)
    return out;
  if (n <= 1 || hi - lo < 1e-9)
  {
    out.push_back(n <= 1 ? std::clamp(0.0, lo, hi) : lo);
    return out;
  }
  for (int i = 0; i < n; ++i)
    out.push_back(lo + (hi - lo) * i / (n - 1));
  if (lo < 0.0 && hi > 0.0)
    out.push_back(0.0);  // always consider stopping that axis
  return out;
}

}  // namespace

void LocalPlanner::setPlan(const std::vector<Pose2D>& plan)
{
  if (plan.empty() || plan_.empty() ||
      std::hypot(plan.back().x - plan_.back().x, plan.back().y - plan_.back().y) > 1e-6)
    xy_latched_ = false;
  plan_ = plan;
  plan_start_ = 0;
}

bool LocalPlanner::isPositionReached(const Pose2D& pose) const
{
  if (plan_.empty())
    return false;
  return std::hypot(plan_.back().x - pose.x, plan_.back().y - pose.y) <= params_.xy_goal_tolerance;
}

std::vector<Pose2D> LocalPlanner::simulate(const Pose2D& start, const Velocity2D& v) const
{
  const double trans = std::hypot(v.vx, v.vy);
  const int steps = std::max(
      1, static_cast<int>(std::ceil(std::max(params_.sim_time * trans / params_.sim_granularity,
                                             params_.sim_time * std::abs(v.wz) / params_.angular_sim_granularity))));
  const double dt = params_.sim_time / steps;
  std::vector<Pose2D> traj;
  traj.reserve(static_cast<size_t>(steps) + 1);
  Pose2D p = start;
  traj.push_back(p);
  for (int i = 0; i < steps; ++i)
  {
    const double c = std::cos(p.theta), s = std::sin(p.theta);
    p.x += (v.vx * c - v.vy * s) * dt;
    p.y += (v.vx * s + v.vy * c) * dt;
    p.theta = wrapAngle(p.theta + v.wz * dt);
    traj.push_back(p);
  }
  return traj;
}

void LocalPlanner::prunePlan(const Pose2D& pose)
{
  // Advance to the closest plan pose among the next few metres; never go backwards.
  double best = std::numeric_limits<double>::infinity();
  size_t best_i = plan_start_;
  double along = 0.0;
  for (size_t i = plan_start_; i < plan_.size(); ++i)
  {
    if (i > plan_start_)
      along += std::hypot(plan_[i].x - plan_[i - 1].x, plan_[i].y - plan_[i - 1].y);
    if (along > 2.0)
      break;
    const double d = std::hypot(plan_[i].x - pose.x, plan_[i].y - pose.y);
    if (d < best)
    {
      best = d;
      best_i = i;
    }
  }
  plan_start_ = best_i;
}

LocalResult LocalPlanner::stopWithAccLimits(const Costmap& cm, const Pose2D& pose, const Velocity2D& vel,
                                            LocalStatus status) const
{
  const double dt = simPeriod();
  LocalResult r;
  r.status = status;
  r.cmd.vx = sign(vel.vx) * std::max(0.0, std::abs(vel.vx) - params_.acc_lim_x * dt);
  r.cmd.vy = sign(vel.vy) * std::max(0.0, std::abs(vel.vy) - params_.acc_lim_y * dt);
  r.cmd.wz = sign(vel.wz) * std::max(0.0, std::abs(vel.wz) - params_.acc_lim_theta * dt);
  r.trajectory = simulate(pose, r.cmd);
  for (const Pose2D& p : r.trajectory)
    if (cm.footprintCost(p) < 0)
    {
      r.cmd = Velocity2D();  // braking into an obstacle: stop now
      break;
    }
  return r;
}

LocalResult LocalPlanner::rotateInPlace(const Costmap& cm, const Pose2D& pose, const Velocity2D& vel,
                                        double angle_error, LocalStatus status) const
{
  // base_local_planner's rotateToGoal: at least min_vel_theta, within the acceleration limits,
  // and slow enough to stop at the target heading.
  const double dt = simPeriod();
  const double min_v = params_.min_vel_theta, max_v = params_.max_vel_theta;
  double v = angle_error > 0.0 ? std::min(max_v, std::max(min_v, angle_error))
                               : std::max(-max_v, std::min(-min_v, angle_error));
  const double max_acc_vel = std::abs(vel.wz) + params_.acc_lim_theta * dt;
  const double min_acc_vel = std::abs(vel.wz) - params_.acc_lim_theta * dt;
  v = sign(v) * std::min(std::max(std::abs(v), min_acc_vel), max_acc_vel);
  v = sign(v) * std::min(std::sqrt(2.0 * params_.acc_lim_theta * std::abs(angle_error)), std::abs(v));
  v = v > 0.0 ? std::min(max_v, std::max(min_v, v)) : std::max(-max_v, std::min(-min_v, v));
  LocalResult r;
  r.status = status;
  r.cmd.wz = v;
  r.trajectory = simulate(pose, r.cmd);
  for (const Pose2D& p : r.trajectory)
    if (cm.footprintCost(p) < 0)
    {
      r.status = LocalStatus::NoValidTrajectory;
      r.cmd = Velocity2D();
      break;
    }
  return r;
}

// The square window around the robot that every trajectory end point (and the point ahead of it)
// can reach, with the distance (m) of each cell to the local plan and to the local goal: DWA's
// MapGridCostFunction without and with is_local_goal_function.
struct LocalWindow
{
  const Costmap* cm = nullptr;
  double res = 0.0;
  double reach = 0.0;  // m from the robot a trajectory's forward point can get
  int x0 = 0, y0 = 0, size = 0;
  std::vector<float> path_dist, goal_dist;

  bool index(double x, double y, size_t& k) const
  {
    int cx, cy;
    cm->worldToMap(x, y, cx, cy);
    const int lx = cx - x0, ly = cy - y0;
    if (lx < 0 || ly < 0 || lx >= size || ly >= size)
      return false;
    k = static_cast<size_t>(ly) * size + lx;
    return true;
  }
  bool lookup(const std::vector<float>& m, double x, double y, double& out) const
  {
    size_t k = 0;
    if (!index(x, y, k))
      return false;
    out = m[k] * res;
    return true;
  }
};

LocalResult LocalPlanner::computeVelocity(const Costmap& cm, const Pose2D& pose, const Velocity2D& vel)
{
  if (plan_.empty())
    return LocalResult();
  prunePlan(pose);
  const Pose2D& goal = plan_.back();
  const double goal_dist = std::hypot(goal.x - pose.x, goal.y - pose.y);
  if (goal_dist <= params_.xy_goal_tolerance || (params_.latch_xy_goal_tolerance && xy_latched_))
    return arriveAtGoal(cm, pose, vel, goal);

  LocalWindow window;
  if (!makeLocalWindow(cm, pose, window))
    return LocalResult();
  LocalResult turn;
  if (turnTowardsPath(cm, pose, vel, turn))
    return turn;
  resetOscillationFlags(pose);
  LocalResult best = sampleTrajectories(cm, pose, vel, window, goal_dist <= params_.forward_point_distance);
  if (best.status == LocalStatus::Moving)
    rememberDirection(best.cmd);
  return best;
}

// Stop, then turn to the goal heading (latched stop-and-rotate, no oscillation).
LocalResult LocalPlanner::arriveAtGoal(const Costmap& cm, const Pose2D& pose, const Velocity2D& vel, const Pose2D& goal)
{
  if (params_.latch_xy_goal_tolerance)
    xy_latched_ = true;
  const double yaw_err = wrapAngle(goal.theta - pose.theta);
  const bool stopped =
      std::hypot(vel.vx, vel.vy) <= params_.trans_stopped_vel && std::abs(vel.wz) <= params_.rot_stopped_vel;
  if (std::abs(yaw_err) <= params_.yaw_goal_tolerance)
  {
    if (stopped)
    {
      LocalResult r;
      r.status = LocalStatus::GoalReached;
      return r;
    }
    return stopWithAccLimits(cm, pose, vel, LocalStatus::RotatingToGoal);
  }
  if (std::hypot(vel.vx, vel.vy) > params_.trans_stopped_vel)
    return stopWithAccLimits(cm, pose, vel, LocalStatus::RotatingToGoal);
  return rotateInPlace(cm, pose, vel, yaw_err, LocalStatus::RotatingToGoal);
}

bool LocalPlanner::makeLocalWindow(const Costmap& cm, const Pose2D& pose, LocalWindow& w) const
{
  w.cm = &cm;
  w.res = cm.resolution();
  w.reach = std::max(params_.max_vel_trans, std::hypot(params_.max_vel_x, params_.max_vel_y)) * params_.sim_time +
            params_.forward_point_distance + 0.5;
  const int half = static_cast<int>(std::ceil(w.reach / w.res));
  int rx, ry;
  if (!cm.worldToMap(pose.x, pose.y, rx, ry))
    return false;
  w.x0 = rx - half;
  w.y0 = ry - half;
  w.size = 2 * half + 1;
  std::vector<uint8_t> path_seed(static_cast<size_t>(w.size) * w.size, 0), goal_seed(path_seed.size(), 0);
  // The local plan: the contiguous part of the plan inside the window; its last pose is the
  // local goal.
  size_t local_goal_i = plan_start_;
  bool any = false;
  for (size_t i = plan_start_; i < plan_.size(); ++i)
  {
    size_t k = 0;
    if (!w.index(plan_[i].x, plan_[i].y, k))
    {
      if (any)
        break;
      continue;
    }
    path_seed[k] = 1;
    local_goal_i = i;
    any = true;
  }
  if (!any)
    return false;
  size_t k = 0;
  w.index(plan_[local_goal_i].x, plan_[local_goal_i].y, k);
  goal_seed[k] = 1;
  w.path_dist = distanceTransform(path_seed, w.size, w.size);
  w.goal_dist = distanceTransform(goal_seed, w.size, w.size);
  return true;
}

bool LocalPlanner::turnTowardsPath(const Costmap& cm, const Pose2D& pose, const Velocity2D& vel, LocalResult& out) const
{
  if (params_.holonomic_robot)
    return false;
  size_t look = plan_start_;
  while (look + 1 < plan_.size() &&
         std::hypot(plan_[look].x - pose.x, plan_[look].y - pose.y) < 2.0 * params_.forward_point_distance)
    ++look;
  const double dx = plan_[look].x - pose.x, dy = plan_[look].y - pose.y;
  if (std::hypot(dx, dy) <= 1e-3)
    return false;
  const double err = wrapAngle(std::atan2(dy, dx) - pose.theta);
  if (std::abs(err) <= params_.rotate_to_path_angle)
    return false;
  if (std::hypot(vel.vx, vel.vy) > params_.trans_stopped_vel)
  {
    out = stopWithAccLimits(cm, pose, vel, LocalStatus::Moving);
    return true;
  }
  out = rotateInPlace(cm, pose, vel, err, LocalStatus::Moving);
  return out.status == LocalStatus::Moving;  // else fall through to sampling
}

void LocalPlanner::resetOscillationFlags(const Pose2D& pose)
{
  if (std::hypot(pose.x - osc_reference_.x, pose.y - osc_reference_.y) > params_.oscillation_reset_dist ||
      std::abs(wrapAngle(pose.theta - osc_reference_.theta)) > params_.oscillation_reset_angle)
  {
    forbid_rot_sign_ = forbid_strafe_sign_ = 0;
    osc_reference_ = pose;
  }
}

// Starting in collision (localization error, or an obstacle marked at the footprint's edge)
// every trajectory would be rejected and the robot would sit until the recoveries, blocked the
// same way, abort the goal. Accept the trajectories that get out: collisions are tolerated until
// the footprint first comes free, after which it must stay free. Until then each pose must be
// clear with the footprint shrunk by kEscapeShrink (a side grazing a shelf drives along it and
// turns away, over several cycles if need be), or lie within kEscapeDistance of the start on a
// trajectory that comes free (an edge pushed into a wall backs out). Nothing tunnels through a wall.
LocalPlanner::Clearance LocalPlanner::checkClearance(const Costmap& cm, const Pose2D& start,
                                                     const std::vector<Pose2D>& traj, const EscapeRule& escape) const
{
  constexpr double kEscapeDistance = 0.15;  // m
  Clearance out;
  out.free = !escape.start_in_collision;
  bool deep = false;
  for (const Pose2D& p : traj)
  {
    const double c = cm.footprintCost(p);
    if (c < 0)
    {
      if (!out.free && !escape.shrunk.empty() && cm.polygonCost(p, escape.shrunk) >= 0)
        continue;  // grazing: still getting out
      if (!out.free && std::hypot(p.x - start.x, p.y - start.y) <= kEscapeDistance)
      {
        deep = true;  // acceptable only if it comes free
        continue;
      }
      out.admissible = false;
      return out;
    }
    out.free = true;
    out.occ = std::max(out.occ, c);
  }
  out.admissible = !(deep && !out.free);
  return out;
}

std::vector<Velocity2D> LocalPlanner::dynamicWindow(const Velocity2D& centre, bool honour_flags, int& n_samples) const
{
  const double dt = simPeriod();
  const std::vector<double> vxs =
      samples(std::max(params_.min_vel_x, centre.vx - params_.acc_lim_x * dt),
              std::min(params_.max_vel_x, centre.vx + params_.acc_lim_x * dt), params_.vx_samples);
  const std::vector<double> vys =
      params_.holonomic_robot
          ? samples(std::max(params_.min_vel_y, centre.vy - params_.acc_lim_y * dt),
                    std::min(params_.max_vel_y, centre.vy + params_.acc_lim_y * dt), params_.vy_samples)
          : std::vector<double>{0.0};
  const std::vector<double> vths =
      samples(std::max(-params_.max_vel_theta, centre.wz - params_.acc_lim_theta * dt),
              std::min(params_.max_vel_theta, centre.wz + params_.acc_lim_theta * dt), params_.vth_samples);
  std::vector<Velocity2D> out;
  for (double vx : vxs)
    for (double vy : vys)
      for (double wz : vths)
      {
        ++n_samples;
        const double vmag = std::hypot(vx, vy);
        if (vmag > params_.max_vel_trans + 1e-9)
          continue;
        if (vmag + 1e-9 < params_.min_vel_trans && std::abs(wz) + 1e-9 < params_.min_vel_theta)
          continue;
        if (honour_flags && forbid_rot_sign_ != 0 && wz * forbid_rot_sign_ > 1e-9 && vmag < params_.min_vel_trans)
          continue;
        if (honour_flags && forbid_strafe_sign_ != 0 && vy * forbid_strafe_sign_ > 1e-9)
          continue;
        out.push_back({vx, vy, wz});
      }
  return out;
}

bool LocalPlanner::trajectoryCost(const LocalWindow& window, const Pose2D& end, double occ, bool near_goal,
                                  double& cost) const
{
  double pd, gd;
  if (!window.lookup(window.path_dist, end.x, end.y, pd) || !window.lookup(window.goal_dist, end.x, end.y, gd))
    return false;
  cost = params_.path_distance_bias * pd + params_.goal_distance_bias * gd + params_.occdist_scale * occ;
  // DWA's alignment and goal-front costs at a point ahead of the trajectory's end: they make
  // the robot face along the path (for a holonomic robot, holonomic_align_scale of them).
  const double align = params_.holonomic_robot ? params_.holonomic_align_scale : 1.0;
  if (!near_goal && align > 0.0)
  {
    const double fx = end.x + params_.forward_point_distance * std::cos(end.theta);
    const double fy = end.y + params_.forward_point_distance * std::sin(end.theta);
    double fpd, fgd;
    if (window.lookup(window.path_dist, fx, fy, fpd) && window.lookup(window.goal_dist, fx, fy, fgd))
      cost += align * (params_.path_distance_bias * fpd + params_.goal_distance_bias * fgd);
    else
      cost += align * (params_.path_distance_bias + params_.goal_distance_bias) * window.reach;
  }
  return true;
}

LocalResult LocalPlanner::sampleTrajectories(const Costmap& cm, const Pose2D& pose, const Velocity2D& vel,
                                             const LocalWindow& window, bool near_goal) const
{
  constexpr double kStillGrazingCost = 1e4;
  EscapeRule escape;
  escape.start_in_collision = cm.footprintCost(pose) < 0;
  // The least shrink that clears the start: no trajectory may graze deeper than the robot
  // already does, or the planner would steer into shelf corners in narrow gaps.
  // Empty when even kEscapeShrink does not clear the start: only the short escape applies.
  if (escape.start_in_collision)
    escape.shrunk = cm.footprintClearing(pose, kEscapeShrink);
  LocalResult best;
  best.cost = std::numeric_limits<double>::infinity();
  int n_samples = 0, n_valid = 0;
  // Pass 0 is DWA's dynamic window around the current velocity, with the oscillation flags.
  // If nothing there is admissible (a turn already committed towards a shelf corner, or the
  // only way out is the rotation the oscillation flags forbid), pass 1 samples the window of
  // a stopped robot without the flags: the base controller brakes into the new command, where
  // DWA would command zero and let the recoveries abort the goal.
  for (int pass = 0; pass < 2 && n_valid == 0; ++pass)
    for (const Velocity2D& v : dynamicWindow(pass == 0 ? vel : Velocity2D(), pass == 0, n_samples))
    {
      const std::vector<Pose2D> traj = simulate(pose, v);
      const Clearance clear = checkClearance(cm, pose, traj, escape);
      double cost;
      if (!clear.admissible || !trajectoryCost(window, traj.back(), clear.occ, near_goal, cost))
        continue;
      if (!clear.free)
        cost += kStillGrazingCost;  // any trajectory that comes free is better
      ++n_valid;
      if (cost < best.cost)
      {
        best.cost = cost;
        best.cmd = v;
        best.trajectory = traj;
      }
    }
  best.samples = n_samples;
  best.valid_samples = n_valid;
  if (n_valid == 0)
  {
    best.status = LocalStatus::NoValidTrajectory;
    best.cmd = Velocity2D();
    best.cost = 0.0;
    return best;
  }
  best.status = LocalStatus::Moving;
  return best;
}

// Remember the chosen rotation / strafe direction: reversing it while nearly stationary is
// forbidden until the robot has moved (resetOscillationFlags).
void LocalPlanner::rememberDirection(const Velocity2D& cmd)
{
  const int rot_sign = cmd.wz > 1e-3 ? 1 : cmd.wz < -1e-3 ? -1 : 0;
  const int strafe_sign = cmd.vy > 1e-3 ? 1 : cmd.vy < -1e-3 ? -1 : 0;
  if (rot_sign != 0 && last_rot_sign_ != 0 && rot_sign != last_rot_sign_)
    forbid_rot_sign_ = last_rot_sign_;
  if (strafe_sign != 0 && last_strafe_sign_ != 0 && strafe_sign != last_strafe_sign_)
    forbid_strafe_sign_ = last_strafe_sign_;
  if (rot_sign != 0)
    last_rot_sign_ = rot_sign;
  if (strafe_sign != 0)
    last_strafe_sign_ = strafe_sign;
}

}  // namespace mybot_navigation
