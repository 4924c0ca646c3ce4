// Swerve odometry: integration, bad readings, encoder wrap, IMU heading.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "mybot_control/swerve_odometry.hpp"
#include "swerve_test_util.h"

using namespace mybot_control;
using namespace swerve_test;

namespace
{
// Simulated encoders of a rigid robot following a body twist exactly.
struct EncoderSim
{
  std::vector<Vec2> offsets = robotOffsets();
  double radius = 0.05;
  std::vector<double> wheels = std::vector<double>(4, 0.0), pivots = std::vector<double>(4, 0.0);
  void step(const Twist2D& t, double dt)
  {
    for (std::size_t i = 0; i < offsets.size(); ++i)
    {
      const double vx = t.vx - t.wz * offsets[i].y, vy = t.vy + t.wz * offsets[i].x;
      const double v = std::hypot(vx, vy);
      if (v > 1e-12)
        pivots[i] = std::atan2(vy, vx);
      wheels[i] += v * dt / radius;
    }
  }
};

SwerveOdometry::Params odomParams()
{
  SwerveOdometry::Params p;
  p.offsets = robotOffsets();
  p.wheel_radius = 0.05;
  return p;
}
}  // namespace

TEST(SwerveOdometry, FirstReadingDoesNotJump)
{
  SwerveOdometry odom(odomParams());
  EXPECT_TRUE(odom.update({100, -3, 7, 12}, {1, 2, 3, 0.5}, 5.0));
  EXPECT_EQ(0.0, odom.pose().x);
  EXPECT_EQ(0.0, odom.pose().y);
  EXPECT_EQ(0.0, odom.pose().theta);
}

TEST(SwerveOdometry, StrafeAndFullCircle)
{
  SwerveOdometry odom(odomParams());
  EncoderSim sim;
  sim.step({0.0, 1.0, 0.0}, 1e-9);  // set pivots for a strafe before the reference
  double t = 0.0;
  odom.update(sim.wheels, sim.pivots, t);
  for (int k = 0; k < 100; ++k)
  {
    sim.step({0.0, 0.3, 0.0}, 0.02);
    ASSERT_TRUE(odom.update(sim.wheels, sim.pivots, t += 0.02));
  }
  EXPECT_NEAR(0.0, odom.pose().x, 1e-9);
  EXPECT_NEAR(0.6, odom.pose().y, 1e-9);
  EXPECT_NEAR(0.3, odom.twist().vy, 1e-9);

  // A full circle translating while rotating with constant module angles relative to the
  // body is a circle in the world: back to the start.
  odom.reset();
  SwerveOdometry::Params p = odomParams();
  const Twist2D arc{0.5, 0.2, 0.5};
  EncoderSim s2;
  s2.step(arc, 1e-12);
  odom.update(s2.wheels, s2.pivots, t = 0.0);
  const int n = 1000;
  const double dt = 2 * M_PI / arc.wz / n;
  for (int k = 0; k < n; ++k)
  {
    s2.step(arc, dt);
    ASSERT_TRUE(odom.update(s2.wheels, s2.pivots, t += dt));
  }
  EXPECT_NEAR(0.0, odom.pose().x, 1e-9);
  EXPECT_NEAR(0.0, odom.pose().y, 1e-9);
  EXPECT_NEAR(0.0, odom.pose().theta, 1e-9);
  EXPECT_NEAR(2 * M_PI * std::hypot(arc.vx, arc.vy) / arc.wz, odom.distance(), 1e-9);
}

TEST(SwerveOdometry, RejectsNanAndStaleStamps)
{
  SwerveOdometry odom(odomParams());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ASSERT_TRUE(odom.update({0, 0, 0, 0}, {0, 0, 0, 0}, 1.0));
  EXPECT_FALSE(odom.update({nan, 0, 0, 0}, {0, 0, 0, 0}, 1.1));
  EXPECT_FALSE(odom.update({1, 1, 1, 1}, {0, 0, 0, 0}, 1.0));
  EXPECT_FALSE(odom.update({1, 1, 1}, {0, 0, 0}, 1.2));
  EXPECT_TRUE(odom.update({1, 1, 1, 1}, {0, 0, 0, 0}, 1.2));
  EXPECT_NEAR(0.05, odom.pose().x, 1e-12);
  EXPECT_TRUE(std::isfinite(odom.pose().theta));
}

TEST(SwerveOdometry, EncoderWrapAround)
{
  SwerveOdometry::Params p = odomParams();
  p.encoder_period = 2 * M_PI;
  SwerveOdometry odom(p);
  odom.update({3.1, 3.1, 3.1, 3.1}, {0, 0, 0, 0}, 0.0);
  const double w = 3.1 + 0.2 - 2 * M_PI;  // rolled 0.2 rad forward through the wrap
  odom.update({w, w, w, w}, {0, 0, 0, 0}, 0.02);
  EXPECT_NEAR(0.2 * 0.05, odom.pose().x, 1e-12);
}

TEST(SwerveOdometry, ImuYawReplacesTheWheelsHeading)
{
  SwerveOdometry odom(odomParams());
  EncoderSim sim;
  double t = 0.0, yaw = 1.0;  // IMU yaw has an arbitrary offset
  odom.update(sim.wheels, sim.pivots, t, yaw);
  for (int k = 0; k < 50; ++k)
  {
    sim.step({0.4, 0.0, 0.0}, 0.02);  // wheels say straight
    yaw += 0.01;                      // the IMU says the body turned (wheels slipping)
    odom.update(sim.wheels, sim.pivots, t += 0.02, yaw);
  }
  EXPECT_NEAR(0.5, odom.pose().theta, 1e-9);
  // A NaN IMU sample falls back to the wheels for that step.
  sim.step({0.4, 0.0, 0.0}, 0.02);
  EXPECT_TRUE(odom.update(sim.wheels, sim.pivots, t += 0.02, std::nan("")));
  EXPECT_NEAR(0.5, odom.pose().theta, 1e-9);
  EXPECT_THROW(SwerveOdometry(
                   []
                   {
                     auto p = odomParams();
                     p.wheel_radius = 0.0;
                     return p;
                   }()),
               std::invalid_argument);
}

TEST(SwerveOdometry, MidStepPivotAngle)
{
  // A module turning during a step rolled along its mean direction: with a 0.2 rad change per
  // step, the end angle alone (WPILib) would be off by 0.1 rad per step.
  SwerveOdometry odom(odomParams());
  odom.update({0, 0, 0, 0}, {0, 0, 0, 0}, 0.0);
  odom.update({1, 1, 1, 1}, {0.2, 0.2, 0.2, 0.2}, 0.02);
  EXPECT_NEAR(0.05 * std::cos(0.1), odom.pose().x, 1e-12);
  EXPECT_NEAR(0.05 * std::sin(0.1), odom.pose().y, 1e-12);
}
