// Odometry: the pose integrator, diff-drive odometry, wheel encoders.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "mybot_control/kinematics.hpp"
#include "mybot_control/odometry.hpp"

using namespace mybot_control;

namespace
{
DiffDriveOdometry::Params params(double period = 0.0)
{
  DiffDriveOdometry::Params p;
  p.wheel_separation = 0.5;
  p.left_radius = 0.1;
  p.right_radius = 0.1;
  p.encoder_period = period;
  p.velocity_window = 1;
  return p;
}
}  // namespace

TEST(Odometry, Initial)
{
  DiffDriveOdometry odom(params());
  EXPECT_EQ(odom.pose().x, 0.0);
  EXPECT_EQ(odom.pose().y, 0.0);
  EXPECT_EQ(odom.pose().theta, 0.0);
  EXPECT_EQ(odom.twist().vx, 0.0);
  EXPECT_EQ(odom.twist().wz, 0.0);
}

TEST(Odometry, FirstReadingDoesNotJump)
{
  DiffDriveOdometry odom(params());
  EXPECT_TRUE(odom.update(123.4, -56.7, 10.0));  // encoders far from zero at start
  EXPECT_EQ(odom.pose().x, 0.0);
  EXPECT_EQ(odom.pose().theta, 0.0);
  EXPECT_TRUE(odom.update(124.4, -55.7, 10.1));  // both +1 rad -> 0.1 m forward
  EXPECT_NEAR(odom.pose().x, 0.1, 1e-12);
  EXPECT_NEAR(odom.twist().vx, 1.0, 1e-9);
}

TEST(Odometry, NoMoveFromInitial)
{
  DiffDriveOdometry odom(params());
  for (int k = 0; k <= 100; ++k)
    odom.update(0.0, 0.0, 0.02 * k);
  EXPECT_EQ(odom.pose().x, 0.0);
  EXPECT_EQ(odom.pose().y, 0.0);
  EXPECT_EQ(odom.pose().theta, 0.0);
  EXPECT_EQ(odom.twist().vx, 0.0);
}

TEST(Odometry, ForwardAndTurn)
{
  // 100 steps of 0.02 rad on both wheels: 0.2 m straight.
  DiffDriveOdometry odom(params());
  for (int k = 0; k <= 100; ++k)
    odom.update(0.02 * k, 0.02 * k, 0.02 * k);
  EXPECT_NEAR(odom.pose().x, 0.2, 1e-12);
  EXPECT_NEAR(odom.pose().y, 0.0, 1e-12);
  EXPECT_NEAR(odom.twist().vx, 0.1, 1e-9);
  // Turn in place: right forward, left back.
  DiffDriveOdometry turn(params());
  for (int k = 0; k <= 100; ++k)
    turn.update(-0.02 * k, 0.02 * k, 0.02 * k);
  EXPECT_NEAR(turn.pose().x, 0.0, 1e-12);
  EXPECT_NEAR(turn.pose().y, 0.0, 1e-12);
  EXPECT_NEAR(turn.pose().theta, 2 * 0.2 / 0.5, 1e-12);
  EXPECT_NEAR(turn.twist().wz, 0.4, 1e-9);  // 0.8 rad in 2 s
}

TEST(Odometry, CircleFromWheelsReturnsToStart)
{
  // Left 1 rad/s, right 2 rad/s: v = 0.15, w = 0.2 -> closed circle after 10*pi s.
  DiffDriveOdometry odom(params());
  const int steps = 5000;
  const double dt = 10 * M_PI / steps;
  for (int k = 0; k <= steps; ++k)
    odom.update(1.0 * k * dt, 2.0 * k * dt, k * dt);
  EXPECT_NEAR(odom.pose().x, 0.0, 1e-9);
  EXPECT_NEAR(odom.pose().y, 0.0, 1e-9);
  EXPECT_NEAR(odom.pose().theta, 0.0, 1e-9);
}

TEST(Odometry, EncoderWrapAround)
{
  // Encoders that wrap at 2*pi, as a position reported in [-pi, pi).
  const double period = 2 * M_PI;
  DiffDriveOdometry wrapped(params(period)), plain(params());
  for (int k = 0; k <= 400; ++k)
  {
    const double raw = 0.1 * k;
    wrapped.update(wrapAngle(raw), wrapAngle(raw), 0.02 * k);
    plain.update(raw, raw, 0.02 * k);
  }
  EXPECT_NEAR(wrapped.pose().x, 4.0, 1e-9);
  EXPECT_NEAR(wrapped.pose().x, plain.pose().x, 1e-9);
  EXPECT_NEAR(wrapped.twist().vx, 0.5, 1e-9);
}

TEST(Odometry, NaNIsRejected)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  DiffDriveOdometry odom(params());
  EXPECT_FALSE(odom.update(nan, 0.0, 0.0));  // not even a reference
  EXPECT_TRUE(odom.update(0.0, 0.0, 0.0));
  EXPECT_TRUE(odom.update(1.0, 1.0, 0.1));
  EXPECT_FALSE(odom.update(nan, 2.0, 0.2));
  EXPECT_FALSE(odom.update(2.0, std::numeric_limits<double>::infinity(), 0.2));
  EXPECT_FALSE(odom.update(2.0, 2.0, nan));
  EXPECT_TRUE(std::isfinite(odom.pose().x));
  EXPECT_TRUE(odom.update(2.0, 2.0, 0.3));
  EXPECT_NEAR(odom.pose().x, 0.2, 1e-12);  // resumes from the last valid reading
  EXPECT_TRUE(std::isfinite(odom.twist().vx));
}

TEST(Odometry, NonIncreasingStampIsRejected)
{
  DiffDriveOdometry odom(params());
  odom.update(0.0, 0.0, 1.0);
  EXPECT_FALSE(odom.update(1.0, 1.0, 1.0));
  EXPECT_FALSE(odom.update(1.0, 1.0, 0.5));
  EXPECT_EQ(odom.pose().x, 0.0);
}

TEST(Odometry, ResetAndSetPose)
{
  DiffDriveOdometry odom(params());
  odom.update(0.0, 0.0, 0.0);
  odom.update(5.0, 5.0, 1.0);
  odom.setPose({1.0, 2.0, 4.0});
  EXPECT_EQ(odom.pose().x, 1.0);
  EXPECT_NEAR(odom.pose().theta, 4.0 - 2 * M_PI, 1e-12);
  odom.update(6.0, 6.0, 2.0);  // continues from the set pose
  EXPECT_NEAR(odom.pose().x, 1.0 + 0.1 * std::cos(4.0), 1e-12);
  odom.reset();
  EXPECT_EQ(odom.pose().x, 0.0);
  odom.update(100.0, 100.0, 3.0);  // first reading after reset: no jump
  EXPECT_EQ(odom.pose().x, 0.0);
}

TEST(Odometry, RollingWindowAveragesTwist)
{
  auto p = params();
  p.velocity_window = 4;
  DiffDriveOdometry odom(p);
  odom.update(0.0, 0.0, 0.0);
  odom.update(1.0, 1.0, 1.0);  // 0.1 m/s
  odom.update(4.0, 4.0, 2.0);  // 0.3 m/s
  EXPECT_NEAR(odom.twist().vx, 0.2, 1e-12);
}

TEST(WheelEncoder, VelocityOverWindowWithWrapAndNaN)
{
  WheelEncoder enc(2, 2 * M_PI);
  EXPECT_FALSE(enc.valid());
  EXPECT_TRUE(enc.update(wrapAngle(3.0), 0.0));
  EXPECT_EQ(enc.velocity(), 0.0);
  EXPECT_TRUE(enc.update(wrapAngle(3.1), 0.1));  // crosses +pi -> -pi
  EXPECT_TRUE(enc.valid());
  EXPECT_NEAR(enc.velocity(), 1.0, 1e-9);
  EXPECT_FALSE(enc.update(std::numeric_limits<double>::quiet_NaN(), 0.2));
  EXPECT_FALSE(enc.update(3.3, 0.1));            // stale stamp
  EXPECT_TRUE(enc.update(wrapAngle(3.5), 0.2));  // window of 2 steps: (3.5 - 3.0) / 0.2
  EXPECT_NEAR(enc.velocity(), 2.5, 1e-9);
  EXPECT_TRUE(enc.update(wrapAngle(3.6), 0.3));  // (3.6 - 3.1) / 0.2
  EXPECT_NEAR(enc.velocity(), 2.5, 1e-9);
  enc.reset();
  EXPECT_FALSE(enc.valid());
  EXPECT_EQ(enc.velocity(), 0.0);
}

TEST(PoseIntegrator, IntegratesAlongTheArcAndAveragesTheTwist)
{
  // A quarter circle of 1 m arc length in one step: the arc's end, not the chord's
  // heading-at-start guess (1, 0).
  PoseIntegrator integrator(2);
  integrator.integrate({1.0, 0.0, M_PI / 2}, 1.0);
  EXPECT_NEAR(integrator.pose().x, 2.0 / M_PI, 1e-9);
  EXPECT_NEAR(integrator.pose().y, 2.0 / M_PI, 1e-9);
  EXPECT_NEAR(integrator.pose().theta, M_PI / 2, 1e-12);
  integrator.integrate({0.0, 0.5, 0.0}, 0.5);  // then 0.5 m sideways (a holonomic base) in 0.5 s
  EXPECT_NEAR(integrator.distance(), 1.5, 1e-12);
  EXPECT_NEAR(integrator.twist().vx, 0.5, 1e-12);  // mean of 1.0 and 0.0 m/s
  EXPECT_NEAR(integrator.twist().vy, 0.5, 1e-12);  // mean of 0.0 and 1.0 m/s
  EXPECT_NEAR(integrator.twist().wz, M_PI / 4, 1e-12);
  integrator.resetTwist();
  integrator.resetDistance();
  EXPECT_EQ(integrator.twist().vx, 0.0);
  EXPECT_EQ(integrator.distance(), 0.0);
}
