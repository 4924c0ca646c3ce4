// Ray casting: exact distances, lines and segments through the grid.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

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

// A reading that is finite but absurd (1e30 m, under a range_max of inf) makes a point 2e31 cells
// away; its cell was an out-of-range conversion to int. It is held 2^28 cells out, and NaN is too.
TEST(RayCast, CellIndexOfAnAbsurdPointIsFarOffTheGrid)
{
  constexpr int kFar = 1 << 28;
  EXPECT_EQ(cellIndex(2.5), 2);
  EXPECT_EQ(cellIndex(-0.5), -1);
  EXPECT_EQ(cellIndex(2e31), kFar);
  EXPECT_EQ(cellIndex(-2e31), -kFar);
  EXPECT_EQ(cellIndex(std::numeric_limits<double>::infinity()), kFar);
  EXPECT_EQ(cellIndex(std::numeric_limits<double>::quiet_NaN()), -kFar);
  int cx = 0, cy = 0;
  const GridMap map(MapInfo{0.05, 10, 10, {}}, GridMap::kFree);
  EXPECT_FALSE(map.worldToCell(1e30, 0.2, cx, cy));
  EXPECT_FALSE(map.worldToCell(std::numeric_limits<double>::quiet_NaN(), 0.2, cx, cy));
}

// A segment to such a point is walked from its start, cell by cell, until the visitor stops it
// where its grid ends; a segment with a non-finite end crosses nothing.
TEST(RayCast, SegmentToAnAbsurdPointIsWalkedFromItsStart)
{
  std::vector<std::pair<int, int>> cells;
  auto first_five = [&](int x, int y)
  {
    cells.emplace_back(x, y);
    return cells.size() < 5;
  };
  traceSegment(0.5, 0.5, 2e31, 0.5, first_five);
  const std::vector<std::pair<int, int>> expected{{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}};
  EXPECT_EQ(cells, expected);
  cells.clear();
  traceSegment(0.5, 0.5, -1e300, -1e300, first_five);
  EXPECT_EQ(cells.size(), 5u);
  EXPECT_EQ(cells[0], std::make_pair(0, 0));
  cells.clear();
  traceSegment(0.5, 0.5, std::numeric_limits<double>::quiet_NaN(), 0.5, first_five);
  traceSegment(0.5, 0.5, std::numeric_limits<double>::infinity(), 0.5, first_five);
  EXPECT_TRUE(cells.empty());
}

TEST(RayCaster, GivesCastRaysRangesWhereverTheRayStartsAndHowTheMapLies)
{
  // The office and the factory, one with unknown cells, one rotated and shifted; rays from
  // inside and from outside the map, short and long. The caster's jumps must never skip a cell.
  GridMap office = officeWorld(0.05);
  for (int y = 60; y < 90; ++y)
    for (int x = 150; x < 200; ++x)
      office.at(x, y) = GridMap::kUnknown;
  GridMap factory = factoryWorld(0.05);
  factory.info.origin = {-3.0, 2.0, 0.3};
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int hits = 0, rays = 0;
  for (const GridMap* map : {&office, &factory})
    for (bool unknown_blocks : {false, true})
    {
      const RayCaster caster(*map, 50, unknown_blocks);
      const double w = map->info.width * map->info.resolution, h = map->info.height * map->info.resolution;
      for (int i = 0; i < 4000; ++i)
      {
        // Map-frame points from 2 m outside the map to 2 m beyond it.
        const Point2D local{unit(rng) * (w + 4.0) - 2.0, unit(rng) * (h + 4.0) - 2.0};
        const Point2D p = transformPoint(map->info.origin, local);
        const double angle = unit(rng) * 2.0 * M_PI, range = 1.0 + unit(rng) * 39.0;
        const double want = castRay(*map, p.x, p.y, angle, range, 50, unknown_blocks);
        ASSERT_NEAR(caster.cast(p.x, p.y, angle, range), want, 1e-6)
            << "ray from (" << p.x << ", " << p.y << ") at " << angle << " rad, max " << range << " m";
        hits += want < range;
        ++rays;
      }
    }
  EXPECT_GT(hits, rays / 2);  // most rays end on something: the comparison is not all max ranges
  // A whole scan: the same beams, the same infinities where nothing is in range.
  const Pose2D sensor{6.0, 5.0, 0.4};
  const std::vector<float> fast = RayCaster(office).scan(sensor, -M_PI, M_PI / 180, 360, 8.0);
  const std::vector<float> slow = simulateScan(office, sensor, -M_PI, M_PI / 180, 360, 8.0);
  ASSERT_EQ(fast.size(), slow.size());
  for (size_t i = 0; i < fast.size(); ++i)
    if (std::isinf(slow[i]))
      EXPECT_TRUE(std::isinf(fast[i])) << "beam " << i;
    else
      EXPECT_NEAR(fast[i], slow[i], 1e-5) << "beam " << i;
}

TEST(DriveFixtures, RouteClearanceIsTheLeastDistanceToAWall)
{
  // A 10 x 10 m room (0.1 m walls) with a 1 m box at (4..5, 4..5).
  const GridMap world = makeWorld(10.0, 10.0, 0.02, {{4.0, 4.0, 5.0, 5.0}});
  // Along y = 2, 1.9 m from the south wall's face and 2 m from the box: the wall is nearest.
  EXPECT_NEAR(routeClearance(world, {{2.0, 2.0}, {8.0, 2.0}}, 3.0), 1.9, 0.03);
  // Passing 0.5 m south of the box.
  EXPECT_NEAR(routeClearance(world, {{2.0, 3.5}, {8.0, 3.5}}), 0.5, 0.03);
  // Through the box, and out of the world.
  EXPECT_EQ(routeClearance(world, {{2.0, 4.5}, {8.0, 4.5}}), 0.0);
  EXPECT_EQ(routeClearance(world, {{2.0, 2.0}, {12.0, 2.0}}), 0.0);
  // Nothing within reach: the reach.
  EXPECT_EQ(routeClearance(world, {{2.5, 2.5}, {2.5, 2.6}}, 0.5), 0.5);
}
