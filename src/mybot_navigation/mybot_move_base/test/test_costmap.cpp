// Costmap layers (static, obstacle, inflation, rolling window) and the footprint check.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "mybot_move_base/costmap.h"
#include "costmap_test_util.h"
#include "synthetic_world.h"

using namespace mybot_navigation;
using namespace mybot_navigation::costmap_test;

TEST(Costmap, ValidateNamesTheParameter)
{
  CostmapParams p;
  EXPECT_EQ(validate(p), "");
  p.inflation_radius = -1;
  EXPECT_NE(validate(p).find("inflation_radius"), std::string::npos);
  p = CostmapParams();
  p.footprint = {{0, 0}, {1, 1}};
  EXPECT_NE(validate(p).find("footprint"), std::string::npos);
}

TEST(Costmap, FootprintRadii)
{
  CostmapParams p;
  p.footprint = {{0.3, 0.25}, {0.3, -0.25}, {-0.3, -0.25}, {-0.3, 0.25}};
  p.footprint_padding = 0.0;
  Costmap cm(p);
  EXPECT_NEAR(cm.inscribedRadius(), 0.25, 1e-9);
  EXPECT_NEAR(cm.circumscribedRadius(), std::hypot(0.3, 0.25), 1e-9);
  p.footprint_padding = 0.01;
  EXPECT_NEAR(inscribedRadius(paddedFootprint(p)), 0.26, 1e-9);
}

TEST(Costmap, InflationUsesCostmap2dValues)
{
  Costmap cm(circleParams(0.2));
  EXPECT_EQ(cm.inflationCost(0.0), costs::kLethal);
  EXPECT_EQ(cm.inflationCost(0.15), costs::kInscribed);
  EXPECT_EQ(cm.inflationCost(0.3), static_cast<uint8_t>(252 * std::exp(-10.0 * (0.3 - cm.inscribedRadius()))));
  EXPECT_EQ(cm.inflationCost(0.6), costs::kFree);
}

TEST(Costmap, StaticLayerIsInflatedAroundWalls)
{
  Costmap cm(circleParams(0.2));
  cm.setStaticMap(emptyRoom());
  cm.updateCosts();
  EXPECT_EQ(cm.costAt(0.05, 2.0), costs::kLethal);      // wall
  EXPECT_EQ(cm.costAt(0.225, 2.0), costs::kInscribed);  // 0.15 m from the wall face
  const uint8_t mid = cm.costAt(0.425, 2.0);            // ~0.35 m away
  EXPECT_GT(mid, 0);
  EXPECT_LT(mid, costs::kInscribed);
  EXPECT_EQ(cm.costAt(3.0, 2.0), costs::kFree);
  EXPECT_EQ(cm.costAt(-1.0, 2.0), costs::kNoInformation);  // off the grid
  // Unknown map cells: free unless track_unknown_space.
  GridMap m = emptyRoom();
  m.at(60, 40) = GridMap::kUnknown;
  Costmap a(circleParams()), b(
                                 []
                                 {
                                   CostmapParams p = circleParams();
                                   p.track_unknown_space = true;
                                   return p;
                                 }());
  a.setStaticMap(m);
  b.setStaticMap(m);
  a.updateCosts();
  b.updateCosts();
  EXPECT_EQ(a.cost(60, 40), costs::kFree);
  EXPECT_EQ(b.cost(60, 40), costs::kNoInformation);
}

TEST(Costmap, ObstacleLayerMarksAndClears)
{
  CostmapParams p = circleParams();
  Costmap cm(p);
  cm.setStaticMap(emptyRoom());
  cm.updateCosts();
  // A box seen at 1.5 m, then gone: a max-range beam through it clears it.
  cm.updateWithScan({1.0, 2.0}, {{2.5, 2.0}}, {});
  cm.updateCosts();
  EXPECT_EQ(cm.costAt(2.5, 2.0), costs::kLethal);
  EXPECT_EQ(cm.costAt(2.35, 2.0), costs::kInscribed);
  // Beyond obstacle_range (2.5 m): not marked.
  cm.updateWithScan({1.0, 2.0}, {{4.0, 2.5}}, {});
  cm.updateCosts();
  EXPECT_EQ(cm.costAt(4.0, 2.5), costs::kFree);
  cm.updateWithScan({1.0, 2.0}, {}, {{5.0, 2.0}});
  cm.updateCosts();
  EXPECT_EQ(cm.costAt(2.5, 2.0), costs::kFree);
  // A hit further along the same beam clears the cells in front of it.
  cm.updateWithScan({1.0, 2.0}, {{2.0, 2.0}}, {});
  cm.updateWithScan({1.0, 2.0}, {{3.0, 2.0}}, {});
  cm.updateCosts();
  EXPECT_EQ(cm.costAt(2.0, 2.0), costs::kFree);
  EXPECT_EQ(cm.costAt(3.0, 2.0), costs::kLethal);
  // Static walls survive clearing and resets.
  cm.updateWithScan({1.0, 2.0}, {}, {{-1.0, 2.0}});
  cm.reset();
  cm.updateCosts();
  EXPECT_EQ(cm.costAt(0.05, 2.0), costs::kLethal);
  EXPECT_EQ(cm.costAt(3.0, 2.0), costs::kFree);
}

TEST(Costmap, MarksUnderTheRobotAreClearedNotTheStaticMap)
{
  // costmap_2d's footprint_clearing_enabled. The robot (0.6 x 0.5 m, padded 0.04 m) stands at
  // (0.42, 2.0) with its rear padding over the room's west wall (static); a mark under its side
  // padding is stale (it could not be standing there otherwise), one beside it is not.
  CostmapParams p;
  p.footprint = {{0.3, 0.25}, {0.3, -0.25}, {-0.3, -0.25}, {-0.3, 0.25}};
  p.footprint_padding = 0.04;
  const Pose2D robot{0.42, 2.0, 0.0};
  for (const bool enabled : {true, false})
  {
    p.footprint_clearing_enabled = enabled;
    Costmap cm(p);
    cm.setStaticMap(emptyRoom());
    cm.updateWithScan({0.5, 2.0}, {{0.5, 2.27}, {0.5, 2.4}}, {});
    cm.clearFootprint(robot);
    cm.updateCosts();
    EXPECT_EQ(cm.costAt(0.5, 2.27) == costs::kLethal, !enabled) << (enabled ? "enabled" : "disabled");
    EXPECT_EQ(cm.costAt(0.5, 2.4), costs::kLethal);
    EXPECT_EQ(cm.costAt(0.02, 2.0), costs::kLethal);  // the wall under the rear padding
  }
}

TEST(Costmap, ConservativeResetKeepsNearbyObstacles)
{
  Costmap cm(circleParams());
  cm.setStaticMap(emptyRoom());
  cm.updateWithScan({1.0, 2.0}, {{1.5, 2.0}, {3.4, 2.0}}, {});
  cm.clearObstaclesOutside(1.0, 2.0, 1.0);
  cm.updateCosts();
  EXPECT_EQ(cm.costAt(1.5, 2.0), costs::kLethal);
  EXPECT_EQ(cm.costAt(3.4, 2.0), costs::kFree);
}

TEST(Costmap, RollingWindowFollowsTheRobotAndKeepsObstacles)
{
  CostmapParams p = circleParams();
  p.rolling_window = true;
  p.width = p.height = 2.0;
  Costmap cm(p);
  cm.setStaticMap(emptyRoom());
  cm.updateOrigin(1.0, 2.0);
  cm.updateWithScan({1.0, 2.0}, {{1.62, 2.02}}, {});
  cm.updateCosts();
  EXPECT_EQ(cm.costAt(1.62, 2.02), costs::kLethal);
  EXPECT_EQ(cm.costAt(0.05, 2.0), costs::kLethal);  // static wall inside the window
  cm.updateOrigin(1.5, 2.2);
  cm.updateCosts();
  EXPECT_EQ(cm.costAt(1.62, 2.02), costs::kLethal);
  EXPECT_EQ(cm.costAt(0.3, 2.0), costs::kNoInformation);  // now outside the 2 m window
  EXPECT_EQ(cm.width(), 40);
}

TEST(Costmap, FootprintCostDetectsCollisions)
{
  CostmapParams p;
  p.footprint = {{0.3, 0.25}, {0.3, -0.25}, {-0.3, -0.25}, {-0.3, 0.25}};
  p.footprint_padding = 0.0;
  Costmap cm(p);
  cm.setStaticMap(emptyRoom());
  cm.updateCosts();
  EXPECT_GE(cm.footprintCost({3.0, 2.0, 0.0}), 0.0);
  EXPECT_LT(cm.footprintCost({0.35, 2.0, 0.0}), 0.0);       // rear edge in the wall
  EXPECT_GE(cm.footprintCost({0.37, 2.0, M_PI / 2}), 0.0);  // turned: 0.25 m half width fits
  EXPECT_EQ(cm.footprintCost({-3.0, 2.0, 0.0}), -3.0);
}

TEST(Costmap, FootprintEdgeClippingAnObstacleCornerIsAHit)
{
  // One lethal cell [3.0, 3.05) x [2.0, 2.05). The triangle's long edge (x + y = 5.099) cuts
  // 1.4 mm of the cell's corner: every cell an edge passes through counts, however little of it
  // (sampling the edge every quarter cell stepped over this one).
  Costmap cm(circleParams());
  cm.setStaticMap(makeWorld(6.0, 4.0, 0.05, {{3.0, 2.0, 3.05, 2.05}}));
  cm.updateCosts();
  const Pose2D pose{3.1, 2.1, 0.0};
  auto triangle = [&](double sum)
  {
    // World corners (2.9, sum - 2.9), (3.2, sum - 3.2), (3.2, 2.199), in the robot frame.
    return std::vector<Point2D>{
        {2.9 - pose.x, sum - 2.9 - pose.y}, {3.2 - pose.x, sum - 3.2 - pose.y}, {3.2 - pose.x, 2.199 - pose.y}};
  };
  EXPECT_EQ(cm.polygonCost(pose, triangle(5.099)), -1.0);
  EXPECT_GE(cm.polygonCost(pose, triangle(5.101)), 0.0);  // 1 mm clear of the corner
}

TEST(Costmap, OccupancyTranslationTable)
{
  Costmap cm(circleParams());
  cm.setStaticMap(emptyRoom());
  cm.updateCosts();
  const std::vector<int8_t> v = cm.toOccupancyValues();
  int x, y;
  cm.worldToMap(0.05, 2.0, x, y);
  EXPECT_EQ(v[y * cm.width() + x], 100);
  cm.worldToMap(3.0, 2.0, x, y);
  EXPECT_EQ(v[y * cm.width() + x], 0);
  cm.worldToMap(0.225, 2.0, x, y);
  EXPECT_EQ(v[y * cm.width() + x], 99);
}
