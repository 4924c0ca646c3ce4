// Cases mirror ros_controllers' diff_drive_controller limit tests (velocity, acceleration,
// jerk) at the library level, plus deceleration and wheel desaturation.
#include <gtest/gtest.h>

#include <cmath>

#include "mybot_control/kinematics.hpp"
#include "mybot_control/speed_limiter.hpp"

using namespace mybot_control;

namespace
{
// diffbot_limits.yaml of the upstream tests.
SpeedLimits linearLimits()
{
  SpeedLimits l;
  l.has_velocity_limits = true;
  l.min_velocity = -0.5;
  l.max_velocity = 1.0;
  l.has_acceleration_limits = true;
  l.min_acceleration = -0.5;
  l.max_acceleration = 1.0;
  l.has_jerk_limits = true;
  l.min_jerk = -5.0;
  l.max_jerk = 5.0;
  return l;
}

// Run a constant command through the limiter for `duration` s at 50 Hz; returns the history.
std::vector<double> run(const SpeedLimiter& lim, double command, double duration, double v_start = 0.0)
{
  const double dt = 0.02;
  double v0 = v_start, v1 = v_start;
  std::vector<double> out;
  for (int k = 0; k < static_cast<int>(std::lround(duration / dt)); ++k)
  {
    double v = command;
    lim.limit(v, v0, v1, dt);
    out.push_back(v);
    v1 = v0;
    v0 = v;
  }
  return out;
}
}  // namespace

TEST(SpeedLimiter, NoLimitsPassesThrough)
{
  SpeedLimiter lim;
  double v = 10.0;
  EXPECT_EQ(lim.limit(v, 0.0, 0.0, 0.02), 1.0);
  EXPECT_EQ(v, 10.0);
}

TEST(SpeedLimiter, VelocityLimits)
{
  SpeedLimits l;
  l.has_velocity_limits = true;
  l.min_velocity = -0.5;
  l.max_velocity = 1.0;
  SpeedLimiter lim(l);
  double v = 10.0;
  EXPECT_NEAR(lim.limitVelocity(v), 0.1, 1e-12);
  EXPECT_EQ(v, 1.0);
  v = -10.0;
  lim.limitVelocity(v);
  EXPECT_EQ(v, -0.5);
  v = 0.0;
  EXPECT_EQ(lim.limitVelocity(v), 1.0);  // zero request: factor 1, no division by zero
}

TEST(SpeedLimiter, LinearAccelerationLimits)
{
  // Upstream: a 10 m/s step under max_acceleration 1 m/s^2 -> 0.5 m/s after 0.5 s.
  SpeedLimits l = linearLimits();
  l.has_jerk_limits = false;
  const auto h = run(SpeedLimiter(l), 10.0, 0.5);
  EXPECT_NEAR(h.back(), 0.5, 1e-9);
  for (std::size_t k = 1; k < h.size(); ++k)
    EXPECT_LE(h[k] - h[k - 1], 1.0 * 0.02 + 1e-12);
}

TEST(SpeedLimiter, LinearVelocityLimitsAfterLongRun)
{
  // Upstream: after 5 s of a 10 m/s command the speed is capped at max_velocity 1 m/s.
  const auto h = run(SpeedLimiter(linearLimits()), 10.0, 5.0);
  for (double v : h)
    EXPECT_LE(v, 1.0 + 1e-12);
  EXPECT_NEAR(h.back(), 1.0, 1e-9);
  const auto r = run(SpeedLimiter(linearLimits()), -10.0, 5.0);
  EXPECT_NEAR(r.back(), -0.5, 1e-9);
}

TEST(SpeedLimiter, JerkLimits)
{
  const SpeedLimits l = linearLimits();
  const double dt = 0.02;
  const auto h = run(SpeedLimiter(l), 10.0, 2.0);
  // Acceleration ramps in at most max_jerk: a_k - a_{k-1} <= jerk * dt.
  double a_prev = 0.0, v_prev = 0.0;
  for (double v : h)
  {
    const double a = (v - v_prev) / dt;
    EXPECT_LE(a - a_prev, l.max_jerk * dt + 1e-9);
    EXPECT_LE(a, l.max_acceleration + 1e-9);
    a_prev = a;
    v_prev = v;
  }
  // The first step is jerk limited (5 * 0.02^2 = 2 mm/s), far below the acceleration limit.
  EXPECT_NEAR(h.front(), 5.0 * dt * dt, 1e-12);
}

TEST(SpeedLimiter, JerkLimitedRampLandsWithoutOvershoot)
{
  // Up to the velocity limit and back to a stop: jerk bounded everywhere (including where the
  // velocity limit and the target are reached), no overshoot, exact final values.
  SpeedLimits l = linearLimits();
  l.has_deceleration_limits = true;
  l.max_deceleration = 2.0;
  const SpeedLimiter lim(l);
  const double dt = 0.02;
  double v0 = 0.0, v1 = 0.0, a_prev = 0.0;
  std::vector<double> h;
  for (int k = 0; k < 250; ++k)
  {
    double v = k < 150 ? 10.0 : 0.0;
    lim.limit(v, v0, v1, dt);
    const double a = (v - v0) / dt;
    EXPECT_LE(std::abs(a - a_prev), l.max_jerk * dt + 1e-9) << "step " << k;
    EXPECT_LE(v, 1.0 + 1e-12);
    EXPECT_GE(v, -1e-12);
    h.push_back(v);
    a_prev = a;
    v1 = v0;
    v0 = v;
  }
  EXPECT_DOUBLE_EQ(h[149], 1.0);
  EXPECT_NEAR(h.back(), 0.0, 1e-12);
}

TEST(SpeedLimiter, AngularLimits)
{
  // Upstream angular case: max_velocity 2 rad/s, max_acceleration 2 rad/s^2.
  const SpeedLimiter lim(SpeedLimits::symmetric(2.0, 2.0));
  EXPECT_NEAR(run(lim, 10.0, 0.5).back(), 1.0, 1e-9);
  EXPECT_NEAR(run(lim, 10.0, 5.0).back(), 2.0, 1e-9);
  EXPECT_NEAR(run(lim, -10.0, 0.5).back(), -1.0, 1e-9);
}

TEST(SpeedLimiter, SeparateDeceleration)
{
  SpeedLimits l = SpeedLimits::symmetric(2.0, 0.5);
  l.has_deceleration_limits = true;
  l.max_deceleration = 2.0;
  const SpeedLimiter lim(l);
  // Braking from 1 m/s to 0 takes 0.5 s at 2 m/s^2 (acceleration alone would take 2 s).
  const auto stop = run(lim, 0.0, 0.5, 1.0);
  EXPECT_NEAR(stop.back(), 0.0, 1e-9);
  EXPECT_NEAR(stop.front(), 1.0 - 2.0 * 0.02, 1e-12);
  // Speeding up still uses max_acceleration.
  EXPECT_NEAR(run(lim, 1.0, 1.0).back(), 0.5, 1e-9);
  // Reverse direction: braking from -1 m/s.
  EXPECT_NEAR(run(lim, 0.0, 0.2, -1.0).back(), -1.0 + 0.4, 1e-9);
}

TEST(SpeedLimiter, ValidateNamesTheField)
{
  SpeedLimits l;
  l.has_acceleration_limits = true;
  l.max_acceleration = -1.0;
  EXPECT_NE(l.validate("linear/x/").find("linear/x/max_acceleration"), std::string::npos);
  SpeedLimits v;
  v.has_velocity_limits = true;
  v.min_velocity = 2.0;
  v.max_velocity = 1.0;
  EXPECT_NE(v.validate().find("min_velocity"), std::string::npos);
  EXPECT_EQ(linearLimits().validate(), "");
}

TEST(TwistLimiter, LimitsEachAxisAndKeepsHistory)
{
  TwistLimiter lim(SpeedLimits::symmetric(1.0, 1.0), SpeedLimits::symmetric(0.5, 0.5),
                   SpeedLimits::symmetric(2.0, 2.0));
  Twist2D out;
  for (int k = 0; k < 25; ++k)
    out = lim.limit({10.0, -10.0, 10.0}, 0.02);
  EXPECT_NEAR(out.vx, 0.5, 1e-9);
  EXPECT_NEAR(out.vy, -0.25, 1e-9);
  EXPECT_NEAR(out.wz, 1.0, 1e-9);
  lim.reset();
  EXPECT_EQ(lim.last().vx, 0.0);
  EXPECT_NEAR(lim.limit({10.0, 0.0, 0.0}, 0.02).vx, 0.02, 1e-12);
}

TEST(Desaturation, KeepsCurvature)
{
  const DiffDriveKinematics kin(0.3, 0.1, 0.1);
  const Twist2D cmd{1.0, 0.0, 4.0};  // right wheel 1.6 m/s, left 0.4 m/s
  WheelVelocities w = kin.toWheelTangent(cmd);
  const double k = desaturate(w, 0.8);
  EXPECT_NEAR(k, 0.5, 1e-12);
  EXPECT_NEAR(std::max(std::abs(w.left), std::abs(w.right)), 0.8, 1e-12);
  const Twist2D out = kin.fromWheelTangent(w);
  EXPECT_NEAR(out.vx / out.wz, cmd.vx / cmd.wz, 1e-12);  // same turning radius
  WheelVelocities slow{0.1, -0.2};
  EXPECT_EQ(desaturate(slow, 0.8), 1.0);
  EXPECT_EQ(desaturationFactor({3.0, -6.0, 1.0, 2.0}, 0.0), 1.0);  // disabled
  EXPECT_NEAR(desaturationFactor({3.0, -6.0, 1.0, 2.0}, 2.0), 1.0 / 3.0, 1e-12);
}

TEST(SpeedLimiter, JerkWithUnevenPeriods)
{
  // Previous step: 0 -> 0.01 over 10 ms (a0 = 1 m/s^2). Next step of 30 ms may raise the
  // acceleration by at most jerk * dt = 5 * 0.03 = 0.15 m/s^2.
  SpeedLimits l;
  l.has_jerk_limits = true;
  l.max_jerk = 5.0;
  l.min_jerk = -5.0;
  const SpeedLimiter lim(l);
  double v = 10.0;
  lim.limit(v, 0.01, 0.0, 0.03, 0.01);
  EXPECT_NEAR(v, 0.01 + 1.15 * 0.03, 1e-12);
  v = -10.0;  // and lower it by at most as much
  lim.limit(v, 0.01, 0.0, 0.03, 0.01);
  EXPECT_NEAR(v, 0.01 + 0.85 * 0.03, 1e-12);
}
