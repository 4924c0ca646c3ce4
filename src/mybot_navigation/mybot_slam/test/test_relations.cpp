// Kuemmerle et al.'s relation metric on trajectories with known errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "mybot_common/temp_dir.h"
#include "mybot_slam/evaluation.h"

using namespace mybot_navigation;

namespace
{
// A square drive, one pose a second, and the relations between consecutive poses and a loop.
std::vector<StampedPose> square(double scale = 1.0)
{
  std::vector<StampedPose> t;
  Pose2D p;
  for (int i = 0; i < 40; ++i)
  {
    t.push_back({100.0 + i, p});
    p = compose(p, {0.5 * scale, 0.0, (i % 10 == 9) ? M_PI / 2 : 0.0});
  }
  return t;
}

std::vector<Relation> relationsOf(const std::vector<StampedPose>& truth)
{
  std::vector<Relation> r;
  for (std::size_t i = 0; i + 1 < truth.size(); ++i)
    r.push_back({truth[i].stamp, truth[i + 1].stamp, between(truth[i].pose, truth[i + 1].pose)});
  r.push_back({truth[0].stamp, truth[39].stamp, between(truth[0].pose, truth[39].pose)});  // a loop
  return r;
}
}  // namespace

TEST(Relations, ExactTrajectoryScoresZero)
{
  const auto truth = square();
  const RelationScore s = scoreRelations(truth, relationsOf(truth));
  EXPECT_EQ(s.translation.count, 40);
  EXPECT_EQ(s.local_translation.count, 39);
  EXPECT_EQ(s.loop_translation.count, 1);
  EXPECT_NEAR(s.translation.max, 0.0, 1e-9);
  EXPECT_NEAR(s.rotation_deg.max, 0.0, 1e-9);
  EXPECT_EQ(s.missing, 0);
}

// A trajectory 2 % too long: every 0.5 m step is 1 cm off; the loop relation carries the
// accumulated error. The metric is invariant to where the trajectory sits in the world.
TEST(Relations, ScaleErrorShowsPerRelation)
{
  const auto truth = square();
  auto est = square(1.02);
  for (auto& p : est)
    p.pose = compose({5.0, -3.0, 0.7}, p.pose);
  const RelationScore s = scoreRelations(est, relationsOf(truth));
  EXPECT_NEAR(s.local_translation.mean, 0.01, 1e-9);
  EXPECT_NEAR(s.local_translation.std, 0.0, 1e-9);
  EXPECT_NEAR(s.local_translation.squared_mean, 1e-4, 1e-12);
  EXPECT_GT(s.loop_translation.mean, 0.01);
  EXPECT_NEAR(s.rotation_deg.max, 0.0, 1e-9);
}

TEST(Relations, MissingStampsAreCountedNotGuessed)
{
  const auto truth = square();
  auto relations = relationsOf(truth);
  relations.push_back({5.0, 6.0, {}});
  const RelationScore s = scoreRelations(truth, relations);
  EXPECT_EQ(s.missing, 1);
  EXPECT_EQ(s.translation.count, 40);
}

// Intel's log stamps bursts of scans under 1 ms apart: a relation names one of them, and the
// scan stamped nearest to it is the one meant, not the first within the tolerance.
TEST(Relations, AStampTakesTheNearestPoseNotTheFirstWithinTheTolerance)
{
  const auto truth = square();
  auto est = truth;
  // Another scan 0.9 ms before pose 10's, from 3 m away: within the 1 ms tolerance.
  est.push_back({truth[10].stamp - 0.0009, compose(truth[10].pose, {3.0, 0.0, 1.0})});
  const RelationScore s = scoreRelations(est, relationsOf(truth));
  EXPECT_EQ(s.missing, 0);
  EXPECT_NEAR(s.translation.max, 0.0, 1e-9);
  EXPECT_NEAR(s.rotation_deg.max, 0.0, 1e-9);
}

TEST(Relations, FileIsReadAndBadLinesNamed)
{
  const mybot_common::TempDir dir("test_relations");
  const std::string path = dir.file("test.relations");
  std::ofstream(path) << "# t1 t2 x y z roll pitch yaw\n1.5 2.5 0.1 -0.2 0 0 0 0.05\n\n";
  const auto r = readRelations(path);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_DOUBLE_EQ(r[0].motion.y, -0.2);
  EXPECT_DOUBLE_EQ(r[0].motion.theta, 0.05);
  std::ofstream(path) << "1.5 2.5 0.1\n";
  try
  {
    readRelations(path);
    FAIL();
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_NE(std::string(e.what()).find(path + ":1"), std::string::npos) << e.what();
  }
}
