#include <gtest/gtest.h>

#include "mybot_slam/occupancy_grid.h"

using namespace mybot_navigation;

namespace
{
RangeScan singleBeam(double range)
{
  RangeScan s;
  s.hits.push_back({range, 0.0});
  return s;
}
}  // namespace

TEST(OccupancyGrid, BeamMarksFreeThenOccupied)
{
  OccupancyGrid g;
  g.insertScan({0.02, 0.02, 0.0}, singleBeam(1.0));
  const int y = g.worldToLattice(0.02);
  for (int x = g.worldToLattice(0.02); x < g.worldToLattice(1.02); ++x)
    EXPECT_LT(g.probability(x, y), 0.5) << x;
  EXPECT_GT(g.probability(g.worldToLattice(1.02), y), 0.5);
  EXPECT_FALSE(g.observed(g.worldToLattice(0.02), g.worldToLattice(1.0)));
  const GridMap m = g.toGridMap();
  int cx, cy;
  ASSERT_TRUE(m.worldToCell(1.02, 0.02, cx, cy));
  EXPECT_EQ(m.at(cx, cy), 100);
  ASSERT_TRUE(m.worldToCell(0.5, 0.02, cx, cy));
  EXPECT_EQ(m.at(cx, cy), 0);
  ASSERT_TRUE(m.worldToCell(0.5, 1.0, cx, cy));
  EXPECT_EQ(m.at(cx, cy), -1);
}

TEST(OccupancyGrid, GrowsInEveryDirectionAndKeepsContent)
{
  OccupancyGrid g;
  g.insertScan({0.0, 0.0, 0.0}, singleBeam(1.0));
  const int hx = g.worldToLattice(1.0), hy = g.worldToLattice(0.0);
  const float before = g.logOdds(hx, hy);
  for (double a : {M_PI / 2, M_PI, -M_PI / 2})
    g.insertScan({0.0, 0.0, a}, singleBeam(20.0));
  EXPECT_FLOAT_EQ(g.logOdds(hx, hy), before);
  EXPECT_TRUE(g.contains(g.worldToLattice(-20.0), g.worldToLattice(0.0)));
  EXPECT_TRUE(g.contains(g.worldToLattice(0.0), g.worldToLattice(20.0)));
  EXPECT_TRUE(g.contains(g.worldToLattice(0.0), g.worldToLattice(-20.0)));
  EXPECT_GT(g.probability(g.worldToLattice(-20.0), g.worldToLattice(0.0)), 0.5);
}

TEST(OccupancyGrid, RepeatedMissesClearAnObstacleWithinClampLimits)
{
  OccupancyGrid g;
  for (int i = 0; i < 50; ++i)
    g.insertScan({0, 0, 0}, singleBeam(1.0));  // saturate at prob_max
  RangeScan through;
  through.hits.push_back({2.0, 0.0});
  int scans = 0;
  const int hx = g.worldToLattice(1.0), hy = g.worldToLattice(0.0);
  while (g.probability(hx, hy) > 0.5 && scans < 100)
  {
    g.insertScan({0, 0, 0}, through);
    ++scans;
  }
  EXPECT_LT(scans, 15);  // clamping keeps the map responsive to change
}

TEST(OccupancyGrid, CellUpdatedOncePerScan)
{
  // Many beams through the same cell near the sensor must count as one observation.
  OccupancyGrid g;
  RangeScan fan;
  for (int i = 0; i < 100; ++i)
    fan.hits.push_back({2.0 * std::cos(i * 0.01), 2.0 * std::sin(i * 0.01)});
  g.insertScan({0, 0, 0}, fan);
  EXPECT_NEAR(g.probability(g.worldToLattice(0.07), g.worldToLattice(0.0)), 0.4, 1e-6);
}
