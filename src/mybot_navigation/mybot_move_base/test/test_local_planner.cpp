// The DWA local planner: sampling, rotation to the path and the goal, escapes, oscillation,
// on a kinematic robot in a synthetic world.
#include <gtest/gtest.h>

#include <cmath>

#include "nav_test_util.h"

using namespace mybot_navigation;
using namespace mybot_navigation::nav_test;

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
