// The global planner: A* and Dijkstra, smoothing, blocked goals, escaping an inflated start.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "mybot_move_base/costmap.h"
#include "mybot_move_base/planner.h"
#include "costmap_test_util.h"
#include "synthetic_world.h"

using namespace mybot_navigation;
using namespace mybot_navigation::costmap_test;

TEST(GlobalPlanner, AStarAndDijkstraFindEqualCostPathsAroundAWall)
{
  const GridMap m = makeWorld(8.0, 6.0, 0.05, {{3.9, 0.0, 4.1, 4.5}});
  Costmap cm(circleParams());
  cm.setStaticMap(m);
  cm.updateCosts();
  PlannerParams pp;
  pp.use_dijkstra = false;
  const PlanResult a = GlobalPlanner(pp).makePlan(cm, {1.0, 1.0, 0.0}, {7.0, 1.0, 1.0});
  pp.use_dijkstra = true;
  const PlanResult d = GlobalPlanner(pp).makePlan(cm, {1.0, 1.0, 0.0}, {7.0, 1.0, 1.0});
  ASSERT_EQ(a.status, PlanStatus::Ok);
  ASSERT_EQ(d.status, PlanStatus::Ok);
  EXPECT_NEAR(a.length, d.length, 0.1 * d.length);
  EXPECT_LT(a.expanded, d.expanded);  // the heuristic pays off
  // Goes over the wall's end (y > 4.5) and ends exactly at the goal pose.
  double max_y = 0;
  for (const Pose2D& p : a.path)
  {
    max_y = std::max(max_y, p.y);
    EXPECT_LT(cm.costAt(p.x, p.y), costs::kInscribed);
  }
  EXPECT_GT(max_y, 4.5);
  EXPECT_NEAR(a.path.back().x, 7.0, 1e-9);
  EXPECT_NEAR(a.path.back().theta, 1.0, 1e-9);
  EXPECT_NEAR(a.path.front().x, 1.0, 1e-9);
  // Spacing about one cell, so the controller can follow it.
  for (size_t i = 1; i < a.path.size(); ++i)
    EXPECT_LE(std::hypot(a.path[i].x - a.path[i - 1].x, a.path[i].y - a.path[i - 1].y), 0.0501);
  // Lower bound: the straight lines via the wall's corner.
  EXPECT_GT(a.length, std::hypot(3.0, 3.5) * 2);
  EXPECT_LT(a.length, 1.25 * std::hypot(3.0, 3.5) * 2);
}

TEST(GlobalPlanner, SmoothingShortensOpenSpacePaths)
{
  Costmap cm(circleParams());
  cm.setStaticMap(emptyRoom());
  cm.updateCosts();
  PlannerParams pp;
  pp.smooth_path = false;
  const PlanResult raw = GlobalPlanner(pp).makePlan(cm, {1.0, 1.0, 0.0}, {5.0, 2.9, 0.0});
  pp.smooth_path = true;
  const PlanResult smooth = GlobalPlanner(pp).makePlan(cm, {1.0, 1.0, 0.0}, {5.0, 2.9, 0.0});
  ASSERT_EQ(smooth.status, PlanStatus::Ok);
  EXPECT_LT(smooth.length, raw.length);
  EXPECT_NEAR(smooth.length, std::hypot(4.0, 1.9), 0.02);
}

TEST(GlobalPlanner, ReportsBlockedAndUnreachableGoals)
{
  const GridMap m = makeWorld(8.0, 6.0, 0.05, {{3.9, 0.0, 4.1, 6.0}, {1.5, 2.5, 2.5, 3.5}});
  Costmap cm(circleParams());
  cm.setStaticMap(m);
  cm.updateCosts();
  GlobalPlanner planner;
  EXPECT_EQ(planner.makePlan(cm, {1, 1, 0}, {2.0, 3.0, 0}).status, PlanStatus::GoalInObstacle);
  EXPECT_EQ(planner.makePlan(cm, {1, 1, 0}, {20.0, 3.0, 0}).status, PlanStatus::GoalOffMap);
  EXPECT_EQ(planner.makePlan(cm, {-1, 1, 0}, {2.0, 1.0, 0}).status, PlanStatus::StartOffMap);
  EXPECT_EQ(planner.makePlan(cm, {1, 1, 0}, {6.0, 3.0, 0}).status, PlanStatus::NoPath);
  // default_tolerance moves a blocked goal to the nearest free cell.
  PlannerParams pp;
  pp.default_tolerance = 1.0;
  const PlanResult r = GlobalPlanner(pp).makePlan(cm, {1, 1, 0}, {2.0, 3.0, 0});
  ASSERT_EQ(r.status, PlanStatus::Ok);
  EXPECT_LT(cm.costAt(r.path.back().x, r.path.back().y), costs::kInscribed);
}

TEST(GlobalPlanner, EscapesFromInflatedStart)
{
  Costmap cm(circleParams());
  cm.setStaticMap(emptyRoom());
  cm.updateCosts();
  ASSERT_EQ(cm.costAt(0.21, 2.0), costs::kInscribed);
  const PlanResult r = GlobalPlanner().makePlan(cm, {0.21, 2.0, 0}, {3.0, 2.0, 0});
  EXPECT_EQ(r.status, PlanStatus::Ok);
}
