// AckermannOdometry: the bicycle model's dead reckoning from the rear wheel and the steering angle.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "mybot_control/odometry.hpp"

using namespace mybot_control;

namespace
{
AckermannOdometry::Params params()
{
  AckermannOdometry::Params p;
  p.wheelbase = 0.5;
  p.wheel_radius = 0.1;
  p.velocity_window = 1;
  return p;
}
}  // namespace

TEST(AckermannOdometry, FirstReadingSetsTheReference)
{
  AckermannOdometry odom(params());
  EXPECT_TRUE(odom.update(42.0, 0.3, 5.0));  // the wheel far from zero at start, steered
  EXPECT_EQ(odom.pose().x, 0.0);
  EXPECT_EQ(odom.pose().theta, 0.0);
  EXPECT_EQ(odom.distance(), 0.0);
}

TEST(AckermannOdometry, StraightAhead)
{
  AckermannOdometry odom(params());
  odom.update(0.0, 0.0, 0.0);
  for (int k = 1; k <= 100; ++k)
    ASSERT_TRUE(odom.update(k * 0.1, 0.0, k * 0.01));  // 10 rad/s: 1 m/s
  EXPECT_NEAR(odom.pose().x, 1.0, 1e-12);
  EXPECT_NEAR(odom.pose().y, 0.0, 1e-12);
  EXPECT_NEAR(odom.twist().vx, 1.0, 1e-9);
  EXPECT_NEAR(odom.twist().wz, 0.0, 1e-12);
}

// Steered by delta, the rear axle follows a circle of radius R = L / tan(delta): after an arc s
// it has turned s / R and stands at (R sin(s/R), R (1 - cos(s/R))), exactly at any step size.
TEST(AckermannOdometry, ASteadySteerDrivesTheBicycleCircle)
{
  const double delta = 0.4, L = 0.5, R = L / std::tan(delta);
  for (const int steps : {10, 1000})
  {
    AckermannOdometry odom(params());
    odom.update(0.0, delta, 0.0);
    const double s = 2.0;  // 20 rad of the 0.1 m wheel
    for (int k = 1; k <= steps; ++k)
      ASSERT_TRUE(odom.update(20.0 * k / steps, delta, 2.0 * k / steps));
    EXPECT_NEAR(odom.pose().theta, s / R, 1e-12) << steps;
    EXPECT_NEAR(odom.pose().x, R * std::sin(s / R), 1e-12) << steps;
    EXPECT_NEAR(odom.pose().y, R * (1 - std::cos(s / R)), 1e-12) << steps;
    EXPECT_NEAR(odom.twist().wz, 1.0 / R, 1e-9) << steps;  // 1 m/s on radius R
    EXPECT_NEAR(odom.distance(), s, 1e-12) << steps;
  }
  // Backing up with the same steer turns the other way.
  AckermannOdometry back(params());
  back.update(0.0, delta, 0.0);
  back.update(-5.0, delta, 1.0);
  EXPECT_NEAR(back.pose().theta, -0.5 / R, 1e-12);
}

// A step whose steering moved is taken at the mean of its two readings.
TEST(AckermannOdometry, AStepsSteeringIsItsMean)
{
  AckermannOdometry odom(params());
  odom.update(0.0, 0.0, 0.0);
  odom.update(1.0, 0.2, 0.1);  // 0.1 m while the wheel turned from 0 to 0.2 rad
  EXPECT_NEAR(odom.pose().theta, 0.1 * std::tan(0.1) / 0.5, 1e-15);
}

TEST(AckermannOdometry, RejectsNonFiniteReadingsAndOldStamps)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  AckermannOdometry odom(params());
  odom.update(0.0, 0.0, 1.0);
  EXPECT_FALSE(odom.update(nan, 0.0, 1.1));
  EXPECT_FALSE(odom.update(1.0, std::numeric_limits<double>::infinity(), 1.1));
  EXPECT_FALSE(odom.update(1.0, 0.0, 1.0));  // not after the reference
  EXPECT_EQ(odom.pose().x, 0.0);
  EXPECT_TRUE(odom.update(1.0, 0.0, 1.1));
  EXPECT_NEAR(odom.pose().x, 0.1, 1e-15);
  odom.resetEncoders();  // the next reading is a reference again: no jump from 1 to 50 rad
  EXPECT_TRUE(odom.update(50.0, 0.0, 1.2));
  EXPECT_NEAR(odom.pose().x, 0.1, 1e-15);
}

TEST(AckermannOdometry, AWrappingEncoderUnwraps)
{
  AckermannOdometry::Params p = params();
  p.encoder_period = 2 * M_PI;
  AckermannOdometry odom(p);
  odom.update(3.0, 0.0, 0.0);
  odom.update(3.2 - 2 * M_PI, 0.0, 0.1);  // passed pi: the position wrapped to -pi
  EXPECT_NEAR(odom.pose().x, 0.02, 1e-12);
}
