// Motion models, distance transform and likelihood field of the AMCL library.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "mybot_amcl/amcl_models.h"
#include "mybot_nav_common/costmap_distance.h"
#include "mybot_nav_common/ray_cast.h"
#include "synthetic_world.h"

using namespace mybot_navigation;

namespace
{

struct Stats
{
  double mean = 0, sd = 0;
};

template <typename F>
Stats stats(int n, F f)
{
  double s = 0, ss = 0;
  for (int i = 0; i < n; ++i)
  {
    const double v = f();
    s += v;
    ss += v * v;
  }
  Stats r;
  r.mean = s / n;
  r.sd = std::sqrt(std::max(0.0, ss / n - r.mean * r.mean));
  return r;
}

MotionNoise only(int which, double value)
{
  MotionNoise n{0, 0, 0, 0, 0};
  (which == 1 ? n.alpha1 : which == 2 ? n.alpha2 : which == 3 ? n.alpha3 : which == 4 ? n.alpha4 : n.alpha5) = value;
  return n;
}

// A simulated 180-degree scan taken by a sensor at `sensor_in_base` on a robot at `base`.
LaserScanData scanAt(const GridMap& world, const Pose2D& base, const Pose2D& sensor_in_base, int beams)
{
  LaserScanData scan;
  scan.range_max = 30.0;
  scan.sensor_in_base = sensor_in_base;
  const double amin = -M_PI / 2, inc = M_PI / (beams - 1);
  const std::vector<float> ranges =
      simulateScan(world, compose(base, sensor_in_base), amin, inc, beams, scan.range_max);
  for (int i = 0; i < beams; ++i)
    scan.readings.push_back({std::isfinite(ranges[i]) ? ranges[i] : scan.range_max, amin + inc * i});
  return scan;
}

}  // namespace

TEST(OdomModelType, ParsesAmclNames)
{
  OdomModelType t;
  ASSERT_TRUE(parseOdomModelType("diff", t));
  EXPECT_EQ(t, OdomModelType::Diff);
  ASSERT_TRUE(parseOdomModelType("omni-corrected", t));
  EXPECT_EQ(t, OdomModelType::OmniCorrected);
  ASSERT_TRUE(parseOdomModelType("diff-corrected", t));
  EXPECT_EQ(t, OdomModelType::DiffCorrected);
  ASSERT_TRUE(parseOdomModelType("omni", t));
  EXPECT_EQ(t, OdomModelType::Omni);
  EXPECT_FALSE(parseOdomModelType("differential", t));
}

TEST(MotionModel, NoiselessDiffMotionIsAppliedInTheParticleFrame)
{
  Rng rng(1);
  const MotionModel m(OdomModelType::DiffCorrected, only(1, 0.0));
  // Odometry: forward 1 m then turn +90 deg, seen from an odom frame rotated against the map.
  const Pose2D odom_old{2.0, 1.0, M_PI / 2}, odom_new{2.0, 2.0, M_PI};
  const Pose2D particle{5.0, 5.0, 0.0};
  const Pose2D p = m.sample(particle, odom_old, odom_new, rng);
  EXPECT_NEAR(p.x, 6.0, 1e-9);
  EXPECT_NEAR(p.y, 5.0, 1e-9);
  EXPECT_NEAR(p.theta, M_PI / 2, 1e-9);
}

TEST(MotionModel, NoiselessOmniMotionKeepsSidewaysMotion)
{
  Rng rng(1);
  for (OdomModelType type : {OdomModelType::OmniCorrected, OdomModelType::Omni})
  {
    const MotionModel m(type, only(1, 0.0));
    // Pure strafe to the left by 0.5 m while turning 0.3 rad.
    const Pose2D odom_old{0, 0, 0}, odom_new{0.0, 0.5, 0.3};
    const Pose2D p = m.sample({1.0, 1.0, M_PI / 2}, odom_old, odom_new, rng);
    EXPECT_NEAR(p.x, 0.5, 1e-9);
    EXPECT_NEAR(p.y, 1.0, 1e-9);
    EXPECT_NEAR(p.theta, M_PI / 2 + 0.3, 1e-9);
  }
}

TEST(MotionModel, CorrectedTranslationNoiseHasAmclStandardDeviation)
{
  Rng rng(7);
  const double trans = 0.8, a3 = 0.05;
  const MotionModel corrected(OdomModelType::DiffCorrected, only(3, a3));
  const Stats s = stats(20000, [&] { return corrected.sample({}, {}, {trans, 0, 0}, rng).x; });
  EXPECT_NEAR(s.mean, trans, 0.005);
  EXPECT_NEAR(s.sd, std::sqrt(a3) * trans, 0.05 * std::sqrt(a3) * trans);

  // amcl's historical "diff" model uses the variance expression as the standard deviation.
  const MotionModel legacy(OdomModelType::Diff, only(3, a3));
  const Stats l = stats(20000, [&] { return legacy.sample({}, {}, {trans, 0, 0}, rng).x; });
  EXPECT_NEAR(l.sd, a3 * trans * trans, 0.05 * a3 * trans * trans);
}

TEST(MotionModel, DrivingBackwardsIsNotAHalfTurnForRotationNoise)
{
  Rng rng(3);
  const MotionModel m(OdomModelType::DiffCorrected, only(1, 0.5));
  // Backwards 1 m: rot1 = pi, but the noise uses min(|rot1|, |rot1 - pi|) = 0.
  const Stats s = stats(2000, [&] { return m.sample({}, {0, 0, 0}, {-1.0, 0, 0}, rng).theta; });
  EXPECT_LT(s.sd, 1e-9);
  const Stats x = stats(2000, [&] { return m.sample({}, {0, 0, 0}, {-1.0, 0, 0}, rng).x; });
  EXPECT_NEAR(x.mean, -1.0, 1e-9);
}

TEST(MotionModel, OmniStrafeNoiseGrowsWithTranslation)
{
  Rng rng(5);
  const double a5 = 0.1, trans = 1.0;
  const MotionModel m(OdomModelType::OmniCorrected, only(5, a5));
  const Stats s = stats(20000, [&] { return m.sample({}, {}, {trans, 0, 0}, rng).y; });
  EXPECT_NEAR(s.sd, std::sqrt(a5) * trans, 0.05 * std::sqrt(a5));
}

TEST(DistanceTransform, MatchesBruteForce)
{
  const int w = 37, h = 23;
  std::vector<uint8_t> seed(w * h, 0);
  std::mt19937 rng(11);
  for (int k = 0; k < 12; ++k)
    seed[rng() % seed.size()] = 1;
  const std::vector<float> d = distanceTransform(seed, w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
    {
      double best = 1e9;
      for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
          if (seed[j * w + i])
            best = std::min(best, std::hypot(i - x, j - y));
      ASSERT_NEAR(d[y * w + x], best, 1e-4) << x << "," << y;
    }
}

TEST(DistanceTransform, NoObstacleGivesHugeDistances)
{
  const std::vector<float> d = distanceTransform(std::vector<uint8_t>(20, 0), 5, 4);
  for (float v : d)
    EXPECT_GT(v, 1e6);
}

TEST(LikelihoodField, DistanceIsCappedAndOffMapUsesTheCap)
{
  const GridMap world = makeWorld(6.0, 4.0, 0.05, {});
  LaserModelParams lp;
  lp.likelihood_max_dist = 1.0;
  LikelihoodField f(lp);
  f.setMap(world);
  EXPECT_NEAR(f.distance(0.05, 2.0), 0.0, 1e-6);   // inside the 0.1 m wall
  EXPECT_NEAR(f.distance(0.5, 2.0), 0.4, 0.06);    // 0.4 m from the wall's inner face
  EXPECT_NEAR(f.distance(3.0, 2.0), 1.0, 1e-6);    // capped
  EXPECT_NEAR(f.distance(-10.0, 2.0), 1.0, 1e-6);  // off the map
}

// One beam straight at a wall 0.1 m thick (x 2.0-2.1): the laser stops at the face it meets, so an
// end point 7.5 cm beyond that face is as wrong as one 7.5 cm short of it. The nearest surface of
// the thin wall is only 2.5 cm from the point inside: scored by that, poses that push the end
// points into the walls ahead cost too little, and the estimate runs ahead of the robot.
TEST(LikelihoodField, EndPointsInsideAWallAreScoredByTheirDepthAlongTheBeam)
{
  GridMap world = makeWorld(6.0, 4.0, 0.05, {});
  for (int cy = 0; cy < world.info.height; ++cy)
    for (int cx = 40; cx < 42; ++cx)
      world.data[static_cast<size_t>(cy) * world.info.width + cx] = GridMap::kOccupied;
  LaserModelParams lp;
  lp.max_beams = 2;
  lp.sigma_hit = 0.05;
  LikelihoodField f(lp);
  f.setMap(world);
  auto one_beam = [](double range, double bearing = 0.0)
  {
    LaserScanData scan;
    scan.readings = {{range, bearing}};
    return scan;
  };
  // End points on cell centres, where the field's distances are exact.
  const Pose2D robot{1.0, 2.0, 0.0};
  const double short_of_it = f.weight(robot, one_beam(0.925)), inside = f.weight(robot, one_beam(1.075));
  EXPECT_NEAR(inside, short_of_it, 1e-6);
  EXPECT_LT(inside, f.weight(robot, one_beam(1.025)) - 0.3);  // 2.5 cm in: much better
  // Across the wall the depth is counted from the face the beam entered by: from the far side
  // (robot at x 3), the same point is 2.5 cm deep.
  EXPECT_NEAR(f.weight({3.0, 2.0, M_PI}, one_beam(0.925)), f.weight(robot, one_beam(1.025)), 1e-6);
}

TEST(LikelihoodField, BeamStepFollowsAmcl)
{
  LaserModelParams lp;
  lp.max_beams = 30;
  LikelihoodField f(lp);
  // 720 beams: step = 719 / 29 = 24 -> beams 0, 24, ..., 696 (30 beams).
  const auto idx = f.beamIndices(720);
  ASSERT_EQ(idx.size(), 30u);
  EXPECT_EQ(idx[1], 24u);
  EXPECT_EQ(f.beamIndices(10).size(), 10u);  // fewer beams than max_beams: use all
}

TEST(LikelihoodField, TruePoseOutweighsDisplacedPoses)
{
  const GridMap world = officeWorld(0.05);
  LikelihoodField f;
  f.setMap(world);
  const Pose2D truth{3.0, 3.0, 0.4};
  const int beams = 360;
  const LaserScanData scan = scanAt(world, truth, {}, beams);
  const double w_true = f.weight(truth, scan);
  EXPECT_GT(w_true, f.weight({3.3, 3.0, 0.4}, scan));
  EXPECT_GT(w_true, f.weight({3.0, 2.7, 0.4}, scan));
  EXPECT_GT(w_true, f.weight({3.0, 3.0, 0.6}, scan));
  // Max-range readings carry no information: a scan of only those weighs 1 everywhere.
  LaserScanData empty = scan;
  for (auto& r : empty.readings)
    r.range = empty.range_max;
  EXPECT_DOUBLE_EQ(f.weight(truth, empty), 1.0);
  // Upper bound: 1 + beams_used * (z_hit + z_rand / range_max)^3.
  const double pz = 0.95 + 0.05 / 30.0;
  EXPECT_LE(w_true, 1.0 + f.beamIndices(beams).size() * pz * pz * pz + 1e-9);
}

TEST(LikelihoodField, SensorOffsetIsApplied)
{
  const GridMap world = officeWorld(0.05);
  LikelihoodField f;
  f.setMap(world);
  const Pose2D base{3.0, 3.0, 0.0};
  const LaserScanData scan = scanAt(world, base, {0.3, 0.0, 0.0}, 181);
  EXPECT_GT(f.weight(base, scan), f.weight(compose(base, scan.sensor_in_base), scan));
}

// Readings that are finite but absurd (1e30 m) under a range_max of inf, which a LaserScan may
// declare: their end points are off the map, as those of readings 1 km long. Their cells were an
// out-of-range conversion to int (undefined behaviour, found by reading, not yet by a failure).
TEST(LikelihoodField, AbsurdRangesAreEndPointsOffTheMap)
{
  const GridMap world = officeWorld(0.05);
  LikelihoodField f;
  f.setMap(world);
  const Pose2D truth{3.0, 3.0, 0.4};
  LaserScanData absurd = scanAt(world, truth, {}, 90), far = absurd;
  absurd.range_max = far.range_max = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < absurd.readings.size(); i += 3)
  {
    absurd.readings[i].range = 1e30;
    far.readings[i].range = 1000.0;
  }
  for (const Pose2D& p : {truth, Pose2D{1.0, 1.0, -2.0}})
  {
    EXPECT_DOUBLE_EQ(f.weight(p, absurd), f.weight(p, far));
    EXPECT_DOUBLE_EQ(f.maxWeightSeenFrom(p, absurd), f.maxWeightSeenFrom(p, far));
    EXPECT_DOUBLE_EQ(f.seeThroughShare(p, absurd, 0.2), f.seeThroughShare(p, far, 0.2));
    EXPECT_TRUE(std::isfinite(f.weight(p, absurd)));
  }
}

// amcl_node's conversion: readings at or below the minimum (the scan's, or laser_min_range if
// larger) and non-finite ones count as max range; laser_max_range narrows the scan's range_max.
TEST(LaserScanData, TakesRangesAsAmclNodeDoes)
{
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const std::vector<float> ranges{0.05f, 0.3f, 2.0f, nan, inf, 25.0f};
  const LaserScanData own = laserScanData(ranges, -0.5, 0.2, 0.1, 30.0, -1.0, -1.0, {0.1, 0.0, 0.0}, false);
  ASSERT_EQ(own.readings.size(), 6u);
  EXPECT_DOUBLE_EQ(own.range_max, 30.0);
  const std::vector<double> expected{30.0, 0.3, 2.0, 30.0, 30.0, 25.0};
  for (size_t i = 0; i < 6; ++i)
  {
    EXPECT_NEAR(own.readings[i].range, expected[i], 1e-6) << i;
    EXPECT_NEAR(own.readings[i].bearing, -0.5 + 0.2 * i, 1e-12) << i;
  }
  EXPECT_DOUBLE_EQ(own.sensor_in_base.x, 0.1);
  const LaserScanData narrowed = laserScanData(ranges, -0.5, 0.2, 0.1, 30.0, 0.5, 20.0, {}, true);
  EXPECT_DOUBLE_EQ(narrowed.range_max, 20.0);
  EXPECT_DOUBLE_EQ(narrowed.readings[1].range, 20.0);     // 0.3 m is below laser_min_range 0.5
  EXPECT_NEAR(narrowed.readings[2].bearing, 0.1, 1e-12);  // upside down: mirrored
  EXPECT_DOUBLE_EQ(narrowed.readings[5].range, 25.0);     // kept: the model skips it as >= range_max
}
