#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "mybot_nav_common/ray_cast.h"
#include "mybot_slam/scan_matcher.h"
#include "synthetic_world.h"

using namespace mybot_navigation;

namespace
{
std::vector<Point2D> scanPoints(const GridMap& world, const Pose2D& pose)
{
  const LaserSpec laser;
  const std::vector<float> r = simulateScan(world, pose, laser.angle_min, laser.angleIncrement(), laser.beams, 30.0);
  std::vector<Point2D> pts;
  for (int i = 0; i < laser.beams; ++i)
    if (std::isfinite(r[i]))
    {
      const double a = laser.angle_min + laser.angleIncrement() * i;
      pts.push_back({r[i] * std::cos(a), r[i] * std::sin(a)});
    }
  return pts;
}

GridMap coarse(const GridMap& fine, double res)
{
  // Downsample a fine truth map: a coarse cell is occupied if any fine cell is.
  MapInfo info;
  info.resolution = res;
  const int f = static_cast<int>(std::lround(res / fine.info.resolution));
  info.width = fine.info.width / f;
  info.height = fine.info.height / f;
  GridMap m(info, 0);
  for (int y = 0; y < info.height * f; ++y)
    for (int x = 0; x < info.width * f; ++x)
      if (fine.at(x, y) == 100)
        m.at(x / f, y / f) = 100;
  return m;
}
// `count` single occupied cells at random (seeded) across a width x height m box centred on the
// origin, seen from it in one scan.
OccupancyGrid scatteredWalls(unsigned seed, int count, double width, double height)
{
  std::mt19937 random(seed);
  RangeScan scattered;
  const auto mm = [&](double span)
  { return static_cast<double>(random() % static_cast<unsigned>(span * 1000)) * 1e-3; };
  for (int i = 0; i < count; ++i)
  {
    const double x = mm(width) - 0.5 * width;
    scattered.hits.push_back({x, mm(height) - 0.5 * height});
  }
  OccupancyGrid grid;
  grid.insertScan(Pose2D{}, scattered);
  return grid;
}
}  // namespace

class ScanMatcherTest : public ::testing::TestWithParam<std::tuple<double, double, double>>
{
};

TEST_P(ScanMatcherTest, RecoversOffsetWithSubCellAccuracy)
{
  const GridMap world = officeWorld(0.01);
  // Reference map built the way SLAM builds it: scans inserted into a log-odds grid.
  OccupancyGrid grid;
  for (const Pose2D& p : {Pose2D{3.0, 5.5, 0.3}, Pose2D{2.5, 5.0, 1.5}, Pose2D{3.5, 6.0, -1.0}, Pose2D{3.0, 5.5, 3.0}})
  {
    RangeScan s;
    s.hits = scanPoints(world, p);
    grid.insertScan(p, s);
  }
  const MatchField field(grid, 0.05, 4);
  const Pose2D truth{3.07, 5.43, 0.25};
  const auto pts = voxelFilter(scanPoints(world, truth), 0.05);
  const auto [dx, dy, dt] = GetParam();
  MatchRequest req;
  req.initial = {truth.x + dx, truth.y + dy, truth.theta + dt};
  req.linear_window = 0.4;
  req.angular_window = 0.3;
  const MatchResult r = matchScan(field, pts, req);
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.pose.x, truth.x, 0.02);
  EXPECT_NEAR(r.pose.y, truth.y, 0.02);
  EXPECT_NEAR(r.pose.theta, truth.theta, 0.01);
  EXPECT_GT(r.score, 0.7);
}

INSTANTIATE_TEST_SUITE_P(Offsets, ScanMatcherTest,
                         ::testing::Values(std::make_tuple(0.0, 0.0, 0.0), std::make_tuple(0.25, -0.15, 0.1),
                                           std::make_tuple(-0.3, 0.3, -0.2), std::make_tuple(0.07, 0.02, 0.02)));

TEST(ScanMatcher, BranchAndBoundEqualsExhaustiveSearch)
{
  const GridMap world = officeWorld(0.01);
  const MatchField field(coarse(world, 0.05), 0.05, 5);
  const MatchField flat(coarse(world, 0.05), 0.05, 1);  // one level: exhaustive search
  const auto pts = voxelFilter(scanPoints(world, {8.0, 4.0, -1.0}), 0.1);
  MatchRequest req;
  req.initial = {8.2, 3.9, -0.9};
  req.linear_window = 0.5;
  req.angular_window = 0.2;
  req.refine = false;
  const MatchResult a = matchScan(field, pts, req);
  const MatchResult b = matchScan(flat, pts, req);
  ASSERT_TRUE(a.ok && b.ok);
  EXPECT_DOUBLE_EQ(a.score, b.score);
}

// A corner seen from inside it, rendered once or twice (2 m apart): searched again with the best
// match's surroundings excluded (loop closure's uniqueness test), the matcher finds the other
// copy, scoring as well, or nothing that scores 0.8 of the best where there is one corner only.
TEST(ScanMatcher, ExcludingTheBestMatchFindsARepeatedPlaceOnly)
{
  RangeScan corner;  // in the frame of a robot 0.5 m from both walls
  for (double t = -0.5; t <= 0.5; t += 0.02)
  {
    corner.hits.push_back({t, 0.5});
    corner.hits.push_back({-0.5, t});
  }
  OccupancyGrid once, twice;
  once.insertScan(Pose2D{1.0, 1.0, 0.0}, corner);
  twice.insertScan(Pose2D{1.0, 1.0, 0.0}, corner);
  twice.insertScan(Pose2D{3.0, 1.0, 0.0}, corner);
  const std::vector<Point2D> points = voxelFilter(corner.hits, 0.05);
  MatchRequest req;
  req.initial = {1.9, 1.1, 0.0};  // between the copies, nearer the first
  req.linear_window = 2.0;
  req.angular_window = 0.1;
  req.refine = false;
  for (const OccupancyGrid* grid : {&once, &twice})
  {
    const MatchField field(*grid, 0.05, matchFieldLevels(req.linear_window, 0.05));
    const MatchResult best = matchScan(field, points, req);
    ASSERT_TRUE(best.ok);
    EXPECT_GT(best.score, 0.9);
    MatchRequest elsewhere = req;
    elsewhere.exclude_center = best.pose;
    elsewhere.exclude_radius = 0.3;
    elsewhere.min_score = 0.8 * best.score;
    const MatchResult second = matchScan(field, points, elsewhere);
    if (grid == &once)
    {
      EXPECT_FALSE(second.ok) << "a second place at " << second.pose.x << ", " << second.pose.y;
      continue;
    }
    ASSERT_TRUE(second.ok);
    EXPECT_NEAR(std::abs(second.pose.x - best.pose.x), 2.0, 0.05);
    EXPECT_NEAR(second.pose.y, 1.0, 0.05);
    EXPECT_NEAR(second.score, best.score, 0.02);
  }
}

TEST(ScanMatcher, AdaptiveVoxelFilterThinsLessWhereFewPointsRemain)
{
  // A 1 m stretch of wall seen at 1 cm spacing: at 0.1 m it keeps 10 or 11 points.
  std::vector<Point2D> wall;
  for (int i = 0; i < 100; ++i)
    wall.push_back({2.0, 0.003 + 0.01 * i});
  EXPECT_LE(voxelFilter(wall, 0.1).size(), 11u);
  // Asked for 30: half the cell keeps about 20, a quarter about 40.
  EXPECT_EQ(adaptiveVoxelFilter(wall, 0.1, 30).size(), voxelFilter(wall, 0.025).size());
  EXPECT_GE(adaptiveVoxelFilter(wall, 0.1, 30).size(), 30u);
  // Never finer than a quarter of the cell, even where that keeps fewer than asked.
  EXPECT_EQ(adaptiveVoxelFilter(wall, 0.1, 1000).size(), voxelFilter(wall, 0.025).size());
  // Enough points at the cell: the cell's filter, unchanged.
  std::vector<Point2D> room;
  for (int i = 0; i < 1000; ++i)
    room.push_back({std::cos(i * 0.00628) * 4.0, std::sin(i * 0.00628) * 4.0});
  const std::vector<Point2D> coarse = voxelFilter(room, 0.1), adaptive = adaptiveVoxelFilter(room, 0.1, 30);
  ASSERT_GE(coarse.size(), 30u);
  ASSERT_EQ(adaptive.size(), coarse.size());
  for (size_t i = 0; i < coarse.size(); ++i)
    EXPECT_EQ(adaptive[i].x, coarse[i].x);
}

TEST(ScanMatcher, RejectsBelowMinimumScore)
{
  const GridMap world = officeWorld(0.01);
  const MatchField field(coarse(world, 0.05), 0.05, 3);
  MatchRequest req;
  req.initial = {6.0, 5.0, 0.0};
  req.min_score = 0.5;
  // Points far outside the map never match.
  const MatchResult r = matchScan(field, {{100.0, 0.0}, {100.0, 1.0}}, req);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(matchScan(field, {}, req).ok);
}

// A wall seen from the origin: its cells ahead of the face are observed free, the ones behind it
// never observed. With unobserved_weight the fall-off behind the face is scaled, not in front.
TEST(MatchField, UnobservedWeightScalesTheFallOffBehindAMappedFaceOnly)
{
  OccupancyGrid grid;
  RangeScan scan;
  for (double y = -1.0; y <= 1.0; y += 0.02)
    scan.hits.push_back({2.025, y});  // the centre of lattice column 40
  grid.insertScan(Pose2D{}, scan);
  const int front = 39, wall = 40, behind = 41, row = 0;
  ASSERT_LT(grid.logOdds(front, row), 0.0f);  // observed free
  ASSERT_GT(grid.logOdds(wall, row), 0.0f);
  ASSERT_EQ(grid.logOdds(behind, row), 0.0f);  // never observed

  const MatchField plain(grid, 0.05, 1, -10, -30, 50, 30);
  const MatchField weighted(grid, 0.05, 3, -10, -30, 50, 30, 0.5);
  EXPECT_FLOAT_EQ(plain.value(0, front, row), plain.value(0, behind, row));  // symmetric Gaussian
  EXPECT_FLOAT_EQ(weighted.value(0, wall, row), 1.0f);
  EXPECT_FLOAT_EQ(weighted.value(0, front, row), plain.value(0, front, row));
  EXPECT_NEAR(weighted.value(0, behind, row), 0.5 * plain.value(0, behind, row), 1.0 / 255.0);
  // The coarser levels are pooled from the weighted level 0: still upper bounds of it.
  for (int x = front - 4; x <= behind + 4; ++x)
    EXPECT_GE(weighted.value(2, x - 3, row - 3), weighted.value(0, x, row));
}

// The field built over only what a search can read equals the whole grid's field there, cell for
// cell at every level: walls scattered everywhere (2.5 % of the cells, so some lie just past any
// too small box), for the coarsest block of several windows and two fall-offs.
TEST(MatchField, AroundASearchEqualsTheWholeGridsFieldWhereTheSearchReads)
{
  const OccupancyGrid grid = scatteredWalls(7, 4000, 20.0, 20.0);
  const Pose2D around{0.3, -0.7, 0.4};
  const double reach = 4.0;
  for (double window : {0.3, 0.6, 2.0})
    for (double sigma : {0.05, 0.1})
    {
      const MatchField whole(grid, sigma, matchFieldLevels(window, grid.resolution()));
      const MatchField part = matchFieldAround(grid, sigma, window, around, reach);
      ASSERT_EQ(part.levels(), whole.levels());
      // Every block the search can start at: the points' cells (within reach of `around`)
      // shifted by up to the window, and the cell beyond that refinement interpolates with. A
      // block at level h also holds the 2^h - 1 cells above it.
      const int lo_x = grid.worldToLattice(around.x - reach - window) - 1,
                hi_x = grid.worldToLattice(around.x + reach + window) + 2,
                lo_y = grid.worldToLattice(around.y - reach - window) - 1,
                hi_y = grid.worldToLattice(around.y + reach + window) + 2;
      int differing = 0, nonzero = 0;
      for (int level = 0; level < whole.levels(); ++level)
        for (int gy = lo_y; gy <= hi_y; ++gy)
          for (int gx = lo_x; gx <= hi_x; ++gx)
          {
            nonzero += whole.value(level, gx, gy) > 0.0f;
            differing += whole.value(level, gx, gy) != part.value(level, gx, gy);
          }
      EXPECT_EQ(differing, 0) << "window " << window << ", sigma " << sigma;
      EXPECT_GT(nonzero, 1000);
    }
}

// The same search in the part and in the whole field finds the same pose with the same score:
// a loop-closure submap's field is built the cheap way with nothing else changed.
TEST(MatchField, AroundASearchFindsWhatTheWholeFieldFinds)
{
  const GridMap world = officeWorld(0.01);
  OccupancyGrid grid;
  for (const Pose2D& p : {Pose2D{3.0, 5.5, 0.3}, Pose2D{8.0, 4.0, -1.0}, Pose2D{12.0, 6.0, 2.0}})
  {
    RangeScan s;
    s.hits = scanPoints(world, p);
    grid.insertScan(p, s);
  }
  const Pose2D truth{8.07, 4.13, -0.95};
  std::vector<Point2D> pts = voxelFilter(scanPoints(world, truth), 0.05);
  pts.erase(std::remove_if(pts.begin(), pts.end(), [](const Point2D& p) { return std::hypot(p.x, p.y) > 4.0; }),
            pts.end());
  ASSERT_GT(pts.size(), 50u);
  MatchRequest req;
  req.initial = {8.3, 3.9, -0.85};
  req.linear_window = 0.6;
  req.angular_window = 0.2;
  const MatchField whole(grid, 0.05, matchFieldLevels(req.linear_window, grid.resolution()));
  const MatchField part = matchFieldAround(grid, 0.05, req.linear_window, req.initial, 4.0);
  const MatchResult a = matchScan(whole, pts, req), b = matchScan(part, pts, req);
  ASSERT_TRUE(a.ok && b.ok);
  EXPECT_EQ(a.pose.x, b.pose.x);
  EXPECT_EQ(a.pose.y, b.pose.y);
  EXPECT_EQ(a.pose.theta, b.pose.theta);
  EXPECT_EQ(a.score, b.score);
  EXPECT_EQ(translationConstraintRatio(whole, pts, a.pose), translationConstraintRatio(part, pts, b.pose));
  EXPECT_NEAR(a.pose.x, truth.x, 0.03);
  EXPECT_NEAR(a.pose.y, truth.y, 0.03);
}

// Level h holds, at each cell, the largest level-0 value of the 2^h x 2^h block from that cell up
// and right (nothing beyond the lattice): what makes a block's score bound its cells' scores.
TEST(MatchField, EachLevelIsTheMaximumOverItsBlockUpToTheLatticesEdge)
{
  const OccupancyGrid grid = scatteredWalls(3, 300, 6.0, 4.0);
  const MatchField field(grid, 0.05, 5);
  ASSERT_EQ(field.levels(), 5);
  const int x0 = field.minCellX(), y0 = field.minCellY(), x1 = x0 + field.width(), y1 = y0 + field.height();
  int checked = 0, differing = 0;
  for (int level = 1; level < field.levels(); ++level)
    for (int gy = y0 - 2; gy < y1 + 2; ++gy)
      for (int gx = x0 - 2; gx < x1 + 2; ++gx)
      {
        float best = 0.0f;
        for (int by = 0; by < (1 << level); ++by)
          for (int bx = 0; bx < (1 << level); ++bx)
            if (gx >= x0 && gy >= y0)  // outside the lattice every level reads 0
              best = std::max(best, field.value(0, gx + bx, gy + by));
        ++checked;
        differing += field.value(level, gx, gy) != best;
      }
  EXPECT_EQ(differing, 0) << "of " << checked;
}
