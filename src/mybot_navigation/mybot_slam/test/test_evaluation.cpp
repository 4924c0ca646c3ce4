#include <gtest/gtest.h>

#include <cmath>

#include "mybot_slam/evaluation.h"
#include "synthetic_world.h"

using namespace mybot_navigation;

TEST(Evaluation, AlignmentRecoversRigidTransform)
{
  const Pose2D T{1.0, -0.5, 0.4};
  std::vector<Pose2D> est, truth;
  for (int i = 0; i < 20; ++i)
  {
    const Pose2D p{0.3 * i, std::sin(0.5 * i), 0.1 * i};
    est.push_back(p);
    truth.push_back(compose(T, p));
  }
  const Pose2D A = alignTrajectories(est, truth);
  EXPECT_NEAR(A.x, T.x, 1e-9);
  EXPECT_NEAR(A.y, T.y, 1e-9);
  EXPECT_NEAR(A.theta, T.theta, 1e-9);
  EXPECT_NEAR(absoluteTrajectoryRmse(est, truth, A), 0.0, 1e-9);
  const RelativePoseError rpe = relativePoseError(est, truth, 1);
  EXPECT_EQ(rpe.pairs, 19);
  EXPECT_NEAR(rpe.translation_rms, 0.0, 1e-9);
}

TEST(Evaluation, MapScoreToleratesOneCellOffset)
{
  const GridMap truth = makeWorld(5.0, 5.0, 0.05, {{2.0, 2.0, 2.5, 2.5}});
  GridMap shifted = truth;
  shifted.info.origin.x += 0.05;  // one cell off
  const MapScore s1 = scoreMap(shifted, truth, Pose2D{}, 1);
  EXPECT_DOUBLE_EQ(s1.precision, 1.0);
  EXPECT_DOUBLE_EQ(s1.recall, 1.0);
  const MapScore s0 = scoreMap(shifted, truth, Pose2D{}, 0);
  EXPECT_LT(s0.precision, 0.9);
}
