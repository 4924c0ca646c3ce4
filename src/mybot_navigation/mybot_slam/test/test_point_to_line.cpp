#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "mybot_slam/point_to_line.h"

using namespace mybot_navigation;

namespace
{
// Points every `step` along the segment a -> b.
void addWall(std::vector<Point2D>& out, Point2D a, Point2D b, double step)
{
  const double length = std::hypot(b.x - a.x, b.y - a.y);
  const int n = static_cast<int>(length / step);
  for (int i = 0; i <= n; ++i)
    out.push_back({a.x + (b.x - a.x) * i / n, a.y + (b.y - a.y) * i / n});
}

// A 6 x 4 m room with a pillar, seen as dense wall points (the reference, world frame).
std::vector<Point2D> room()
{
  std::vector<Point2D> pts;
  addWall(pts, {-3, -2}, {3, -2}, 0.02);
  addWall(pts, {3, -2}, {3, 2}, 0.02);
  addWall(pts, {3, 2}, {-3, 2}, 0.02);
  addWall(pts, {-3, 2}, {-3, -2}, 0.02);
  addWall(pts, {1, 0}, {1.5, 0}, 0.02);
  addWall(pts, {1.5, 0}, {1.5, 0.5}, 0.02);
  return pts;
}

// The reference's points as a scan from `pose` would see them (base frame), every third one,
// with Gaussian range-like noise.
std::vector<Point2D> scanFrom(const std::vector<Point2D>& world, const Pose2D& pose, double noise, unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, noise);
  const Pose2D inv = inverse(pose);
  std::vector<Point2D> out;
  for (size_t i = 1; i < world.size(); i += 3)
  {
    Point2D p = transformPoint(inv, world[i]);
    p.x += n(rng);
    p.y += n(rng);
    out.push_back(p);
  }
  return out;
}
}  // namespace

TEST(LineReference, FitsTheNormalOfTheWallThroughEachPointAndNoneAtACorner)
{
  std::vector<Point2D> pts;
  addWall(pts, {0, 0}, {2, 0}, 0.02);
  const LineReference ref(pts);
  Point2D q, n;
  ASSERT_TRUE(ref.nearest({1.0, 0.03}, 0.1, q, n));
  EXPECT_NEAR(std::abs(n.y), 1.0, 1e-9);
  EXPECT_NEAR(q.y, 0.0, 1e-9);
  EXPECT_FALSE(ref.nearest({1.0, 0.2}, 0.1, q, n)) << "nothing within 0.1 m";

  // A lone cluster without a direction has no line.
  const LineReference blob({{0, 0}, {0.01, 0.01}, {0.01, -0.01}, {-0.01, 0.01}, {-0.01, -0.01}});
  EXPECT_EQ(blob.size(), 0u);
}

// A far wall, its hits 0.2 m apart (1 deg beams at 11.5 m): no line within 0.15 m of a hit, one
// within the wider sparse radius.
TEST(LineReference, ASparseFarWallGetsItsLineFromTheWiderNeighbourhood)
{
  std::vector<Point2D> pts;
  addWall(pts, {11.5, -3}, {11.5, 3}, 0.2);
  EXPECT_EQ(LineReference(pts, 0.15, 0.05, 0.0).size(), 0u);
  const LineReference ref(pts);
  EXPECT_EQ(ref.size(), pts.size() - 2) << "all but the two ends, which have one neighbour";
  Point2D q, n;
  ASSERT_TRUE(ref.nearest({11.45, 0.03}, 0.1, q, n));
  EXPECT_NEAR(std::abs(n.x), 1.0, 1e-9);
  EXPECT_NEAR(q.x, 11.5, 1e-9);
}

TEST(PointToLine, RecoversASubCellOffsetThatTheGridCannotSee)
{
  const std::vector<Point2D> world = room();
  const LineReference ref(world);
  const Pose2D truth{0.513, -0.287, 0.31};
  const std::vector<Point2D> scan = scanFrom(world, truth, 0.005, 1);
  // Started 2.2 cm, 1.3 cm and 0.6 degrees away: less than half a 5 cm cell.
  const Pose2D start{truth.x + 0.022, truth.y - 0.013, truth.theta + 0.01};
  const PointToLineResult r = refinePointToLine(ref, scan, start);
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.pose.x, truth.x, 1e-3);
  EXPECT_NEAR(r.pose.y, truth.y, 1e-3);
  EXPECT_NEAR(r.pose.theta, truth.theta, 3e-4);
  EXPECT_LT(r.rms, 0.01);
  EXPECT_GT(r.constraint_ratio, 0.3);
}

TEST(PointToLine, AlongACorridorThePoseStaysWhereItStarted)
{
  std::vector<Point2D> world;
  addWall(world, {-10, -1}, {10, -1}, 0.02);
  addWall(world, {-10, 1}, {10, 1}, 0.02);
  const LineReference ref(world);
  const Pose2D truth{0.0, 0.1, 0.0};
  const std::vector<Point2D> scan = scanFrom(world, truth, 0.005, 2);
  // Scan points from x in [-10, 10] seen from 0: starting 0.3 m along, every point still lies on
  // a wall, and across the corridor it is 3 cm off.
  const Pose2D start{0.3, 0.13, 0.0};
  const PointToLineResult r = refinePointToLine(ref, scan, start);
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.pose.y, truth.y, 1e-3) << "across the corridor the walls pin it";
  EXPECT_NEAR(r.pose.x, start.x, 1e-3) << "along it nothing does: the prior keeps it";
  EXPECT_LT(r.constraint_ratio, 0.01);
}

TEST(PointToLine, FailsWhereTooFewPointsLieNearAnyLine)
{
  const std::vector<Point2D> world = room();
  const LineReference ref(world);
  const Pose2D truth{0.0, 0.0, 0.0};
  std::vector<Point2D> scan = scanFrom(world, truth, 0.005, 3);
  // Most of the scan sees what the reference does not have (a second room 20 m away).
  const size_t seen = scan.size();
  for (size_t i = 0; i < 2 * seen; ++i)
    scan.push_back({20.0 + 0.01 * static_cast<double>(i % 100), 0.05 * static_cast<double>(i / 100)});
  const PointToLineResult r = refinePointToLine(ref, scan, truth);
  EXPECT_FALSE(r.ok);
  EXPECT_LE(r.inliers, static_cast<int>(seen));
  EXPECT_GT(r.inliers, static_cast<int>(0.9 * static_cast<double>(seen))) << "the room's points still matched";
}
