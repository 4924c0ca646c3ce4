// Diff-drive kinematics and the SE(2) exponential (poseExp, poseLog).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "mybot_control/kinematics.hpp"

using namespace mybot_control;

TEST(Kinematics, InverseThenForwardReturnsTwist)
{
  const DiffDriveKinematics kin(0.3, 0.1, 0.12);
  for (double v : {-1.0, 0.0, 0.37, 2.0})
    for (double w : {-3.0, 0.0, 0.5, 1.7})
    {
      const Twist2D t{v, 0.0, w};
      const Twist2D back = kin.fromWheelTangent(kin.toWheelTangent(t));
      EXPECT_NEAR(back.vx, v, 1e-12);
      EXPECT_NEAR(back.wz, w, 1e-12);
      const Twist2D back2 = kin.fromWheelAngular(kin.toWheelAngular(t));
      EXPECT_NEAR(back2.vx, v, 1e-12);
      EXPECT_NEAR(back2.wz, w, 1e-12);
    }
}

TEST(Kinematics, WheelSigns)
{
  const DiffDriveKinematics kin(0.3, 0.1, 0.1);
  const WheelVelocities w = kin.toWheelTangent({0.0, 0.0, 1.0});  // turn left in place
  EXPECT_NEAR(w.left, -0.15, 1e-12);
  EXPECT_NEAR(w.right, 0.15, 1e-12);
  const WheelVelocities a = kin.toWheelAngular({0.5, 0.0, 0.0});
  EXPECT_NEAR(a.left, 5.0, 1e-12);
  EXPECT_NEAR(a.right, 5.0, 1e-12);
}

TEST(PoseExp, WrapAngle)
{
  EXPECT_NEAR(wrapAngle(3 * M_PI), M_PI, 1e-12);
  EXPECT_NEAR(wrapAngle(-M_PI), M_PI, 1e-12);
  EXPECT_NEAR(wrapAngle(-3 * M_PI / 2), M_PI / 2, 1e-12);
  EXPECT_NEAR(wrapAngle(0.1), 0.1, 1e-15);
}

TEST(PoseExp, FullCircleReturnsToStart)
{
  // Constant twist, 1000 steps around a full circle (diff drive and holonomic).
  for (const Twist2D twist : {Twist2D{0.5, 0.0, 0.8}, Twist2D{0.3, -0.4, 1.3}})
  {
    const int steps = 1000;
    const double period = 2 * M_PI / twist.wz;
    const double dt = period / steps;
    Pose2D p{1.0, -2.0, 0.3};
    for (int k = 0; k < steps; ++k)
      p = poseExp(p, twist * dt);
    EXPECT_NEAR(p.x, 1.0, 1e-9);
    EXPECT_NEAR(p.y, -2.0, 1e-9);
    EXPECT_NEAR(wrapAngle(p.theta - 0.3), 0.0, 1e-9);
  }
}

TEST(PoseExp, QuarterArcIsExactInOneStep)
{
  // v = 1, w = 1 for pi/2 s: quarter circle of radius 1 -> (1, 1, pi/2).
  const Pose2D p = poseExp({}, {M_PI / 2, 0.0, M_PI / 2});
  EXPECT_NEAR(p.x, 1.0, 1e-12);
  EXPECT_NEAR(p.y, 1.0, 1e-12);
  EXPECT_NEAR(p.theta, M_PI / 2, 1e-12);
}

TEST(PoseExp, SmallAngleFallbackIsContinuous)
{
  // Just below and above the switch between the exact and second-order formulas.
  for (double w : {0.9e-6, 1.1e-6, 1e-9, -1e-7})
  {
    const Pose2D p = poseExp({0, 0, 0.7}, {0.2, 0.05, w});
    const double th = 0.7 + w / 2;
    EXPECT_NEAR(p.x, 0.2 * std::cos(th) - 0.05 * std::sin(th), 1e-12);
    EXPECT_NEAR(p.y, 0.2 * std::sin(th) + 0.05 * std::cos(th), 1e-12);
  }
  const Pose2D straight = poseExp({}, {1.0, 0.0, 0.0});
  EXPECT_EQ(straight.x, 1.0);
  EXPECT_EQ(straight.y, 0.0);
}

TEST(PoseExp, LogInvertsExp)
{
  for (const Twist2D d : {Twist2D{0.4, 0.1, 0.9}, Twist2D{-0.2, 0.3, -2.5}, Twist2D{0.3, 0.0, 1e-8}})
  {
    const Pose2D from{0.5, 0.2, -1.0};
    const Twist2D back = poseLog(from, poseExp(from, d));
    EXPECT_NEAR(back.vx, d.vx, 1e-9);
    EXPECT_NEAR(back.vy, d.vy, 1e-9);
    EXPECT_NEAR(back.wz, d.wz, 1e-9);
  }
}
