// Ray casting: exact distances, lines and segments through the grid.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

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
