// Swerve module loops: steering and drive control, configuration.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "mybot_control/swerve_module.hpp"
#include "swerve_test_util.h"

using namespace mybot_control;
using namespace swerve_test;

namespace
{
SwerveModuleConfig moduleConfig()
{
  SwerveModuleConfig c;
  c.pivot.p = 8.0;
  c.pivot.d = 0.0;
  c.pivot.output_min = -10.0;
  c.pivot.output_max = 10.0;
  c.drive.p = 0.5;
  c.drive.i = 2.0;
  c.drive.f = 1.0;
  c.wheel_radius = 0.05;
  return c;
}
}  // namespace

TEST(SwerveModuleController, NinetyDegreeStepConvergesWithoutOscillation)
{
  SwerveModuleController ctl(moduleConfig());
  MockModuleActuator act(0.03);
  const double dt = 0.02, goal = M_PI / 2;
  double settle = -1.0, worst_overshoot = 0.0;
  for (int k = 0; k < 100; ++k)
  {
    const auto out = ctl.update({0.0, goal}, act.pivotPosition(), act.wheelVelocity(), dt);
    act.step(out.pivot_command, out.wheel_command, dt);
    const double err = wrapAngle(act.pivotPosition() - goal);
    worst_overshoot = std::max(worst_overshoot, err);
    if (std::abs(err) > 0.02)
      settle = -1.0;
    else if (settle < 0.0)
      settle = (k + 1) * dt;
  }
  EXPECT_GT(settle, 0.0);
  EXPECT_LT(settle, 1.0);
  EXPECT_LT(worst_overshoot, 0.1);
}

TEST(SwerveModuleController, NeverTurnsMoreThan90Degrees)
{
  SwerveModuleController ctl(moduleConfig());
  MockModuleActuator act(0.03);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-M_PI, M_PI);
  const double dt = 0.02;
  for (int cmd = 0; cmd < 200; ++cmd)
  {
    const SwerveModuleState want{1.0, u(rng)};
    const double start = act.pivotPosition();
    double travelled = 0.0;
    for (int k = 0; k < 25; ++k)
    {
      const auto out = ctl.update(want, act.pivotPosition(), act.wheelVelocity(), dt);
      EXPECT_LE(std::abs(out.pivot_error), M_PI / 2 + 1e-12);
      act.step(out.pivot_command, out.wheel_command, dt);
      travelled = std::max(travelled, std::abs(act.pivotPosition() - start));
    }
    EXPECT_LE(travelled, M_PI / 2 + 0.1) << "command " << cmd;
  }
}

TEST(SwerveModuleController, DriveTracksSpeedWithCosineScaling)
{
  SwerveModuleController ctl(moduleConfig());
  MockModuleActuator act(0.05);
  const double dt = 0.02;
  SwerveModuleController::Output out;
  for (int k = 0; k < 150; ++k)
  {
    out = ctl.update({0.3, 0.0}, act.pivotPosition(), act.wheelVelocity(), dt);
    act.step(out.pivot_command, out.wheel_command, dt);
  }
  EXPECT_NEAR(0.3 / 0.05, act.wheelVelocity(), 0.01);
  EXPECT_NEAR(0.0, out.speed_error, 0.001);
  // Request 60 degrees off: the first step drives at cos(60) of the speed.
  SwerveModuleController fresh(moduleConfig());
  const auto o = fresh.update({0.3, M_PI / 3}, 0.0, 0.0, dt);
  EXPECT_NEAR(0.15, o.target.speed, 1e-12);
  EXPECT_NEAR(M_PI / 3, o.pivot_error, 1e-12);
}

TEST(SwerveModuleController, RateFeedForwardTracksARotatingRequest)
{
  SwerveModuleController ctl(moduleConfig());
  MockModuleActuator act(0.01);
  const double dt = 0.02, rate = 1.0;
  double worst = 0.0;
  for (int k = 0; k < 200; ++k)
  {
    const double want = wrapAngle(rate * k * dt);
    const auto out = ctl.update({0.0, want}, act.pivotPosition(), 0.0, dt);
    act.step(out.pivot_command, out.wheel_command, dt);
    if (k > 25)
      worst = std::max(worst, std::abs(out.pivot_error));
  }
  EXPECT_LT(worst, 0.05);
}

TEST(SwerveModuleConfig, Validates)
{
  SwerveModuleConfig c = moduleConfig();
  EXPECT_EQ("", c.validate());
  c.wheel_radius = 0.0;
  EXPECT_NE(std::string::npos, c.validate("m/").find("m/wheel_radius"));
  c = moduleConfig();
  c.drive.output_min = 5.0;
  c.drive.output_max = 1.0;
  EXPECT_NE(std::string::npos, c.validate().find("drive_pid/"));
}
