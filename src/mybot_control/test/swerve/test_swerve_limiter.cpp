// Swerve twist limiter: acceleration limits that keep the direction of travel.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "mybot_control/swerve_limiter.hpp"
#include "swerve_test_util.h"

using namespace mybot_control;
using namespace swerve_test;

TEST(SwerveTwistLimiter, KeepsTheCurvatureWhileAccelerating)
{
  SwerveTwistLimiter lim(SpeedLimits::symmetric(0.8, 1.0), SpeedLimits::symmetric(0.8, 1.0),
                         SpeedLimits::symmetric(2.0, 4.0));
  const Twist2D cmd{0.5, 0.0, 0.5};
  const double dt = 0.02;
  Twist2D prev;
  int steps = 0;
  for (; steps < 100; ++steps)
  {
    const Twist2D out = lim.limit(cmd, dt);
    EXPECT_NEAR(out.vx, out.wz, 1e-12);  // v / w stays the commanded 1 m radius
    EXPECT_EQ(0.0, out.vy);
    EXPECT_LE(std::abs(out.vx - prev.vx), 1.0 * dt + 1e-12);
    EXPECT_LE(std::abs(out.wz - prev.wz), 4.0 * dt + 1e-12);
    prev = out;
    if (std::abs(out.vx - cmd.vx) < 1e-12)
      break;
  }
  EXPECT_EQ(24, steps);  // limited by vx: 0.5 m/s at 1 m/s^2 in 25 steps of 20 ms
}

TEST(SwerveTwistLimiter, VelocityLimitScalesAllAxes)
{
  SwerveTwistLimiter lim(SpeedLimits::symmetric(0.5), SpeedLimits::symmetric(0.5), SpeedLimits::symmetric(1.0));
  const Twist2D out = lim.limit({1.0, 0.25, 0.5}, 0.02);
  EXPECT_NEAR(0.5, out.vx, 1e-12);
  EXPECT_NEAR(0.125, out.vy, 1e-12);
  EXPECT_NEAR(0.25, out.wz, 1e-12);
}

TEST(SwerveTwistLimiter, ChangeOfDirectionRespectsEveryAxis)
{
  SwerveTwistLimiter lim(SpeedLimits::symmetric(1.0, 1.0), SpeedLimits::symmetric(1.0, 2.0),
                         SpeedLimits::symmetric(1.0, 1.0));
  lim.reset({1.0, 0.0, 0.0});
  Twist2D prev = lim.last();
  for (int k = 0; k < 100; ++k)
  {
    const Twist2D out = lim.limit({0.0, 1.0, 0.0}, 0.02);
    EXPECT_LE(std::abs(out.vx - prev.vx), 1.0 * 0.02 + 1e-12);
    EXPECT_LE(std::abs(out.vy - prev.vy), 2.0 * 0.02 + 1e-12);
    prev = out;
  }
  EXPECT_NEAR(1.0, prev.vy, 1e-12);
  EXPECT_NEAR(0.0, prev.vx, 1e-12);
  // dt <= 0 or a NaN command: the last output, unchanged.
  EXPECT_EQ(prev.vy, lim.limit({5.0, 5.0, 5.0}, 0.0).vy);
  EXPECT_EQ(prev.vy, lim.limit({std::nan(""), 0.0, 0.0}, 0.02).vy);
}
