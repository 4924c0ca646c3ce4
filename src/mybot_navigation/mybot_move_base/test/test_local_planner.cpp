// DWA local planner and the move_base state machine, closed loop on a kinematic robot with a
// simulated laser in a synthetic world.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "mybot_amcl/amcl_models.h"
#include "mybot_move_base/local_planner.h"
#include "mybot_move_base/navigator.h"
#include "mybot_nav_common/ray_cast.h"
#include "synthetic_world.h"

using namespace mybot_navigation;

namespace
{

LocalPlannerParams diffParams()
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

LocalPlannerParams holonomicParams()
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

CostmapParams costmapParams(bool rolling, bool rectangle)
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

Costmap staticCostmap(const GridMap& world, bool rectangle = false)
{
  Costmap cm(costmapParams(false, rectangle));
  cm.setStaticMap(world);
  return cm;
}

std::vector<Pose2D> straightPlan(const Pose2D& start, double step, int n)
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
ClosedLoopResult runToGoal(NavStack& st, Pose2D pose, const Pose2D& goal, double timeout, double cancel_at = -1.0)
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

}  // namespace

TEST(LocalPlanner, ValidateNamesTheParameter)
{
  LocalPlannerParams p;
  EXPECT_EQ(validate(p), "");
  p.max_vel_theta = 0;
  EXPECT_NE(validate(p).find("max_vel_theta"), std::string::npos);
  p = LocalPlannerParams();
  p.controller_frequency = 0;
  EXPECT_NE(validate(p).find("controller_frequency"), std::string::npos);
}

TEST(LocalPlanner, SimulateIntegratesHolonomicMotion)
{
  LocalPlannerParams p;
  p.sim_time = 1.0;
  LocalPlanner lp(p);
  const auto t = lp.simulate({0, 0, M_PI / 2}, {0.5, 0.2, 0.0});
  EXPECT_NEAR(t.back().x, -0.2, 1e-9);
  EXPECT_NEAR(t.back().y, 0.5, 1e-9);
  const auto r = lp.simulate({0, 0, 0}, {0.0, 0.0, 1.0});
  EXPECT_NEAR(r.back().theta, 1.0, 1e-9);
  EXPECT_GE(r.size(), 11u);  // angular_sim_granularity 0.1 rad
}

TEST(LocalPlanner, DiffDriveFollowsAStraightPathForward)
{
  const GridMap world = makeWorld(8.0, 4.0, 0.05, {});
  const Costmap cm = staticCostmap(world);
  LocalPlanner lp(diffParams());
  lp.setPlan(straightPlan({1.0, 2.0, 0.0}, 0.05, 100));
  const LocalResult r = lp.computeVelocity(cm, {1.0, 2.0, 0.0}, {0.3, 0, 0});
  ASSERT_EQ(r.status, LocalStatus::Moving);
  EXPECT_GT(r.cmd.vx, 0.3);
  EXPECT_NEAR(r.cmd.wz, 0.0, 0.2);
  EXPECT_EQ(r.cmd.vy, 0.0);  // never strafes
  EXPECT_GT(r.valid_samples, 0);
}

TEST(LocalPlanner, RotatesInPlaceWhenThePathIsBehind)
{
  const GridMap world = makeWorld(8.0, 4.0, 0.05, {});
  const Costmap cm = staticCostmap(world);
  LocalPlanner lp(diffParams());
  lp.setPlan(straightPlan({4.0, 2.0, M_PI}, 0.05, 60));
  const LocalResult r = lp.computeVelocity(cm, {4.0, 2.0, 0.0}, {});
  ASSERT_EQ(r.status, LocalStatus::Moving);
  EXPECT_EQ(r.cmd.vx, 0.0);
  EXPECT_GE(std::abs(r.cmd.wz), 0.3);
}

TEST(LocalPlanner, StopsThenRotatesAtTheGoalAndReportsReached)
{
  const GridMap world = makeWorld(8.0, 4.0, 0.05, {});
  const Costmap cm = staticCostmap(world);
  LocalPlanner lp(diffParams());
  lp.setPlan({{3.0, 2.0, 0.0}, {3.05, 2.0, 1.0}});
  // Still moving inside the tolerance: brake first.
  LocalResult r = lp.computeVelocity(cm, {3.0, 2.0, 0.0}, {0.4, 0, 0});
  EXPECT_EQ(r.status, LocalStatus::RotatingToGoal);
  EXPECT_LT(r.cmd.vx, 0.4);
  EXPECT_EQ(r.cmd.wz, 0.0);
  // Stopped: turn towards +1 rad.
  r = lp.computeVelocity(cm, {3.0, 2.0, 0.0}, {});
  EXPECT_EQ(r.status, LocalStatus::RotatingToGoal);
  EXPECT_GT(r.cmd.wz, 0.0);
  r = lp.computeVelocity(cm, {3.0, 2.0, 0.95}, {});
  EXPECT_EQ(r.status, LocalStatus::GoalReached);
  EXPECT_EQ(r.cmd.wz, 0.0);
}

TEST(LocalPlanner, RejectsTrajectoriesIntoObstacles)
{
  const GridMap world = makeWorld(8.0, 4.0, 0.05, {{2.0, 0.0, 2.2, 4.0}});
  const Costmap cm = staticCostmap(world);
  LocalPlanner lp(diffParams());
  lp.setPlan(straightPlan({1.5, 2.0, 0.0}, 0.05, 60));
  // Facing the wall 0.3 m away: only slow trajectories that stop short of it are admissible.
  const LocalResult r = lp.computeVelocity(cm, {1.7, 2.0, 0.0}, {0.0, 0, 0});
  EXPECT_LT(r.cmd.vx, 0.1);
  for (const Pose2D& p : r.trajectory)
    EXPECT_GE(cm.footprintCost(p), 0.0);
}

TEST(LocalPlanner, GetsOutWhenTheFootprintAlreadyTouchesAnObstacle)
{
  // Localization put the front edge 5 cm into a wall; the path leads back the other way. Every
  // trajectory starts in collision, so without an escape the robot would sit until the goal
  // aborted ("failed to find a valid control").
  const GridMap world = makeWorld(8.0, 4.0, 0.05, {{2.0, 0.0, 2.2, 4.0}});
  const Costmap cm = staticCostmap(world, true);
  const Pose2D pose{1.75, 2.0, 0.0};
  ASSERT_LT(cm.footprintCost(pose), 0.0);
  LocalPlanner lp(diffParams());
  lp.setPlan(straightPlan({1.75, 2.0, 0.0}, -0.05, 20));
  const LocalResult r = lp.computeVelocity(cm, pose, {});
  ASSERT_EQ(r.status, LocalStatus::Moving);
  ASSERT_FALSE(r.trajectory.empty());
  EXPECT_GE(cm.footprintCost(r.trajectory.back()), 0.0);
  EXPECT_LT(r.trajectory.back().x, pose.x);  // away from the wall

  // The same contact with a thin wall and the path beyond it: driving through is no escape.
  const GridMap thin = makeWorld(8.0, 4.0, 0.05, {{2.0, 0.0, 2.05, 4.0}});
  const Costmap cm2 = staticCostmap(thin, true);
  ASSERT_LT(cm2.footprintCost(pose), 0.0);
  LocalPlanner lp2(diffParams());
  lp2.setPlan(straightPlan({1.75, 2.0, 0.0}, 0.05, 40));
  const LocalResult r2 = lp2.computeVelocity(cm2, pose, {0.3, 0, 0});
  for (const Pose2D& p : r2.trajectory)
    EXPECT_LT(p.x, 1.9) << "trajectory tunnels through the wall";
}

TEST(LocalPlanner, BrakesOutOfACommittedTurnInsteadOfGivingUp)
{
  // Turning right fast next to a box on the right: every velocity the dynamic window can
  // reach keeps swinging the footprint into the box. DWA would find nothing; the robot must
  // still get a command that leads somewhere safe (straight on, or turning left).
  const GridMap world = makeWorld(8.0, 4.0, 0.05, {{1.0, 1.0, 2.0, 1.66}});
  const Costmap cm = staticCostmap(world, true);
  const Pose2D pose{1.5, 2.0, 0.0};
  ASSERT_GE(cm.footprintCost(pose), 0.0);
  LocalPlanner lp(diffParams());
  lp.setPlan(straightPlan(pose, 0.05, 60));
  const LocalResult r = lp.computeVelocity(cm, pose, {0.0, 0, -1.5});
  ASSERT_EQ(r.status, LocalStatus::Moving);
  EXPECT_GT(r.cmd.wz, -1.0);
  for (const Pose2D& p : r.trajectory)
    EXPECT_GE(cm.footprintCost(p), 0.0);
}

TEST(LocalPlanner, HolonomicRobotStrafesToASidewaysGoal)
{
  const GridMap world = makeWorld(8.0, 4.0, 0.05, {});
  const Costmap cm = staticCostmap(world, true);
  LocalPlanner lp(holonomicParams());
  std::vector<Pose2D> plan = straightPlan({4.0, 1.5, M_PI / 2}, 0.05, 20);
  for (Pose2D& p : plan)
    p.theta = 0.0;  // keep the heading: the goal is to the robot's left
  lp.setPlan(plan);
  const LocalResult r = lp.computeVelocity(cm, {4.0, 1.5, 0.0}, {});
  ASSERT_EQ(r.status, LocalStatus::Moving);
  EXPECT_GT(r.cmd.vy, 0.1);
}

TEST(LocalPlanner, HolonomicAlignScaleTurnsTheRobotAlongALongPath)
{
  const GridMap world = makeWorld(8.0, 8.0, 0.05, {});
  const Costmap cm = staticCostmap(world, true);
  // A long path to the robot's left, or to its right: with half the alignment cost it moves
  // towards the path at once (strafing) and turns to face along it.
  LocalPlannerParams p = holonomicParams();
  p.holonomic_align_scale = 0.5;
  for (double side : {1.0, -1.0})
  {
    LocalPlanner lp(p);
    lp.setPlan(straightPlan({4.0, 4.0 - 3.0 * side, side * M_PI / 2}, 0.05, 100));
    const LocalResult r = lp.computeVelocity(cm, {4.0, 4.0 - 3.0 * side, 0.0}, {});
    ASSERT_EQ(r.status, LocalStatus::Moving) << "side " << side;
    EXPECT_GT(side * r.cmd.vy, 0.1) << "side " << side;
    EXPECT_GT(side * r.cmd.wz, 0.2) << "side " << side;
  }
  LocalPlannerParams bad = holonomicParams();
  bad.holonomic_align_scale = 1.5;
  EXPECT_NE(validate(bad).find("holonomic_align_scale"), std::string::npos);
}

TEST(Navigator, DiffDriveReachesGoalsInTheOffice)
{
  NavStack st(officeWorld(0.05), diffParams(), false,
              []
              {
                NavigatorParams np;
                np.planner_frequency = 1.0;
                return np;
              }());
  Pose2D pose{1.5, 1.5, 0.0};
  const std::vector<Pose2D> goals{{5.0, 3.0, M_PI / 2}, {9.0, 6.0, 0.0}, {3.0, 8.8, -M_PI / 2}, {1.5, 1.5, M_PI}};
  for (const Pose2D& goal : goals)
  {
    const ClosedLoopResult r = runToGoal(st, pose, goal, 120.0);
    ASSERT_EQ(r.state, NavState::Succeeded) << "goal " << goal.x << "," << goal.y << ": " << r.message << " at "
                                            << r.final_pose.x << "," << r.final_pose.y << " t=" << r.time;
    EXPECT_LT(std::hypot(r.final_pose.x - goal.x, r.final_pose.y - goal.y), 0.1 + 0.05);
    EXPECT_LT(std::abs(wrapAngle(r.final_pose.theta - goal.theta)), 0.1 + 0.05);
    EXPECT_GT(r.min_clearance, 0.2);  // the robot's radius: never touched a wall
    EXPECT_EQ(r.max_abs_vy, 0.0);
    pose = r.final_pose;
  }
}

TEST(Navigator, HolonomicRobotUsesSidewaysMotion)
{
  NavStack st(officeWorld(0.05), holonomicParams(), true);
  // Goal 1.5 m to the robot's left with the same heading.
  const ClosedLoopResult r = runToGoal(st, {3.0, 2.5, 0.0}, {3.0, 4.0, 0.0}, 60.0);
  ASSERT_EQ(r.state, NavState::Succeeded)
      << r.message << " at " << r.final_pose.x << "," << r.final_pose.y << "," << r.final_pose.theta << " t=" << r.time;
  EXPECT_GT(r.max_abs_vy, 0.2);
  EXPECT_LT(r.distance, 1.5 * 1.25);
}

TEST(Navigator, GoalInObstacleOrOffMapAbortsWithAReason)
{
  NavStack st(officeWorld(0.05), diffParams(), false);
  std::string reason = st.nav.setGoal({2.0, 7.5, 0.0}, 0.0, {1.5, 1.5, 0.0});  // inside the table
  EXPECT_EQ(st.nav.state(), NavState::Aborted);
  EXPECT_NE(reason.find("obstacle"), std::string::npos);
  reason = st.nav.setGoal({30.0, 2.0, 0.0}, 0.0, {1.5, 1.5, 0.0});
  EXPECT_EQ(st.nav.state(), NavState::Aborted);
  EXPECT_NE(reason.find("outside the map"), std::string::npos);
  EXPECT_EQ(st.nav.step(0.1, {1.5, 1.5, 0.0}, {}).cmd.vx, 0.0);
}

TEST(Navigator, UnreachableGoalRunsRecoveriesThenAborts)
{
  // A closed box around the goal: the plan fails, recoveries run, then abort with a reason.
  NavStack st(makeWorld(8.0, 6.0, 0.05,
                        {{5.0, 2.0, 7.0, 2.1}, {5.0, 4.0, 7.0, 4.1}, {5.0, 2.0, 5.1, 4.1}, {6.9, 2.0, 7.0, 4.1}}),
              diffParams(), false,
              []
              {
                NavigatorParams np;
                np.planner_patience = 2.0;
                return np;
              }());
  const ClosedLoopResult r = runToGoal(st, {2.0, 3.0, 0.0}, {6.0, 3.0, 0.0}, 120.0);
  EXPECT_EQ(r.state, NavState::Aborted);
  EXPECT_NE(r.message.find("valid plan"), std::string::npos);
  EXPECT_EQ(st.nav.recoveriesRun(), 4);
}

TEST(Navigator, CancelStopsTheRobot)
{
  NavStack st(officeWorld(0.05), diffParams(), false);
  const ClosedLoopResult r = runToGoal(st, {1.5, 1.5, 0.0}, {5.0, 1.5, 0.0}, 30.0, 2.0);
  EXPECT_EQ(r.state, NavState::Idle);
  EXPECT_LT(r.time, 2.5);
  EXPECT_GT(r.distance, 0.1);
  const NavOutput out = st.nav.step(10.0, r.final_pose, {});
  EXPECT_EQ(out.cmd.vx, 0.0);
  EXPECT_EQ(out.cmd.wz, 0.0);
}

TEST(LocalPlanner, DrivesOffAShelfItsSideGrazes)
{
  // The robot's side overlaps a shelf face by 1 cm (a costmap update after it stopped there),
  // the path runs on along the shelf. Getting clear takes more than 0.15 m of driving and
  // turning: seen in the factory demo, where the robot sat for 500 s of aborted goals.
  const GridMap world = makeWorld(8.0, 4.0, 0.05, {{0.0, 1.0, 8.0, 1.5}});
  const Costmap cm = staticCostmap(world, true);
  const Pose2D pose{2.0, 1.74, 0.0};
  ASSERT_LT(cm.footprintCost(pose), 0.0);
  LocalPlanner lp(diffParams());
  Pose2D p = pose;
  Velocity2D vel;
  bool came_free = false;
  for (int step = 0; step < 40 && !came_free; ++step)
  {
    lp.setPlan(straightPlan({p.x, 2.2, 0.0}, 0.05, 60));
    const LocalResult r = lp.computeVelocity(cm, p, vel);
    ASSERT_EQ(r.status, LocalStatus::Moving) << "step " << step;
    vel = r.cmd;
    p = compose(p, {vel.vx * 0.1, vel.vy * 0.1, vel.wz * 0.1});
    EXPECT_GT(p.y, 1.6) << "the robot went into the shelf";
    came_free = cm.footprintCost(p) >= 0.0;
  }
  EXPECT_TRUE(came_free);
}

TEST(Navigator, MybotLeavesAShelfEndItRoundedTightly)
{
  // The factory demo's stall (twice on 2026-11-25): mybot came round the end of a shelf with the
  // corner 0.26 m from its centre, about 2 cm outside its padded footprint, and from then on
  // every goal ended in "failed to find a valid control" while it stood still. mybot's configs:
  // the 0.46 x 0.36 m footprint with 0.04 m padding, inflation 0.5 m, and its DWA parameters.
  CostmapParams cp;
  cp.footprint = {{0.25, 0.18}, {0.25, -0.18}, {-0.21, -0.18}, {-0.21, 0.18}};
  cp.footprint_padding = 0.04;
  cp.inflation_radius = 0.5;
  cp.cost_scaling_factor = 5.0;
  cp.width = cp.height = 4.0;
  LocalPlannerParams lp = diffParams();
  lp.acc_lim_x = 1.0;
  lp.acc_lim_theta = 2.5;
  lp.vx_samples = 10;
  lp.path_distance_bias = 32.0;
  lp.goal_distance_bias = 24.0;
  lp.occdist_scale = 0.02;
  lp.forward_point_distance = 0.325;
  NavigatorParams np;
  np.planner_frequency = 1.0;
  np.planner_patience = 5.0;
  np.controller_patience = 8.0;
  np.oscillation_timeout = 15.0;
  np.oscillation_distance = 0.2;
  // Shelves 5 and 6 of factory.world, shifted by (+4, +1): the gap between them is x 4..5.
  const GridMap world = makeWorld(10.0, 4.0, 0.05, {{0.0, 2.1, 4.0, 2.9}, {5.0, 2.1, 9.0, 2.9}});
  for (const double dx : {0.0, 0.02, -0.02})
  {
    NavStack st(world, lp, cp, np);
    const Pose2D start{4.26 + dx, 2.17, -1.75};
    const Pose2D goal{3.38, 1.68, -2.5};
    const ClosedLoopResult r = runToGoal(st, start, goal, 120.0);
    EXPECT_EQ(r.state, NavState::Succeeded)
        << "dx " << dx << ": " << r.message << " at " << r.final_pose.x << "," << r.final_pose.y << " t=" << r.time;
  }
}
