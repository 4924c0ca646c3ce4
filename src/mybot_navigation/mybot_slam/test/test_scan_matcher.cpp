#include <gtest/gtest.h>

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
