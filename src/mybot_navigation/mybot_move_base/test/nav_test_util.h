// Helpers of the local planner and navigator tests: robot parameters, costmaps, straight plans,
// and a closed loop (navigator, costmaps, a kinematic robot with a simulated laser).
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "mybot_amcl/amcl_models.h"
#include "mybot_move_base/local_planner.h"
#include "mybot_move_base/navigator.h"
#include "mybot_nav_common/ray_cast.h"
#include "synthetic_world.h"

namespace mybot_navigation
{
namespace nav_test
{

inline LocalPlannerParams diffParams()
{
  LocalPlannerParams p;
  p.max_vel_x = 0.5;
  p.min_vel_x = -0.1;
  p.max_vel_trans = 0.5;
  p.min_vel_trans = 0.05;
  p.max_vel_theta = 1.5;
  p.min_vel_theta = 0.3;
  p.acc_lim_x = 1.5;
  p.acc_lim_theta = 3.0;
  p.vx_samples = 8;
  p.vth_samples = 20;
  p.sim_time = 1.5;
  p.controller_frequency = 10.0;
  p.xy_goal_tolerance = 0.1;
  p.yaw_goal_tolerance = 0.1;
  return p;
}

inline LocalPlannerParams holonomicParams()
{
  LocalPlannerParams p = diffParams();
  p.holonomic_robot = true;
  p.max_vel_y = 0.4;
  p.min_vel_y = -0.4;
  p.acc_lim_y = 1.5;
  p.vy_samples = 9;
  p.vx_samples = 9;
  p.vth_samples = 11;
  return p;
}

inline CostmapParams costmapParams(bool rolling, bool rectangle)
{
  CostmapParams p;
  if (rectangle)
    p.footprint = {{0.3, 0.25}, {0.3, -0.25}, {-0.3, -0.25}, {-0.3, 0.25}};
  else
    p.robot_radius = 0.2;
  p.inflation_radius = 0.5;
  p.cost_scaling_factor = 5.0;
  p.rolling_window = rolling;
  p.width = p.height = 4.0;
  return p;
}

inline Costmap staticCostmap(const GridMap& world, bool rectangle = false)
{
  Costmap cm(costmapParams(false, rectangle));
  cm.setStaticMap(world);
  return cm;
}

inline std::vector<Pose2D> straightPlan(const Pose2D& start, double step, int n)
{
  std::vector<Pose2D> plan;
  for (int i = 0; i <= n; ++i)
    plan.push_back(
        {start.x + step * i * std::cos(start.theta), start.y + step * i * std::sin(start.theta), start.theta});
  return plan;
}

// Global and local costmaps on one world, a planner, a controller and the navigator.
struct NavStack
{
  NavStack(const GridMap& w, const LocalPlannerParams& lp, bool rectangle,
           const NavigatorParams& np = NavigatorParams())
      : world(w),
        global(costmapParams(false, rectangle)),
        local(costmapParams(true, rectangle)),
        controller(lp),
        nav(np, global, local, planner, controller)
  {
    global.setStaticMap(world);
    local.setStaticMap(world);
  }
  NavStack(const GridMap& w, const LocalPlannerParams& lp, const CostmapParams& cp, const NavigatorParams& np)
      : world(w),
        global(
            [&]
            {
              CostmapParams g = cp;
              g.rolling_window = false;
              return g;
            }()),
        local(
            [&]
            {
              CostmapParams l = cp;
              l.rolling_window = true;
              return l;
            }()),
        controller(lp),
        nav(np, global, local, planner, controller)
  {
    global.setStaticMap(world);
    local.setStaticMap(world);
  }
  GridMap world;
  Costmap global, local;
  GlobalPlanner planner;
  LocalPlanner controller;
  Navigator nav;
};

struct ClosedLoopResult
{
  NavState state = NavState::Idle;
  double time = 0.0;
  double distance = 0.0;
  double min_clearance = 1e9;  // world-truth distance from the robot centre to obstacles
  double max_abs_vy = 0.0;
  Pose2D final_pose;
  std::string message;
};

// Integrates the commanded velocity perfectly (the controller sees the true pose) and feeds
// simulated 360-degree scans to both costmaps.
inline ClosedLoopResult runToGoal(NavStack& st, Pose2D pose, const Pose2D& goal, double timeout,
                                  double cancel_at = -1.0)
{
  const GridMap& world = st.world;
  Costmap &global = st.global, &local = st.local;
  Navigator& nav = st.nav;
  ClosedLoopResult res;
  const double dt = 0.1;
  Velocity2D vel;
  double t = 0.0;
  std::string err = nav.setGoal(goal, t, pose);
  res.message = err;
  if (!err.empty())
  {
    res.state = nav.state();
    return res;
  }
  LikelihoodField clearance(
      []
      {
        LaserModelParams lp;
        lp.likelihood_max_dist = 5.0;
        return lp;
      }());
  clearance.setMap(world);
  for (; t < timeout; t += dt)
  {
    if (cancel_at >= 0 && t >= cancel_at && nav.state() != NavState::Idle)
      nav.cancel();
    const int beams = 180;
    const double inc = 2 * M_PI / beams;
    const std::vector<float> r = simulateScan(world, pose, -M_PI, inc, beams, 5.0);
    std::vector<Point2D> hits, ends;
    for (int i = 0; i < beams; ++i)
    {
      const double a = pose.theta - M_PI + inc * i;
      if (std::isfinite(r[i]))
        hits.push_back({pose.x + r[i] * std::cos(a), pose.y + r[i] * std::sin(a)});
      else
        ends.push_back({pose.x + 5.0 * std::cos(a), pose.y + 5.0 * std::sin(a)});
    }
    local.updateOrigin(pose.x, pose.y);
    global.updateWithScan({pose.x, pose.y}, hits, ends);
    local.updateWithScan({pose.x, pose.y}, hits, ends);
    global.updateCosts();
    local.updateCosts();
    const NavOutput out = nav.step(t, pose, vel);
    if (std::getenv("NAV_DEBUG") && out.local.status == LocalStatus::NoValidTrajectory)
      for (int y = 0; y < local.height(); ++y)
        for (int x = 0; x < local.width(); ++x)
        {
          const Point2D w = local.mapToWorld(x, y);
          if (local.cost(x, y) == costs::kLethal && std::hypot(w.x - pose.x, w.y - pose.y) < 0.5)
            std::printf("lethal %.3f,%.3f obstacle=%d\n", w.x, w.y, local.isObstacle(x, y));
        }
    if (std::getenv("NAV_DEBUG"))
      std::printf("t=%.1f pose=%.2f,%.2f,%.2f state=%s cmd=%.2f,%.2f,%.2f local=%d valid=%d/%d %s\n", t, pose.x, pose.y,
                  pose.theta, toString(out.state), out.cmd.vx, out.cmd.vy, out.cmd.wz,
                  static_cast<int>(out.local.status), out.local.valid_samples, out.local.samples, out.message.c_str());
    res.state = out.state;
    res.message = out.message;
    if (out.state == NavState::Succeeded || out.state == NavState::Aborted ||
        (cancel_at >= 0 && out.state == NavState::Idle))
    {
      vel = out.cmd;
      break;
    }
    vel = out.cmd;
    res.max_abs_vy = std::max(res.max_abs_vy, std::abs(vel.vy));
    const Pose2D before = pose;
    pose = compose(pose, {(vel.vx * dt), (vel.vy * dt), vel.wz * dt});
    res.distance += std::hypot(pose.x - before.x, pose.y - before.y);
    res.min_clearance = std::min(res.min_clearance, clearance.distance(pose.x, pose.y));
  }
  res.time = t;
  res.final_pose = pose;
  return res;
}

}  // namespace nav_test
}  // namespace mybot_navigation
