#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>

#include "mybot_slam/evaluation.h"
#include "mybot_nav_common/ray_cast.h"
#include "slam_run.h"

using namespace mybot_navigation;

// The drives below pass the same true poses whatever their noise: they share their noiseless scans
// (DriveSimulator::shareScans; every sample is bit for bit what it was without sharing).
static const bool kScansShared = (DriveSimulator::shareScans(true), true);

namespace
{
// A loop through both rooms of the office world, back to the start: round the east room's shelf,
// along the west room's table, through the door twice. It keeps at least 0.5 m from every wall and
// piece of furniture (TheOfficeLoopKeepsClearOfTheFurniture), so the laser never sees one from inside.
const std::vector<Point2D> kOfficeLoop{{1.0, 0.6},  {5.0, 0.6},  {5.0, 4.2},  {7.5, 4.2},  {8.0, 1.0},
                                       {10.2, 1.0}, {10.2, 6.5}, {11.2, 7.0}, {11.2, 8.8}, {7.0, 8.9},
                                       {6.8, 4.3},  {3.0, 4.2},  {1.5, 6.2},  {0.9, 6.5},  {0.9, 8.7},
                                       {3.0, 9.0},  {4.5, 6.0},  {1.0, 3.0},  {1.0, 0.6}};

SlamParams testParams()
{
  SlamParams p;
  p.linear_update = 0.25;
  p.angular_update = 0.25;
  return p;
}

struct Score
{
  MapScore map;
  double ate;
};

// Odometry noise of the drives below: `alpha` of the translation and of the rotation, a heading
// bias of `drift_rot` rad a metre.
OdometryNoise odometryNoise(double alpha, double drift_rot)
{
  OdometryNoise noise;
  noise.alpha_trans = alpha;
  noise.alpha_rot = alpha;
  noise.drift_rot = drift_rot;
  return noise;
}

Score evaluate(const Slam& slam, const OfflineRun& run, const GridMap& world)
{
  const Pose2D align = alignTrajectories(run.estimate, run.truth);
  return {scoreMap(slam.map(), world, align, 1), absoluteTrajectoryRmse(run.estimate, run.truth, align)};
}
}  // namespace

TEST(Slam, TheOfficeLoopKeepsClearOfTheFurniture)
{
  EXPECT_GE(routeClearance(officeWorld(0.01), kOfficeLoop), 0.5);
}

TEST(Slam, OfficeLoopWithOdometryNoiseMeetsAccuracyTargets)
{
  const GridMap world = officeWorld(0.01);
  const LaserSpec laser;
  OdometryNoise noise;
  noise.alpha_trans = 0.05;
  noise.alpha_rot = 0.05;
  noise.drift_rot = 0.02;
  DriveSimulator drive(world, kOfficeLoop, laser, noise, 0.5, 1.0, 7);
  Slam slam(testParams());
  const OfflineRun run = runSlamOnDrive(slam, drive, laser, 30.0);
  ASSERT_GT(run.estimate.size(), 50u);
  const Score s = evaluate(slam, run, world);
  const double odom_ate = absoluteTrajectoryRmse(run.odometry, run.truth, alignTrajectories(run.odometry, run.truth));
  RecordProperty("precision", std::to_string(s.map.precision));
  std::printf("precision %.3f recall %.3f ATE %.3f m (odometry %.3f m), loop closures %d/%d, weak %d\n",
              s.map.precision, s.map.recall, s.ate, odom_ate, slam.stats().loop_closures, slam.stats().loop_attempts,
              slam.stats().weak_matches);
  EXPECT_GE(s.map.precision, 0.9);
  EXPECT_GE(s.map.recall, 0.9);
  EXPECT_LT(s.ate, 0.05);
  EXPECT_GT(odom_ate, 3 * s.ate);
  // map -> odom is the accumulated correction: it takes the last scan's odometry pose onto where
  // the last scan was tracked.
  const Pose2D tracked = compose(slam.keyframes().back().pose, slam.lastScanInKeyframe());
  const Pose2D via_tf = compose(slam.mapToOdom(), run.last_odom);
  EXPECT_NEAR(via_tf.x, tracked.x, 1e-9);
  EXPECT_NEAR(via_tf.y, tracked.y, 1e-9);
  EXPECT_NEAR(wrapAngle(via_tf.theta - tracked.theta), 0.0, 1e-9);
}

namespace
{
// The front end drifts where the laser gives no valid reading for a while (dazzled by the sun, its
// window misted over): the odometry alone, strongly noisy here, places those scans, and with tiny
// local maps the front end carries on from wherever they ended. Twice for 6 s: in the east room
// south-west corner and on the way back to the door. (With the laser always seeing walls, this
// front end did not drift in the office: ATE 0.005 m over the loop.)
struct DriftRun
{
  Slam slam;
  OfflineRun run;
  Score score;
};

DriftRun driveOfficeWithDrift(bool loop_closure)
{
  const GridMap world = officeWorld(0.01);
  const LaserSpec laser;
  DriveSimulator drive(world, kOfficeLoop, laser, odometryNoise(0.15, 0.03), 0.5, 1.0, 1);
  SlamParams p = testParams();
  p.loop_closure = loop_closure;
  p.local_map_scans = 4;
  DriftRun r{Slam(p), {}, {}};
  r.run = runSlamOnDrive(r.slam, drive, laser, 8.0, nullptr, nullptr,
                         [](DriveSample& s)
                         {
                           // Every beam NaN (REP 117: no valid reading), not +inf (no return within
                           // range, which would clear space through the walls).
                           if ((s.stamp >= 30.0 && s.stamp < 36.0) || (s.stamp >= 70.0 && s.stamp < 76.0))
                             std::fill(s.ranges.begin(), s.ranges.end(), std::numeric_limits<float>::quiet_NaN());
                         });
  r.score = evaluate(r.slam, r.run, world);
  return r;
}

// The drives are shared by the tests below (each takes seconds).
const DriftRun& closedDriftRun()
{
  static const DriftRun r = driveOfficeWithDrift(true);
  return r;
}

const DriftRun& openDriftRun()
{
  static const DriftRun r = driveOfficeWithDrift(false);
  return r;
}
}  // namespace

TEST(Slam, LoopClosureImprovesMapUnderOdometryDrift)
{
  // Closing the loop must pull the trajectory and the map back together.
  const Score& open = openDriftRun().score;
  const Score& closed = closedDriftRun().score;
  const SlamStats& s_closed = closedDriftRun().slam.stats();
  std::printf(
      "without closure: precision %.3f recall %.3f ATE %.3f; with: precision %.3f recall %.3f ATE %.3f "
      "(%d closures, %d held for confirmation, %d of them dropped)\n",
      open.map.precision, open.map.recall, open.ate, closed.map.precision, closed.map.recall, closed.ate,
      s_closed.loop_closures, s_closed.loop_held, s_closed.loop_unconfirmed);
  // Measured 2026-11-30: ATE 0.299 m, precision 0.409 open; 0.036 m, 0.952 closed (23 closures,
  // one held and confirmed). The drive's seeds 2-4: open 0.249 / 0.134 / 0.066 m, closed 0.035 /
  // 0.034 / 0.033 m (none held).
  EXPECT_GT(s_closed.loop_closures, 0);
  // The drift here needs corrections beyond loop_confirm_correction: they were held, then confirmed.
  EXPECT_GT(s_closed.loop_held, 0);
  EXPECT_LT(s_closed.loop_unconfirmed, s_closed.loop_held);
  EXPECT_LT(closed.ate, 0.5 * open.ate);
  EXPECT_GT(closed.map.precision, open.map.precision + 0.2);
  EXPECT_GT(closed.map.recall, open.map.recall + 0.1);
  EXPECT_GE(closed.map.precision, 0.85);
  EXPECT_GE(closed.map.recall, 0.9);
}

// Confirmation guards against a one-off match in a repetitive place; a unique match (no second
// place within loop_unique_ratio of its score) that is strong and not large needs none, so that
// a true closure found where a route ends is applied (slam_loop_closure seed 15).
TEST(Slam, OnlyLargeClosuresOrOnesThatAreNotUniqueAndStrongWaitForConfirmation)
{
  SlamParams p;  // loop_confirm_correction 0.15, loop_large_correction 0.4, loop_min_score_large 0.75
  EXPECT_FALSE(closureNeedsConfirmation(p, 0.1, 0.6, false));  // small: applied at once
  EXPECT_TRUE(closureNeedsConfirmation(p, 0.2, 0.9, false));   // not known to be unique
  EXPECT_FALSE(closureNeedsConfirmation(p, 0.2, 0.9, true));
  EXPECT_TRUE(closureNeedsConfirmation(p, 0.2, 0.7, true));  // unique but weak
  EXPECT_TRUE(closureNeedsConfirmation(p, 0.5, 1.0, true));  // unique and strong but large
  p.loop_confirm_correction = 0.0;                           // confirmation off
  EXPECT_FALSE(closureNeedsConfirmation(p, 0.5, 0.6, false));
}

TEST(Slam, TheMapAfterLoopClosuresShowsEveryKeyframeWhereTheGraphPutIt)
{
  // Closures move keyframes and the global map is re-rendered only when read: what map() returns
  // must be every keyframe's scan at its final pose, not the map as it was drawn before a closure.
  const Slam& slam = closedDriftRun().slam;
  ASSERT_GT(slam.stats().loop_closures, 0);
  OccupancyGrid expected(slam.params().grid);
  for (const Keyframe& k : slam.keyframes())
    expected.insertScan(k.pose, k.scan);
  const GridMap want = expected.toGridMap(slam.params().occ_thresh), got = slam.map();
  int known = 0;
  for (int cy = 0; cy < got.info.height; ++cy)
    for (int cx = 0; cx < got.info.width; ++cx)
    {
      const Point2D c = got.cellCenter(cx, cy);
      int wx, wy;
      const int8_t w = want.worldToCell(c.x, c.y, wx, wy) ? want.at(wx, wy) : -1;
      ASSERT_EQ(got.at(cx, cy), w) << "cell " << cx << " " << cy;
      known += w >= 0;
    }
  EXPECT_GT(known, 1000);
}

TEST(Slam, AGlobalMatchsCandidateIsAKeyframeOfTheMapItWasMatchedAgainst)
{
  // A first corridor along y = 1 (keyframes 0-9), a long tour, and a return drawn 0.9 m off,
  // over the corridor, by a drifted estimate (keyframes 100-119). A global search at keyframe 119
  // matched against the keyframes [0, 100) puts the robot at (3, 0): its closure must tie it to
  // the corridor's keyframe 3, not to the return's own keyframe 105 drawn nearer that pose.
  std::vector<Keyframe> kfs(120);
  for (int i = 0; i < 120; ++i)
  {
    kfs[static_cast<size_t>(i)].travelled = i < 100 ? i : 1000.0 + (i - 100);
    kfs[static_cast<size_t>(i)].pose = i < 10    ? Pose2D{double(i), 1.0, 0.0}
                                       : i < 100 ? Pose2D{100.0 + i, 50.0, 0.0}
                                                 : Pose2D{double(i - 102), 0.1, 0.0};
  }
  const Pose2D matched{3.0, 0.0, 0.0};
  EXPECT_EQ(nearestLoopCandidate(kfs, 119, matched, 119, 4.0, 8.0), 105);  // every keyframe 8 m back
  EXPECT_EQ(nearestLoopCandidate(kfs, 119, matched, 100, 4.0, 8.0), 3);    // the coarse map's only
  EXPECT_EQ(nearestLoopCandidate(kfs, 119, matched, 119, 4.0, 15.0), 3);   // 105 is 14 m back
  EXPECT_EQ(nearestLoopCandidate(kfs, 119, Pose2D{50.0, 0.0, 0.0}, 119, 4.0, 8.0), -1);
}

TEST(Slam, LoopCandidatesAreTheNearestKeyframeOfEachEarlierPass)
{
  // A corridor along y = 0 driven east (keyframes 0-19, a metre apart), west 0.5 m beside it
  // (20-39) and east again 1 m beside it (40-59), then keyframe 60 at (5, 0.2).
  std::vector<Keyframe> kfs(61);
  for (int i = 0; i < 60; ++i)
  {
    const int pass = i / 20, along = i % 20;
    kfs[static_cast<size_t>(i)].travelled = i;
    kfs[static_cast<size_t>(i)].pose =
        Pose2D{pass == 1 ? 19.0 - along : double(along), 0.5 * pass, pass == 1 ? M_PI : 0.0};
  }
  kfs[60].travelled = 60.0;
  kfs[60].pose = Pose2D{5.0, 0.2, 0.0};
  // Nearest first, then the nearest keyframe more than 10 from each chosen one: one per pass.
  EXPECT_EQ(loopCandidatesByPass(kfs, 60, kfs[60].pose, 60, 4.0, 8.0, 10, 4), (std::vector<int>{5, 34, 45}));
  EXPECT_EQ(loopCandidatesByPass(kfs, 60, kfs[60].pose, 60, 4.0, 8.0, 10, 2), (std::vector<int>{5, 34}));
  // Within 10 m of path: the third pass is too recent.
  EXPECT_EQ(loopCandidatesByPass(kfs, 60, kfs[60].pose, 60, 4.0, 20.0, 10, 3), (std::vector<int>{5, 34}));
  // With no separation, the nearest keyframes whichever pass they are on.
  EXPECT_EQ(loopCandidatesByPass(kfs, 60, kfs[60].pose, 60, 4.0, 8.0, 0, 4), (std::vector<int>{5, 34, 45, 4}));
  EXPECT_EQ(nearestLoopCandidate(kfs, 60, kfs[60].pose, 60, 4.0, 8.0), 5);
  EXPECT_TRUE(loopCandidatesByPass(kfs, 60, Pose2D{50.0, 0.0, 0.0}, 60, 4.0, 8.0, 10, 3).empty());
}

TEST(Slam, MapConsistencyRanksMapsAsGroundTruthDoes)
{
  // The final optimisation is judged without ground truth, by how well the keyframes agree with
  // the map they render: the drifting open-loop map must read as less consistent.
  const double open = openDriftRun().slam.mapConsistency(), closed = closedDriftRun().slam.mapConsistency();
  std::printf("map consistency: open loop %.3f (precision %.3f), closed %.3f (precision %.3f)\n", open,
              openDriftRun().score.map.precision, closed, closedDriftRun().score.map.precision);
  EXPECT_LT(open, closed);
}

TEST(Slam, FinalOptimizationTiesEveryRevisitAndTightensTheTrajectory)
{
  // Online, each revisit is tied to one candidate now and then; the final optimisation ties
  // every keyframe to each earlier pass.
  Slam slam = closedDriftRun().slam;
  OfflineRun run = closedDriftRun().run;
  const Score& online = closedDriftRun().score;
  const int closures = slam.stats().loop_closures;
  slam.runFinalOptimization();
  run.estimate.clear();
  for (const Keyframe& k : slam.keyframes())
    run.estimate.push_back(k.pose);
  const Score final = evaluate(slam, run, officeWorld(0.01));
  std::printf(
      "online: precision %.3f recall %.3f ATE %.4f (%d closures); final: precision %.3f recall %.3f "
      "ATE %.4f (%d revisit edges, %d dropped; map consistency %.3f -> %.3f)\n",
      online.map.precision, online.map.recall, online.ate, closures, final.map.precision, final.map.recall, final.ate,
      slam.stats().final_edges, slam.stats().final_edges_dropped, slam.stats().final_consistency_before,
      slam.stats().final_consistency_after);
  // Every pass through the start, the door and the east room's west side is tied (2026-11-30:
  // 120 edges within 4 m, half the 8 m usable range, against 23 closures online), and the
  // trajectory and the map tighten against the truth (ATE 3.59 -> 3.43 cm, map precision 0.952 ->
  // 0.972). How well the keyframes agree with the map they render is not asserted: it fell (0.975
  // -> 0.970) while both improved; on the old route, through the furniture, it rose (0.947 ->
  // 0.950) while precision fell (0.952 -> 0.946). A few thousandths of it say nothing either way
  // (runFinalOptimization); MapConsistencyRanksMapsAsGroundTruthDoes is what it is for.
  EXPECT_GT(slam.stats().final_edges, closures);
  EXPECT_EQ(slam.stats().final_edges_dropped, 0);
  EXPECT_LT(final.ate, online.ate);
  EXPECT_GE(final.map.precision, online.map.precision);
  EXPECT_GE(final.map.precision, 0.85);
  EXPECT_GE(final.map.recall, 0.9);
  // map -> odom still takes the last scan's odometry onto its (moved) tracked pose.
  const Pose2D tracked = compose(slam.keyframes().back().pose, slam.lastScanInKeyframe());
  const Pose2D via_tf = compose(slam.mapToOdom(), run.last_odom);
  EXPECT_NEAR(via_tf.x, tracked.x, 1e-9);
  EXPECT_NEAR(via_tf.y, tracked.y, 1e-9);
}

TEST(Slam, PlaceScansPullsATrackedScanOntoTheKeyframesAroundIt)
{
  // After the final optimisation a scan tracked a few centimetres off is matched against the
  // keyframes around its own. Here each scan is a keyframe's own, handed over 7 cm and 1 degree
  // off that keyframe: it must come back to it.
  Slam slam = closedDriftRun().slam;
  slam.runFinalOptimization();
  const std::vector<Keyframe>& kfs = slam.keyframes();
  const Pose2D off{0.06, -0.04, 0.017};
  std::vector<ScanToPlace> scans;
  for (size_t k = 0; k < kfs.size(); k += 5)
    scans.push_back({static_cast<int>(k), off, kfs[k].match_points});
  scans.push_back({3, off, {}});  // no points: stays where tracking put it
  const std::vector<Pose2D> placed = slam.placeScans(scans);
  ASSERT_EQ(placed.size(), scans.size());
  // A scan is either matched (then near its keyframe: the map is of the keyframes around it,
  // which after optimisation lie within a centimetre or so of it) or, where the match is weak or
  // leaves a direction free (the office's corridors), left exactly where it was handed over.
  std::vector<double> errors;
  int left = 0;
  for (size_t i = 0; i + 1 < scans.size(); ++i)
  {
    const Pose2D& k = kfs[static_cast<size_t>(scans[i].keyframe)].pose;
    const Pose2D e = between(k, placed[i]);
    if (std::abs(e.x - off.x) < 1e-9 && std::abs(e.y - off.y) < 1e-9 && std::abs(e.theta - off.theta) < 1e-9)
      ++left;
    else
      errors.push_back(std::hypot(e.x, e.y));
  }
  ASSERT_FALSE(errors.empty());
  std::sort(errors.begin(), errors.end());
  const double median = errors[errors.size() / 2], p90 = errors[errors.size() * 9 / 10];
  std::printf(
      "placeScans: %zu of %zu scans matched, translation error median %.4f m, 90th percentile %.4f, "
      "worst %.4f (handed over 0.072 m off)\n",
      errors.size(), scans.size() - 1, median, p90, errors.back());
  // 2026-11-27, the grid match alone: 40 of 48 matched, median 0.0094 m, 90th percentile 0.0167,
  // worst 0.0267. 2026-11-28, with the point-to-line step (final_scan_point_to_line), which also
  // pins the corridors' scans across them: 48 of 48, median 0.0068, 90th percentile 0.0121,
  // worst 0.0194. 2026-11-30, the route clear of the furniture: 51 of 51, 0.0063, 0.0118, 0.0196.
  EXPECT_GE(errors.size(), 3 * (scans.size() - 1) / 4);
  EXPECT_LT(median, 0.009);
  EXPECT_LT(p90, 0.016);
  EXPECT_LT(errors.back(), 0.036);  // half the offset it was handed over with
  const Pose2D kept = compose(kfs[3].pose, off);
  EXPECT_NEAR(placed.back().x, kept.x, 1e-12);
  EXPECT_NEAR(placed.back().theta, kept.theta, 1e-12);

  // A scan whose heading tracking kept while the robot turned (odometry 0.33 s stale at 1.5
  // rad/s on Intel): 0.45 rad off, beyond the small window, it is found by the wide one. Where
  // the match leaves a direction free, its heading is still taken: 2026-11-30, 26 of 26 came back
  // (17 while such a scan stayed where it was handed over: the route passes 0.5 m from long walls).
  std::vector<ScanToPlace> turned;
  for (size_t k = 0; k < kfs.size(); k += 10)
    turned.push_back({static_cast<int>(k), {0.02, -0.01, 0.45}, kfs[k].match_points});
  const std::vector<Pose2D> found = slam.placeScans(turned);
  int back = 0;
  for (size_t i = 0; i < turned.size(); ++i)
  {
    const Pose2D e = between(kfs[static_cast<size_t>(turned[i].keyframe)].pose, found[i]);
    back += std::abs(e.theta) < 0.02 && std::hypot(e.x, e.y) < 0.03;
  }
  std::printf("placeScans: %d of %zu scans handed over 0.45 rad off came back within 0.02 rad\n", back, turned.size());
  EXPECT_GE(back, static_cast<int>(3 * turned.size() / 4));

  // Off (final_scan_keyframes 0), every scan stays where tracking put it.
  SlamParams p = slam.params();
  p.final_scan_keyframes = 0;
  Slam off_slam(p);
  off_slam.addScan(0.0, Pose2D{}, kfs.front().scan);
  const std::vector<Pose2D> kept_all = off_slam.placeScans({{0, off, kfs.front().match_points}});
  EXPECT_NEAR(kept_all[0].x, off.x, 1e-12);
  EXPECT_NEAR(kept_all[0].y, off.y, 1e-12);
  // A keyframe that does not exist is the caller's error.
  EXPECT_THROW(slam.placeScans({{static_cast<int>(kfs.size()), off, {}}}), std::out_of_range);
}

namespace
{
// A slow laser, 2.5 Hz and 181 beams: at 0.5 m/s a scan every 0.2 m, so that odometry reporting a
// step backwards puts the prediction 0.4 m off, beyond the matcher's 0.3 m window.
LaserSpec slowLaser()
{
  LaserSpec laser;
  laser.rate = 2.5;
  laser.beams = 181;
  return laser;
}

// The drive's odometry as a robot whose encoders report each step's translation backwards while
// `reversed` says so (the rotation as measured).
class BackwardSteps
{
public:
  Pose2D next(const Pose2D& odom, bool reversed)
  {
    if (!started_)
      reported_ = last_ = odom;
    started_ = true;
    Pose2D step = between(last_, odom);
    last_ = odom;
    if (reversed)
      step = Pose2D{-step.x, -step.y, step.theta};
    reported_ = compose(reported_, step);
    return reported_;
  }

private:
  Pose2D reported_, last_;
  bool started_ = false;
};

// The office loop with a 2.5 Hz, 181-beam laser whose odometry, between 15 s and 20 s, reports
// each step's translation backwards while the robot drives on at 0.5 m/s: each scan's odometry
// prediction lands 0.4 m from where the scan was taken, beyond the matcher's 0.3 m window (as
// FR079's odometry did for 10 s, at 0.2 m a scan).
struct BackwardOdometryRun
{
  Score score;
  int motion_fallbacks = 0;
};

// The office loop with the 2.5 Hz laser and a little odometry noise, the odometry as `odometry`
// makes it (and the ranges as `sensed` edits them): the drive of the tests of odometry gone wrong.
Score driveOfficeSlowly(Slam& slam, const std::function<Pose2D(const DriveSample&)>& odometry,
                        const std::function<void(DriveSample&)>& sensed = nullptr)
{
  const GridMap world = officeWorld(0.01);
  const LaserSpec laser = slowLaser();
  OdometryNoise noise;
  noise.alpha_trans = 0.02;
  noise.alpha_rot = 0.02;
  DriveSimulator drive(world, kOfficeLoop, laser, noise, 0.5, 1.0, 5);
  const OfflineRun run = runSlamOnDrive(slam, drive, laser, 30.0, odometry, nullptr, sensed);
  return evaluate(slam, run, world);
}

// People standing 0.5-2 m from the laser, somewhere else each scan: each beam ends on one with
// probability `share` where one stands before the wall (the Radish logs' museum and convention
// halls). Seeded: the same crowd on every run.
std::function<void(DriveSample&)> aCrowd(double share, unsigned seed)
{
  struct Crowd
  {
    Crowd(double share, unsigned seed) : rng(seed), on_a_person(share) {}
    std::mt19937 rng;
    std::uniform_real_distribution<float> person{0.5f, 2.0f};
    std::bernoulli_distribution on_a_person;
  };
  auto crowd = std::make_shared<Crowd>(share, seed);
  return [crowd](DriveSample& s)
  {
    for (float& r : s.ranges)
    {
      const float d = crowd->person(crowd->rng);
      if (crowd->on_a_person(crowd->rng) && d < r)
        r = d;
    }
  };
}

// The odometry reports each step backwards for 5 s from `from`.
BackwardOdometryRun driveWithBackwardOdometry(double from, bool motion_fallback, double window_motion_scale = 0.0)
{
  SlamParams p = testParams();
  p.track_motion_fallback = motion_fallback;
  p.search_window_motion_scale = window_motion_scale;
  Slam slam(p);
  BackwardSteps odometry;
  const Score score = driveOfficeSlowly(
      slam, [&](const DriveSample& s) { return odometry.next(s.odom, s.stamp >= from && s.stamp < from + 5.0); });
  return {score, slam.stats().motion_fallbacks};
}
}  // namespace

// The odometry reverses from 12 s, halfway up the loop's second leg: the map's last step is the
// robot's true motion, which the fallback carries on.
TEST(Slam, TrackingFollowsTheMapWhereTheOdometryReportsTheWrongDirection)
{
  const BackwardOdometryRun without = driveWithBackwardOdometry(12.0, false),
                            with = driveWithBackwardOdometry(12.0, true);
  std::printf(
      "without the motion fallback: ATE %.3f m, precision %.3f; with: ATE %.3f m, precision %.3f "
      "(%d scans placed by it)\n",
      without.score.ate, without.score.map.precision, with.score.ate, with.score.map.precision, with.motion_fallbacks);
  // Measured 2026-11-30: ATE 1.487 m, precision 0.187 without; 0.026 m, 0.994 with (13 scans
  // placed by it). Where the reversal begins just before a turn in place (from 16 s: 0.885 ->
  // 0.803 m) or just after one (from 10 s: nothing placed), the map's last step is a turn when the
  // robot drives on, there is no motion to carry on, and the fallback does not apply; nor once a
  // scan has followed the odometry, whose step the map's then points along. The window that grows
  // with the odometry's step does (next test). On FR079's perturbed replays the fallback recovered
  // all of it (worst relation 0.565 -> 0.196 m); README, known limits.
  EXPECT_EQ(without.motion_fallbacks, 0);
  EXPECT_GE(with.motion_fallbacks, 5);
  EXPECT_LT(with.score.ate, 0.35 * without.score.ate);
  EXPECT_GT(with.score.map.precision, without.score.map.precision + 0.3);
}

// The odometry reverses from 10 s, as the robot sets off after its first turn in place, where the
// motion fallback has no step to carry on. With the linear window grown to 2.5 odometry steps
// (config/slam.yaml) the scan the odometry put 0.4 m behind lies within 0.5 m, so each scan is
// found where it was taken, also after one has followed the odometry.
TEST(Slam, AWindowThatGrowsWithTheOdometrysStepFindsScansTheOdometryPutBehind)
{
  const BackwardOdometryRun fallback = driveWithBackwardOdometry(10.0, true),
                            grown = driveWithBackwardOdometry(10.0, true, 2.5);
  std::printf("motion fallback alone: ATE %.3f m, precision %.3f; with the grown window: ATE %.3f m, precision %.3f\n",
              fallback.score.ate, fallback.score.map.precision, grown.score.ate, grown.score.map.precision);
  // Measured 2026-11-30: ATE 1.417 -> 0.025 m, precision 0.208 -> 0.995.
  EXPECT_LT(grown.score.ate, 0.25 * fallback.score.ate);
  EXPECT_GT(grown.score.map.precision, fallback.score.map.precision + 0.3);
}

namespace
{
// The office loop with the 2.5 Hz laser, its odometry's heading swung `swing` and then twice that
// for two scans from 20 s, and back (a log that writes odometry and scans in bursts, as Intel's
// does, pairs scans with odometry from the wrong moment). Each swing is within the matcher's
// 0.35 rad window, so both scans are found where they were taken; the scan after them, predicted
// from the second, lies twice the swing away, outside it.
struct SwingRun
{
  Score score;
  int undone = 0;
};

SwingRun driveWithHeadingSwing(bool undo_correction, double swing)
{
  SlamParams p = testParams();
  p.track_undo_correction = undo_correction;
  // The wider heading search where nothing matched finds that scan as well (2026-11-30, with the
  // correction kept: ATE 0.028 m, precision 0.988); off, to show what undoing the correction does.
  p.track_retry_window_angular = 0.0;
  Slam slam(p);
  int swung = 0;
  const Score score = driveOfficeSlowly(slam,
                                        [&](const DriveSample& s)
                                        {
                                          if (s.stamp < 20.0 || swung >= 2)
                                            return s.odom;
                                          ++swung;
                                          return compose(s.odom, Pose2D{0.0, 0.0, swung * swing});
                                        });
  return {score, slam.stats().corrections_undone};
}
}  // namespace

TEST(Slam, AScanAfterAFarCorrectionIsAlsoMatchedWithoutIt)
{
  const SwingRun kept = driveWithHeadingSwing(false, 0.25), undone = driveWithHeadingSwing(true, 0.25);
  std::printf(
      "odometry heading swung 0.25 then 0.5 rad for two scans: the correction kept: ATE %.3f m, precision %.3f; "
      "also matched without it: ATE %.3f m, precision %.3f (%d scans placed so)\n",
      kept.score.ate, kept.score.map.precision, undone.score.ate, undone.score.map.precision, undone.undone);
  // Measured 2026-11-30: ATE 0.264 m, precision 0.421 with the correction kept (the map turned
  // 0.5 rad from 21 s on); 0.028 m, 0.986 also matched without it (one scan placed so).
  EXPECT_EQ(kept.undone, 0);
  EXPECT_GE(undone.undone, 1);
  EXPECT_LT(undone.score.ate, 0.25 * kept.score.ate);
  EXPECT_GT(undone.score.map.precision, kept.score.map.precision + 0.3);
}

namespace
{
// The office loop with a 10 Hz laser and odometry that reaches the mapper in bursts: each fifth
// scan brings the odometry up to date, the four between repeat it (Intel's log, its odometry
// 0.1 s late, pairs scans so). Turning in place at 1 rad/s, the held scans are 0.1 rad from
// their prediction, within the matcher's 0.35 rad window, but the scan that catches up is
// predicted 0.5 rad on, 0.4 rad from where it was taken, outside it.
struct BurstRun
{
  Score score;
  int turn_fallbacks = 0;
};

BurstRun driveWithOdometryInBursts(bool turn_fallback)
{
  SlamParams p = testParams();
  p.track_turn_fallback = turn_fallback;
  // The wider heading search where nothing matched finds the catching-up scans as well
  // (2026-11-30, without the map's turn: ATE 0.051 m, precision 0.966); off, to show what the
  // map's turn does.
  p.track_retry_window_angular = 0.0;
  Slam slam(p);
  const GridMap world = officeWorld(0.01);
  LaserSpec laser;
  laser.rate = 10.0;
  laser.beams = 181;
  OdometryNoise noise;
  noise.alpha_trans = 0.02;
  noise.alpha_rot = 0.02;
  DriveSimulator drive(world, kOfficeLoop, laser, noise, 0.5, 1.0, 5);
  int scan = 0;
  Pose2D held;
  const OfflineRun run = runSlamOnDrive(slam, drive, laser, 30.0,
                                        [&](const DriveSample& s)
                                        {
                                          if (scan++ % 5 == 0)
                                            held = s.odom;
                                          return held;
                                        });
  return {evaluate(slam, run, world), slam.stats().turn_fallbacks};
}
}  // namespace

TEST(Slam, TrackingFollowsTheMapsTurnWhereTheOdometryCatchesUpInBursts)
{
  const BurstRun without = driveWithOdometryInBursts(false), with = driveWithOdometryInBursts(true);
  std::printf(
      "odometry in bursts of five scans: without the map's turn: ATE %.3f m, precision %.3f; with it: ATE %.3f m, "
      "precision %.3f (%d scans placed by it)\n",
      without.score.ate, without.score.map.precision, with.score.ate, with.score.map.precision, with.turn_fallbacks);
  // Measured 2026-11-30: ATE 0.949 m, precision 0.176 without (each turn's catching-up scans
  // predicted 0.4 rad off); 0.040 m, 0.972 with it (22 scans placed by it).
  EXPECT_EQ(without.turn_fallbacks, 0);
  EXPECT_GE(with.turn_fallbacks, 5);  // the loop turns in place 17 times
  EXPECT_LT(with.score.ate, 0.1 * without.score.ate);
  EXPECT_GT(with.score.map.precision, without.score.map.precision + 0.5);
}

namespace
{
// The office loop as above, the odometry reporting each step backwards for the `reversed` scans
// that follow the first accepted loop closure (FR079 replayed with every other scan: a closure at
// 304 s, in the 10 s its odometry drove the wrong way). How far each of those scans is from where
// the closure's keyframe says it is, against the truth: the motion from the map's last step, which
// the closure moved with both its poses, must carry the scans past the odometry's reversal.
struct AfterClosureRun
{
  double worst = 0.0;      // m, the scans' worst error relative to the closure's keyframe
  double travelled = 0.0;  // m, the truth's motion over those scans
  int scans = 0;
  int motion_fallbacks = 0;
};

AfterClosureRun reverseAfterClosure(int reversed, unsigned seed)
{
  const GridMap world = officeWorld(0.01);
  const LaserSpec laser = slowLaser();
  OdometryNoise noise;
  noise.alpha_trans = 0.05;
  noise.alpha_rot = 0.05;
  noise.drift_rot = 0.05;
  DriveSimulator drive(world, kOfficeLoop, laser, noise, 0.5, 1.0, seed);
  Slam slam(testParams());
  BackwardSteps odometry;
  Pose2D anchor, anchor_truth;
  int left = -1;  // scans still to reverse once the closure is in; -1 before it
  AfterClosureRun r;
  runSlamOnDrive(
      slam, drive, laser, 30.0, [&](const DriveSample& s) { return odometry.next(s.odom, left > 0); },
      [&](const DriveSample& s, ScanOutcome)
      {
        if (left < 0 && slam.stats().loop_closures > 0)
        {
          left = reversed;
          anchor = slam.currentPose();
          anchor_truth = s.truth;
          return;
        }
        if (left <= 0)
          return;
        --left;
        const Pose2D error = between(between(anchor_truth, s.truth), between(anchor, slam.currentPose()));
        r.worst = std::max(r.worst, std::hypot(error.x, error.y));
        r.travelled = translationNorm(between(anchor_truth, s.truth));
        ++r.scans;
      });
  r.motion_fallbacks = slam.stats().motion_fallbacks;
  return r;
}
}  // namespace

TEST(Slam, TheMapsLastStepSurvivesALoopClosure)
{
  for (unsigned seed : {1u, 2u, 3u})
  {
    const AfterClosureRun r = reverseAfterClosure(3, seed);
    std::printf(
        "seed %u: %d scans reversed after the closure, %.2f m driven, worst error %.3f m (%d placed by the "
        "map's motion)\n",
        seed, r.scans, r.travelled, r.worst, r.motion_fallbacks);
    // Measured 2026-11-30: worst 0.021 / 0.005 / 0.021 m, every scan placed by the map's motion.
    // Before 52c8acb a closure dropped the step: 0.89 / 1.19 / 1.17 m, each scan a step behind
    // the last; and where the odometry's match succeeded at its window's edge the map's motion
    // was not tried (seed 2 and 3: 0.4 m from the first scan).
    ASSERT_EQ(r.scans, 3);
    EXPECT_GT(r.travelled, 0.5);  // the robot drove on: the reversal moved each prediction 0.4 m
    EXPECT_GE(r.motion_fallbacks, 3);
    EXPECT_LT(r.worst, 0.05);
  }
}

namespace
{
// mybot.world (mybot_gazebo_lite) shifted by 5 m: a 10 m square room with two boxes, a short wall
// and three round things (squares here).
GridMap mybotRoom()
{
  return makeWorld(10.0, 10.0, 0.01,
                   {
                       {7.25, 6.75, 7.75, 7.25},  // box_1
                       {2.0, 2.2, 3.0, 2.8},      // box_2 (turned 0.5 rad there)
                       {1.5, 7.42, 4.5, 7.58},    // partition
                       {7.7, 2.7, 8.3, 3.3},      // cylinder_1
                       {1.3, 5.3, 1.7, 5.7},      // cylinder_2
                       {4.6, 1.1, 5.4, 1.9},      // ball
                   });
}

// slam_loop_closure.test in the library: its route around the room twice, 3.5 m of usable range,
// local maps of 4 keyframes and its odometry noise. Crossing the middle of the room a scan keeps
// 7-14 points in reach at match_point_spacing.
Score driveMybotRoom(int match_min_points, unsigned seed)
{
  const GridMap world = mybotRoom();
  const LaserSpec laser;
  OdometryNoise noise;
  noise.alpha_trans = 0.15;
  noise.alpha_rot = 0.15;
  noise.drift_rot = 0.1;
  const std::vector<Point2D> route{{1.0, 1.0}, {9.0, 0.6}, {9.0, 4.5}, {6.0, 5.5}, {6.0, 9.0}, {1.0, 9.0},
                                   {1.0, 6.5}, {5.0, 6.5}, {5.0, 4.0}, {1.0, 4.0}, {1.0, 1.0}, {9.0, 0.6},
                                   {9.0, 4.5}, {6.0, 5.5}, {6.0, 9.0}, {1.0, 9.0}, {1.0, 1.0}};
  DriveSimulator drive(world, route, laser, noise, 0.4, 1.0, seed);
  SlamParams p = testParams();
  p.local_map_scans = 4;
  p.match_unobserved_weight = 0.5;  // config/slam.yaml's
  p.match_min_points = match_min_points;
  Slam slam(p);
  const OfflineRun run = runSlamOnDrive(slam, drive, laser, 3.5);
  return evaluate(slam, run, world);
}
}  // namespace

TEST(Slam, AScanWithFewPointsIsThinnedLess)
{
  for (unsigned seed : {2u, 5u})
  {
    const Score fixed = driveMybotRoom(0, seed), adaptive = driveMybotRoom(30, seed);
    std::printf("seed %u: match_min_points 0: ATE %.3f m, precision %.3f; 30: ATE %.3f m, precision %.3f\n", seed,
                fixed.ate, fixed.map.precision, adaptive.ate, adaptive.map.precision);
    // Measured 2026-11-29: seed 2 ATE 0.098 -> 0.062 m, precision 0.745 -> 0.885; seed 5 0.060
    // -> 0.036 m, 0.822 -> 0.892. Of seeds 1-6, 5 gained ATE (seed 6: 0.022 -> 0.024 m).
    EXPECT_LT(adaptive.ate, 0.75 * fixed.ate);
    EXPECT_GT(adaptive.map.precision, fixed.map.precision + 0.05);
  }
}

namespace
{
// The office loop through a crowd: in every scan most beams end on people standing 0.5-2 m from
// the laser, somewhere else each scan, so even the true pose scores low (the Radish logs' museum
// and convention halls). The odometry's heading drifts 0.1 rad a metre; loop closures are off, so
// the front end alone keeps the heading.
struct CrowdRun
{
  Score score;
  int weak = 0;  // keyframes the odometry alone placed
  int keyframes = 0;
};

CrowdRun driveThroughACrowd(double weak_match_min_score)
{
  const GridMap world = officeWorld(0.01);
  const LaserSpec laser;
  // The loop's first six legs, through the east room and back towards the door (24 m).
  const std::vector<Point2D> route(kOfficeLoop.begin(), kOfficeLoop.begin() + 7);
  DriveSimulator drive(world, route, laser, odometryNoise(0.05, 0.1), 0.5, 1.0, 3);
  SlamParams p = testParams();
  p.loop_closure = false;
  p.weak_match_min_score = weak_match_min_score;
  Slam slam(p);
  const OfflineRun run = runSlamOnDrive(slam, drive, laser, 8.0, nullptr, nullptr, aCrowd(0.75, 7));
  return {evaluate(slam, run, world), slam.stats().weak_matches, slam.stats().keyframes};
}
}  // namespace

// A match that scores under min_match_score is weak, and the odometry used to place the scan
// alone: in the crowd, two keyframes in five, and the map takes the odometry's drift. Matched
// again close to the prediction, a weak match still corrects the heading a little each scan.
// Measured 2026-11-30: ATE 0.195 m, precision 0.289 (42 of 106 keyframes by odometry) without;
// 0.048 m, 0.510 (none) with.
TEST(Slam, AWeakMatchCloseToThePredictionStillCorrectsIt)
{
  const CrowdRun odometry = driveThroughACrowd(0.0), weak = driveThroughACrowd(0.2);
  std::printf(
      "through a crowd: weak matches not used: ATE %.3f m, precision %.3f (%d of %d keyframes by odometry); "
      "used near the prediction: ATE %.3f m, precision %.3f (%d)\n",
      odometry.score.ate, odometry.score.map.precision, odometry.weak, odometry.keyframes, weak.score.ate,
      weak.score.map.precision, weak.weak);
  EXPECT_GT(odometry.weak, odometry.keyframes / 4);  // the premise: the crowd makes many matches weak
  EXPECT_LT(weak.weak, odometry.weak / 4);
  EXPECT_LT(weak.score.ate, 0.5 * odometry.score.ate);
  EXPECT_GT(weak.score.map.precision, odometry.score.map.precision + 0.1);
}

namespace
{
// The slow office drive (2.5 Hz laser) through the crowd of driveThroughACrowd, its odometry
// reporting each step backwards for 5 s from `from`: the odometry's prediction lands 0.4 m from
// where each scan was taken, and the motion fallback's match, near the truth, is weak as well.
Score reverseThroughACrowd(double from, double weak_match_min_score, int& motion_fallbacks)
{
  SlamParams p = testParams();
  p.weak_match_min_score = weak_match_min_score;
  Slam slam(p);
  BackwardSteps odometry;
  const Score score = driveOfficeSlowly(
      slam, [&](const DriveSample& s) { return odometry.next(s.odom, s.stamp >= from && s.stamp < from + 5.0); },
      aCrowd(0.6, 7));
  motion_fallbacks = slam.stats().motion_fallbacks;
  return score;
}
}  // namespace

// The motion fallback's prediction is matched with a weak match as the odometry's is: in a crowd
// the fallback's strict match fails too, and the scans then follow the reversed odometry. (A weak
// match near the odometry's own prediction is not taken while a rival contradicts it: Intel with
// its odometry 0.1 s late, bench_slam_robustness, 0.0376 -> 0.73 m when it was.)
TEST(Slam, AWeakMatchLetsTheMapsMotionOutrunReversedOdometryThroughACrowd)
{
  int strict_fallbacks = 0, weak_fallbacks = 0;
  const Score strict = reverseThroughACrowd(12.0, 0.0, strict_fallbacks),
              weak = reverseThroughACrowd(12.0, 0.2, weak_fallbacks);
  std::printf(
      "reversed odometry through a crowd: weak matches not used: ATE %.3f m, precision %.3f (%d scans placed by the "
      "motion fallback); used: ATE %.3f m, precision %.3f (%d)\n",
      strict.ate, strict.map.precision, strict_fallbacks, weak.ate, weak.map.precision, weak_fallbacks);
  // Measured 2026-11-30: ATE 0.839 m, precision 0.369 (6 scans) without; 0.010 m, 0.984 (13) with.
  // Weak matches near the odometry's prediction alone (not the rival's): 0.831 m.
  EXPECT_GT(weak_fallbacks, strict_fallbacks);
  EXPECT_LT(weak.ate, 0.1 * strict.ate);
  EXPECT_GT(weak.map.precision, strict.map.precision + 0.3);
}

namespace
{
// The drive's odometry as a base driver that stops sending new poses for one turn in place: the
// first turn from `from` s on (the truth's step has no translation), its steps are dropped, the
// reported pose stands still while the robot turns, and it carries on from there afterwards (the
// Radish Seattle log lost its odometry records for 3 s while the robot turned 80 degrees).
class StalledTurn
{
public:
  explicit StalledTurn(double from) : from_(from) {}
  Pose2D next(const DriveSample& s)
  {
    if (!started_)
    {
      reported_ = last_odom_ = s.odom;
      last_truth_ = s.truth;
      started_ = true;
    }
    const Pose2D step = between(last_odom_, s.odom), truth_step = between(last_truth_, s.truth);
    last_odom_ = s.odom;
    last_truth_ = s.truth;
    const bool turning_in_place = translationNorm(truth_step) < 1e-3 && std::abs(truth_step.theta) > 1e-3;
    if (s.stamp >= from_ && turning_in_place && !over_)
    {
      stalled_ += std::abs(truth_step.theta);
      return reported_;
    }
    over_ = stalled_ > 0.0;
    reported_ = compose(reported_, step);
    return reported_;
  }
  double stalled() const { return stalled_; }  // rad the robot turned while the odometry stood still

private:
  double from_;
  Pose2D reported_, last_odom_, last_truth_;
  bool started_ = false, over_ = false;
  double stalled_ = 0.0;
};

struct StallRun
{
  Score score;
  double stalled = 0.0;
  int stall_matches = 0;
};

// The office loop with a 1 Hz laser (the Radish logs keep a scan a metre), the odometry as
// StalledTurn reports it: the robot turns a radian between two scans, beyond the matcher's
// 0.35 rad window around a prediction that stood still.
StallRun driveWithAStalledTurn(double from, bool stall_search)
{
  SlamParams p = testParams();
  p.track_stall_search = stall_search;
  Slam slam(p);
  const GridMap world = officeWorld(0.01);
  LaserSpec laser = slowLaser();
  laser.rate = 1.0;
  OdometryNoise noise;
  noise.alpha_trans = 0.02;
  noise.alpha_rot = 0.02;
  DriveSimulator drive(world, kOfficeLoop, laser, noise, 0.5, 1.0, 5);
  StalledTurn odometry(from);
  const OfflineRun run =
      runSlamOnDrive(slam, drive, laser, 30.0, [&](const DriveSample& s) { return odometry.next(s); });
  return {evaluate(slam, run, world), odometry.stalled(), slam.stats().stall_matches};
}
}  // namespace

TEST(Slam, TheScansFindTheTurnTheOdometryMissedWhileItStoodStill)
{
  for (const double from : {0.0, 30.0})
  {
    const StallRun without = driveWithAStalledTurn(from, false), with = driveWithAStalledTurn(from, true);
    std::printf(
        "odometry standing still for a turn of %.2f rad from %.0f s: without the search in every heading: ATE %.3f "
        "m, precision %.3f; with it: ATE %.3f m, precision %.3f (%d scans placed by it)\n",
        with.stalled, from, without.score.ate, without.score.map.precision, with.score.ate, with.score.map.precision,
        with.stall_matches);
    // Measured 2026-11-30: the first turn (1.57 rad): ATE 0.692 m, precision 0.415 without; 0.032 m,
    // 0.987 with (2 scans placed by it). The turn after 30 s (1.42 rad): 2.153 m, 0.126; 0.029 m, 0.997 (1).
    EXPECT_GT(with.stalled, 1.0);
    EXPECT_EQ(without.stall_matches, 0);
    EXPECT_GE(with.stall_matches, 1);
    EXPECT_LT(with.score.ate, 0.1 * without.score.ate);
    EXPECT_GT(with.score.map.precision, without.score.map.precision + 0.3);
  }
}

namespace
{
// The office loop with the 2.5 Hz laser, its odometry one scan late (each scan paired with the
// odometry of the scan before, 0.4 s): turning in place at 1 rad/s, a turn's first scan is
// predicted 0.4 rad short, outside the matcher's 0.35 rad window, and each scan after it keeps
// that error until the turn is over.
struct LateRun
{
  Score score;
  int retry_matches = 0;
  int weak = 0;
};

LateRun driveWithOdometryOneScanLate(double retry_window_angular)
{
  SlamParams p = testParams();
  p.track_retry_window_angular = retry_window_angular;
  Slam slam(p);
  bool first = true;
  Pose2D before;
  const Score score = driveOfficeSlowly(slam,
                                        [&](const DriveSample& s)
                                        {
                                          const Pose2D late = first ? s.odom : before;
                                          first = false;
                                          before = s.odom;
                                          return late;
                                        });
  return {score, slam.stats().retry_matches, slam.stats().weak_matches};
}
}  // namespace

TEST(Slam, TheScansFindTheTurnALateOdometryCutShort)
{
  const LateRun without = driveWithOdometryOneScanLate(0.0), with = driveWithOdometryOneScanLate(0.7);
  std::printf(
      "odometry one scan (0.4 s) late: without the wider heading search: ATE %.3f m, precision %.3f (%d keyframes by "
      "odometry); with it: ATE %.3f m, precision %.3f (%d scans placed by it, %d keyframes by odometry)\n",
      without.score.ate, without.score.map.precision, without.weak, with.score.ate, with.score.map.precision,
      with.retry_matches, with.weak);
  // Measured 2026-11-30: ATE 0.786 m, precision 0.360 without; 0.036 m, 0.975 with (4 scans).
  EXPECT_EQ(without.retry_matches, 0);
  EXPECT_GE(with.retry_matches, 1);
  EXPECT_LT(with.score.ate, 0.1 * without.score.ate);
  EXPECT_GT(with.score.map.precision, without.score.map.precision + 0.5);
}

// A robot parked among people, its odometry repeating itself, its scans matching nothing: one
// search in every heading, not one a scan (each costs a full turn of the matcher).
TEST(Slam, AFailedSearchInEveryHeadingWaitsForAScanThatMatches)
{
  Slam slam(testParams());
  const LaserSpec laser;
  auto convert = [&](const std::vector<float>& r)
  {
    return convertRanges(r, laser.angle_min, laser.angleIncrement(), laser.range_min, laser.range_max, 30.0,
                         ScanGeometry{});
  };
  const GridMap world = officeWorld(0.01);
  const Pose2D parked{2.0, 2.0, 0.0};
  const auto seen = simulateScan(world, parked, laser.angle_min, laser.angleIncrement(), laser.beams, 30.0);
  ASSERT_EQ(slam.addScan(0.0, parked, convert(seen)), ScanOutcome::Processed);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> person(0.3f, 1.5f);
  auto crowd = [&]()
  {
    std::vector<float> ranges(static_cast<size_t>(laser.beams));
    for (float& r : ranges)
      r = person(rng);
    return convert(ranges);
  };
  double stamp = 0.0;
  for (int i = 0; i < 20; ++i)
    slam.addScan(stamp += 0.1, parked, crowd());
  EXPECT_EQ(slam.stats().stall_searches, 1);
  EXPECT_EQ(slam.stats().stall_matches, 0);
  // A scan that matches where the robot stands arms it again.
  slam.addScan(stamp += 0.1, parked, convert(seen));
  for (int i = 0; i < 5; ++i)
    slam.addScan(stamp += 0.1, parked, crowd());
  EXPECT_EQ(slam.stats().stall_searches, 2);
  EXPECT_NEAR(slam.currentPose().x, parked.x, 1e-9);
  EXPECT_NEAR(slam.currentPose().theta, parked.theta, 1e-9);
}

// Broken odometry (an overflowed encoder count, a driver's garbage) put a scan 1e308 m away, and
// the grid tried to grow to 2^58 bytes (scripts/fuzz). Such a scan is refused and the map kept,
// also one 2 km away: the map would pass kMaxMapSide cells a side.
TEST(Slam, OdometryBeyondTheMapsLimitsIsRefusedAndTheMapKept)
{
  const LaserSpec laser;
  const GridMap world = officeWorld(0.01);
  const auto ranges = simulateScan(world, {2, 2, 0}, laser.angle_min, laser.angleIncrement(), laser.beams, 30.0);
  const RangeScan scan = convertRanges(ranges, laser.angle_min, laser.angleIncrement(), laser.range_min,
                                       laser.range_max, 30.0, ScanGeometry{});
  Slam fresh(testParams());
  EXPECT_EQ(fresh.addScan(1.0, {2e6, 0, 0}, scan), ScanOutcome::BeyondMap);
  EXPECT_TRUE(fresh.keyframes().empty());
  Slam slam(testParams());
  ASSERT_EQ(slam.addScan(1.0, {}, scan), ScanOutcome::Processed);
  const GridMap before = slam.map();
  EXPECT_EQ(slam.addScan(1.1, {1e308, 0, 0}, scan), ScanOutcome::BeyondMap);
  EXPECT_EQ(slam.addScan(1.2, {0, -2000, 0}, scan), ScanOutcome::BeyondMap);
  EXPECT_EQ(slam.keyframes().size(), 1u);
  EXPECT_EQ(slam.map().data, before.data);
  EXPECT_EQ(slam.currentPose().x, 0.0);
  // The odometry back where it was: mapping goes on.
  EXPECT_EQ(slam.addScan(1.3, {0.3, 0, 0}, scan), ScanOutcome::Processed);
  EXPECT_EQ(slam.keyframes().size(), 2u);
}

TEST(Slam, BadInputIsReportedNotFatal)
{
  Slam slam(testParams());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const LaserSpec laser;
  auto convert = [&](const std::vector<float>& r)
  {
    return convertRanges(r, laser.angle_min, laser.angleIncrement(), laser.range_min, laser.range_max, 30.0,
                         ScanGeometry{});
  };
  EXPECT_EQ(slam.addScan(1.0, {}, convert(std::vector<float>(720, nan))), ScanOutcome::NoValidPoints);
  EXPECT_EQ(slam.addScan(1.1, {}, convert({})), ScanOutcome::NoValidPoints);
  const GridMap world = officeWorld(0.01);
  const auto ranges = simulateScan(world, {2, 2, 0}, laser.angle_min, laser.angleIncrement(), laser.beams, 30.0);
  EXPECT_EQ(slam.addScan(1.2, {}, convert(ranges)), ScanOutcome::Processed);
  EXPECT_EQ(slam.addScan(1.2, {}, convert(ranges)), ScanOutcome::OutOfOrder);
  EXPECT_EQ(slam.addScan(0.5, {}, convert(ranges)), ScanOutcome::OutOfOrder);
  EXPECT_EQ(slam.addScan(1.3, {0.01, 0, 0}, convert(ranges)), ScanOutcome::Skipped);
  EXPECT_EQ(slam.stats().keyframes, 1);
  const GridMap m = slam.map();
  EXPECT_GT(m.info.width, 0);
  for (int8_t v : m.data)
    EXPECT_TRUE(v == -1 || v == 0 || v == 100);
}

TEST(Slam, MatchesDoNotFallShortWhereTheLocalMapsReachEnds)
{
  // Exact odometry and a 2.5 m usable range down a 24 m corridor with pillars along its walls:
  // the scan-to-map chain alone must measure the distance. A local map ends where its keyframes'
  // range ended; a scan that reaches past that end along a wall used to be pulled back onto the
  // last mapped cells, and every match fell a little short. Measured 2026-11-27 (21.737 m true):
  // at 2.5 / 3.5 / 5 m usable range 20.086 / 21.384 / 21.613 m before, 21.670 / 21.813 / 21.813
  // now (21.813 at 8 m either way, where no scan reaches past its map; slam_loop_closure.test's
  // map was 1.5 % too small on ground-truth odometry).
  std::vector<Rect> pillars;
  for (double x = 2.0; x < 23.0; x += 2.5)
    pillars.push_back({x, x < 12.0 ? 0.1 : 3.6, x + 0.3, x < 12.0 ? 0.4 : 3.9});
  const GridMap world = makeWorld(24.0, 4.0, 0.01, pillars);
  const LaserSpec laser;
  DriveSimulator drive(world, {{1.0, 2.0}, {23.0, 2.0}}, laser, OdometryNoise{}, 0.5, 1.0, 1);
  SlamParams p = testParams();
  p.loop_closure = false;
  p.local_map_scans = 4;
  Slam slam(p);
  const OfflineRun run = runSlamOnDrive(slam, drive, laser, 2.5);
  ASSERT_GT(run.estimate.size(), 50u);
  const double travelled = run.estimate.back().x - run.estimate.front().x;
  const double truth = run.truth.back().x - run.truth.front().x;
  std::printf("distance down the corridor: %.3f m estimated, %.3f m true (%zu keyframes)\n", travelled, truth,
              run.estimate.size());
  EXPECT_NEAR(travelled / truth, 1.0, 0.005);
}

TEST(Slam, OdometryEdgesKeepTheHeadingOfTrustedOdometry)
{
  // Odometry whose heading is exact (an IMU holds it) but whose distances are noisy; a short usable
  // range and tiny local maps let the scan-match chain turn a little at every keyframe, even with
  // a strong heading prior in the matcher (0.062 rad here). With odometry edges the graph keeps
  // the odometry's heading and loop closures cannot bend it.
  const GridMap world = officeWorld(0.01);
  const LaserSpec laser;
  OdometryNoise noise;
  noise.alpha_trans = 0.15;
  auto worst_heading = [&](double odom_sigma_theta, Score* score)
  {
    DriveSimulator drive(world, kOfficeLoop, laser, noise, 0.5, 1.0, 4);
    SlamParams p = testParams();
    p.match_rotation_weight = 100.0;  // the matcher's own heading prior, as for the swerve robot
    p.local_map_scans = 4;
    if (odom_sigma_theta > 0.0)
    {
      p.odom_edge_sigma_xy = 0.1;
      p.odom_edge_sigma_theta = odom_sigma_theta;
    }
    Slam slam(p);
    const OfflineRun r = runSlamOnDrive(slam, drive, laser, 4.0);
    *score = evaluate(slam, r, world);
    double worst = 0.0;  // in the world frame: the map's heading is what far walls amplify
    for (size_t i = 0; i < r.estimate.size(); ++i)
      worst = std::max(worst, std::abs(wrapAngle(r.estimate[i].theta - r.truth[i].theta)));
    return worst;
  };
  Score chain, with_odom;
  const double chain_worst = worst_heading(0.0, &chain);
  const double odom_worst = worst_heading(0.001, &with_odom);
  std::printf(
      "worst keyframe heading error: scan-match chain %.4f rad (precision %.3f), with odometry edges "
      "%.4f rad (precision %.3f)\n",
      chain_worst, chain.map.precision, odom_worst, with_odom.map.precision);
  // Seeds 1-6 (2026-11-27, the matcher using only points within its local map's reach): with
  // odometry edges 0.0029-0.0084 rad, precision >= 0.908; the chain alone 0.009-0.062 rad. How far
  // the chain turns now depends on the seed (0.009 and 0.010 rad in seeds 2 and 3, where the edges
  // cannot halve it); seed 4 is one where it turns (0.062 rad, precision 0.788). 2026-11-30, the
  // route clear of the furniture, seed 4: the chain 0.0187 rad (precision 0.951), with odometry
  // edges 0.0055 rad (0.978).
  EXPECT_LT(odom_worst, 0.01);
  EXPECT_LT(odom_worst, 0.5 * chain_worst);
  EXPECT_GE(with_odom.map.precision, 0.85);
}

TEST(Slam, LoopClosureEventsReportWhatOneScanDid)
{
  SlamStats before;
  before.loop_closures = 2;
  before.loop_held = 1;
  before.last_closure.reason = "held until a later attempt finds the same correction";
  EXPECT_TRUE(loopClosureEvents(before, before).empty());

  // The held closure was dropped and another one accepted at the same keyframe: the drop first.
  SlamStats after = before;
  after.loop_unconfirmed = 1;
  after.last_unconfirmed.to = 40;
  after.last_unconfirmed.reason = "dropped: no later attempt confirmed it";
  after.loop_closures = 3;
  after.last_closure.to = 46;
  after.last_closure.from = 3;
  after.last_closure.accepted = true;
  std::vector<LoopClosureRecord> events = loopClosureEvents(before, after);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].to, 40);
  EXPECT_STREQ(events[0].reason, "dropped: no later attempt confirmed it");
  EXPECT_EQ(events[1].to, 46);
  EXPECT_EQ(events[1].from, 3);
  EXPECT_STREQ(events[1].reason, "accepted");

  // One applied without waiting for confirmation says so (loop_unique_ratio).
  after.last_closure.unique = true;
  events = loopClosureEvents(before, after);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_STREQ(events[1].reason, "accepted at once: unique and strong");

  // A rejection carries its reason.
  after = before;
  after.loop_rejected = 1;
  after.last_closure.reason = "rejected: the optimised graph disagrees with it";
  events = loopClosureEvents(before, after);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_STREQ(events[0].reason, "rejected: the optimised graph disagrees with it");
}
