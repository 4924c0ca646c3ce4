#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "mybot_nav_common/range_scan.h"
#include "mybot_nav_common/ray_cast.h"
#include "synthetic_world.h"

using namespace mybot_navigation;

TEST(RayCast, ExactDistanceToWall)
{
  // 10 x 10 m room, walls 0.1 m thick: from (5,5) facing +x the wall face is at x = 9.9.
  const GridMap world = makeWorld(10.0, 10.0, 0.01, {});
  EXPECT_NEAR(castRay(world, 5.0, 5.0, 0.0, 30.0), 4.9, 1e-6);
  EXPECT_NEAR(castRay(world, 5.0, 5.0, M_PI, 30.0), 4.9, 1e-6);
  EXPECT_NEAR(castRay(world, 5.0, 5.0, M_PI / 4, 30.0), 4.9 * std::sqrt(2.0), 0.02);
  EXPECT_DOUBLE_EQ(castRay(world, 5.0, 5.0, 0.0, 2.0), 2.0);  // max range when nothing is hit
}

TEST(RayCast, LineVisitsEndpointsInOrder)
{
  std::vector<std::pair<int, int>> cells;
  traceLine(0, 0, 5, 2,
            [&](int x, int y)
            {
              cells.emplace_back(x, y);
              return true;
            });
  ASSERT_EQ(cells.size(), 6u);
  EXPECT_EQ(cells.front(), std::make_pair(0, 0));
  EXPECT_EQ(cells.back(), std::make_pair(5, 2));
}

TEST(RayCast, SegmentVisitsEveryCellItCrosses)
{
  // y = 1 is crossed at x = 0.6: cell (0, 1) is on the segment, though a line from cell (0, 0) to
  // cell (1, 1) skips it; both directions give the same cells, in order.
  const std::vector<std::pair<int, int>> expected{{0, 0}, {0, 1}, {1, 1}};
  std::vector<std::pair<int, int>> cells;
  traceSegment(0.2, 0.95, 1.8, 1.15,
               [&](int x, int y)
               {
                 cells.emplace_back(x, y);
                 return true;
               });
  EXPECT_EQ(cells, expected);
  cells.clear();
  traceSegment(1.8, 1.15, 0.2, 0.95,
               [&](int x, int y)
               {
                 cells.emplace_back(x, y);
                 return true;
               });
  const std::vector<std::pair<int, int>> reversed(expected.rbegin(), expected.rend());
  EXPECT_EQ(cells, reversed);
}

TEST(RangeScan, InvalidReadingsAreClassified)
{
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const std::vector<float> ranges{1.0f, nan, inf, -inf, 0.01f, 35.0f, 12.0f};
  ScanGeometry g;
  g.sensor_in_base = {0.1, 0.0, 0.0};
  ScanConversionStats st;
  const RangeScan s = convertRanges(ranges, 0.0, 0.1, 0.1, 30.0, 10.0, g, &st);
  EXPECT_EQ(st.hits, 1);
  EXPECT_EQ(st.invalid, 3);    // NaN, -inf, below range_min
  EXPECT_EQ(st.no_return, 2);  // +inf, >= range_max
  EXPECT_EQ(st.clipped, 1);    // 12 m > max usable 10 m
  ASSERT_EQ(s.hits.size(), 1u);
  EXPECT_NEAR(s.hits[0].x, 1.1, 1e-9);
  EXPECT_EQ(s.misses.size(), 3u);
  for (const Point2D& m : s.misses)
    EXPECT_NEAR(std::hypot(m.x - 0.1, m.y), 10.0, 1e-6);
}

TEST(RangeScan, UpsideDownSensorMirrorsAngles)
{
  ScanGeometry g;
  g.upside_down = true;
  const RangeScan s = convertRanges({1.0f}, M_PI / 2, 0.0, 0.1, 30.0, 30.0, g);
  ASSERT_EQ(s.hits.size(), 1u);
  EXPECT_NEAR(s.hits[0].y, -1.0, 1e-9);
}
