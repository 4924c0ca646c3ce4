// Slam's global loop search (global_search.cpp): a robot whose odometry jumps by metres (carried,
// pushed, a wheel spinning on a cable) goes on mapping a displaced copy of the office; the local
// search, which looks 3 m around the estimate, never finds the way back.
#include <gtest/gtest.h>

#include <cmath>

#include "mybot_slam/evaluation.h"
#include "slam_run.h"

using namespace mybot_navigation;

namespace
{
// Twice round both rooms of the office world.
const std::vector<Point2D> kTwoLoops{
    {1.0, 1.0},  {5.0, 0.8}, {5.0, 4.2}, {7.5, 4.2}, {10.5, 1.0}, {10.5, 6.5}, {7.0, 9.0}, {6.8, 4.3}, {3.0, 4.2},
    {0.8, 6.5},  {3.0, 9.0}, {4.5, 6.0}, {1.0, 3.0}, {1.0, 1.0},  {5.0, 0.8},  {5.0, 4.2}, {7.5, 4.2}, {10.5, 1.0},
    {10.5, 6.5}, {7.0, 9.0}, {6.8, 4.3}, {3.0, 4.2}, {0.8, 6.5},  {3.0, 9.0},  {4.5, 6.0}, {1.0, 3.0}, {1.0, 1.0}};

struct SlipRun
{
  Slam slam;
  OfflineRun run;
  double ate = 0.0;
  MapScore map;
};

// The odometry jumps by `slip` (in the robot's frame) once the first loop is done.
SlipRun driveWithSlip(double global_interval, double local_window_max)
{
  static const GridMap world = officeWorld(0.01);
  LaserSpec laser;
  laser.rate = 10.0;  // Hz: a quarter of the scans, for the test's time
  OdometryNoise noise;
  noise.alpha_trans = 0.02;
  noise.alpha_rot = 0.02;
  DriveSimulator drive(world, kTwoLoops, laser, noise, 0.5, 1.0, 3);
  SlamParams p;
  p.linear_update = 0.25;
  p.angular_update = 0.25;
  // A robot that can be carried: a closure may move the pose by up to 10 m whatever the path.
  p.loop_max_correction = 10.0;
  p.loop_window_linear_max = local_window_max;
  p.loop_global_interval = global_interval;
  p.weak_step_cauchy = true;  // the jump shows as a step the matcher could not confirm
  SlipRun r{Slam(p), {}, 0.0, {}};
  const Pose2D slip{6.0, -5.0, 0.3};
  bool slipped = false;
  Pose2D jump;  // odometry frame -> slipped odometry frame
  r.run = runSlamOnDrive(r.slam, drive, laser, 30.0,
                         [&](const DriveSample& s)
                         {
                           if (!slipped && s.stamp >= 120.0)
                           {
                             slipped = true;
                             jump = compose(compose(s.odom, slip), inverse(s.odom));
                           }
                           return slipped ? compose(jump, s.odom) : s.odom;
                         });
  const Pose2D align = alignTrajectories(r.run.estimate, r.run.truth);
  r.ate = absoluteTrajectoryRmse(r.run.estimate, r.run.truth, align);
  r.map = scoreMap(r.slam.map(), world, align, 1);
  return r;
}

// The jump with the global search off and the local window held at 3 m: the premise of both tests
// below, driven once (it takes seconds).
const SlipRun& neitherSearchReaches()
{
  static const SlipRun r = driveWithSlip(0.0, 3.0);
  return r;
}
}  // namespace

TEST(GlobalSearch, FindsTheMappedPlaceAfterTheOdometryJumpedMetres)
{
  // The local search's window held at 3 m (it grows with the drift possible, up to
  // loop_window_linear_max): the jump is beyond it in x, so that only the global search can find
  // the place.
  const SlipRun& without = neitherSearchReaches();
  const SlipRun with = driveWithSlip(10.0, 3.0);
  const SlamStats& s = with.slam.stats();
  std::printf(
      "without the global search: ATE %.3f m, map precision %.3f; with: ATE %.3f m, precision %.3f recall %.3f "
      "(%d global searches, %d matches, %d closures from them)\n",
      without.ate, without.map.precision, with.ate, with.map.precision, with.map.recall, s.loop_global_attempts,
      s.loop_global_matches, s.loop_global_closures);
  // The premise: the local search alone leaves the second loop where the jump put it.
  ASSERT_GT(without.ate, 0.5);
  EXPECT_EQ(without.slam.stats().loop_global_attempts, 0);
  EXPECT_GE(s.loop_global_closures, 1);
  EXPECT_LT(with.ate, 0.05);
  EXPECT_GE(with.map.precision, 0.9);
  EXPECT_GE(with.map.recall, 0.9);
  EXPECT_GT(with.map.precision, without.map.precision + 0.2);
}

TEST(LocalSearch, GrowsItsWindowAndSubmapWithTheDriftPossible)
{
  // The same jump (6 m, -5 m, 0.3 rad) with the global search off: a closure may move the pose by
  // 10 m here, so the local window grows to its 6 m cap and the candidate's submap follows its
  // pass that far; the jump is then within reach of the local search alone.
  const SlipRun& held = neitherSearchReaches();
  const SlipRun grown = driveWithSlip(0.0, 6.0);
  std::printf("local window held at 3 m: ATE %.3f m, precision %.3f; grown to 6 m: ATE %.3f m, precision %.3f\n",
              held.ate, held.map.precision, grown.ate, grown.map.precision);
  ASSERT_GT(held.ate, 0.5);
  EXPECT_EQ(grown.slam.stats().loop_global_attempts, 0);
  EXPECT_LT(grown.ate, 0.05);
  EXPECT_GE(grown.map.precision, 0.9);
}
