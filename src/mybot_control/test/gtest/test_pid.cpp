#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <limits>

#include "mybot_control/pid.hpp"

using namespace mybot_control;

namespace
{
// First-order plant dy/dt = (u - y) / tau, simulated with the PID at dt.
struct Plant
{
  double tau = 0.1;
  double gain = 1.0;
  double y = 0.0;
  void step(double u, double dt) { y += dt * (gain * u - y) / tau; }
};

struct StepResult
{
  double overshoot = 0.0;    // fraction of the step
  double settle_time = 1e9;  // s, last time outside +/-2 %
  double final_value = 0.0;
  bool ever_saturated = false;
};

StepResult stepResponse(Pid& pid, Plant plant, double target, double duration, double dt = 0.001)
{
  StepResult r;
  double peak = 0.0;
  const int n = static_cast<int>(duration / dt);
  for (int k = 0; k < n; ++k)
  {
    const double u = pid.compute(target, plant.y, dt);
    r.ever_saturated |= pid.saturated();
    plant.step(u, dt);
    peak = std::max(peak, plant.y);
    if (std::abs(plant.y - target) > 0.02 * std::abs(target))
      r.settle_time = (k + 1) * dt;
  }
  r.overshoot = (peak - target) / target;
  r.final_value = plant.y;
  return r;
}
}  // namespace

TEST(Pid, ProportionalOnly)
{
  PidConfig c;
  c.p = 2.0;
  Pid pid(c);
  EXPECT_DOUBLE_EQ(pid.compute(1.0, 0.25, 0.01), 1.5);
  EXPECT_DOUBLE_EQ(pid.error(), 0.75);
}

TEST(Pid, StepResponseWithoutSaturation)
{
  PidConfig c;
  c.p = 2.0;
  c.i = 20.0;
  Pid pid(c);
  const StepResult r = stepResponse(pid, Plant{}, 5.0, 3.0);
  EXPECT_NEAR(r.final_value, 5.0, 1e-3);  // integral action removes the steady-state error
  EXPECT_LT(r.overshoot, 0.05);
  EXPECT_LT(r.settle_time, 1.0);
  EXPECT_FALSE(r.ever_saturated);
}

TEST(Pid, StepResponseWithSaturationDoesNotWindUp)
{
  PidConfig c;
  c.p = 2.0;
  c.i = 20.0;
  c.output_min = -6.0;
  c.output_max = 6.0;  // barely above what the 5.0 target needs: long saturation phase
  Pid pid(c);
  const StepResult r = stepResponse(pid, Plant{0.1, 1.0}, 5.0, 5.0);
  EXPECT_TRUE(r.ever_saturated);
  EXPECT_NEAR(r.final_value, 5.0, 1e-3);
  // Without anti-windup the integral accumulated during saturation overshoots badly.
  EXPECT_LT(r.overshoot, 0.05);

  PidConfig unclamped_i = c;
  unclamped_i.i_clamp_min = -1e9;
  unclamped_i.i_clamp_max = 1e9;
  Pid pid2(unclamped_i);
  const StepResult r2 = stepResponse(pid2, Plant{0.1, 1.0}, 5.0, 5.0);
  EXPECT_LT(r2.overshoot, 0.05);  // conditional integration alone holds it
}

TEST(Pid, OutputClamp)
{
  PidConfig c;
  c.p = 100.0;
  c.output_min = -1.0;
  c.output_max = 2.0;
  Pid pid(c);
  EXPECT_EQ(pid.compute(10.0, 0.0, 0.01), 2.0);
  EXPECT_TRUE(pid.saturated());
  EXPECT_EQ(pid.compute(-10.0, 0.0, 0.01), -1.0);
}

TEST(Pid, IntegralClamp)
{
  PidConfig c;
  c.i = 1.0;
  c.i_clamp_min = -0.5;
  c.i_clamp_max = 0.5;
  Pid pid(c);
  for (int k = 0; k < 1000; ++k)
    pid.compute(1.0, 0.0, 0.01);
  EXPECT_DOUBLE_EQ(pid.iTerm(), 0.5);
  EXPECT_DOUBLE_EQ(pid.output(), 0.5);
}

TEST(Pid, DerivativeOnMeasurementHasNoSetpointKick)
{
  PidConfig c;
  c.d = 1.0;
  Pid pid(c);
  pid.compute(0.0, 0.0, 0.01);
  EXPECT_EQ(pid.compute(100.0, 0.0, 0.01), 0.0);            // setpoint step, measurement still
  EXPECT_NEAR(pid.compute(100.0, 0.1, 0.01), -10.0, 1e-9);  // measurement rises 10/s
}

TEST(Pid, DerivativeLowPass)
{
  PidConfig c;
  c.d = 1.0;
  c.d_filter_tau = 0.09;  // alpha = 0.01 / 0.1 = 0.1
  Pid pid(c);
  pid.compute(0.0, 0.0, 0.01);
  EXPECT_NEAR(pid.compute(0.0, 0.1, 0.01), -1.0, 1e-9);  // 10% of the raw -10
  for (int k = 2; k < 300; ++k)
    pid.compute(0.0, 0.1 * k, 0.01);
  EXPECT_NEAR(pid.dTerm(), -10.0, 1e-6);  // converges to the raw rate on a ramp
}

TEST(Pid, AngleWrap)
{
  PidConfig c;
  c.p = 1.0;
  c.d = 0.1;
  c.angle_wrap = true;
  Pid pid(c);
  // Setpoint 179 deg, measurement -179 deg: error is -2 deg, not +358.
  const double deg = M_PI / 180.0;
  EXPECT_NEAR(pid.compute(179 * deg, -179 * deg, 0.01), -2 * deg, 1e-12);
  // Measurement crossing +-pi (-179 -> 179.5 deg) is a -1.5 deg step for the derivative.
  pid.compute(179 * deg, 179.5 * deg, 0.01);
  EXPECT_NEAR(pid.dTerm(), 0.1 * (1.5 * deg) / 0.01, 1e-9);
}

TEST(Pid, FeedForward)
{
  PidConfig c;
  c.f = 1.0;
  c.p = 0.5;
  Pid pid(c);
  EXPECT_DOUBLE_EQ(pid.compute(4.0, 4.0, 0.01), 4.0);  // at the setpoint: pure feed-forward
  EXPECT_DOUBLE_EQ(pid.compute(4.0, 3.0, 0.01), 4.5);
}

TEST(Pid, ResetClearsState)
{
  PidConfig c;
  c.p = 1.0;
  c.i = 10.0;
  c.d = 1.0;
  Pid pid(c);
  for (int k = 0; k < 10; ++k)
    pid.compute(1.0, 0.1 * k, 0.01);
  pid.reset();
  EXPECT_EQ(pid.iTerm(), 0.0);
  EXPECT_EQ(pid.output(), 0.0);
  // No derivative spike from the measurement remembered before the reset.
  EXPECT_DOUBLE_EQ(pid.compute(0.0, 5.0, 0.01), -5.0 + 10.0 * -5.0 * 0.01);
}

TEST(Pid, InvalidInputsKeepLastOutput)
{
  PidConfig c;
  c.p = 1.0;
  Pid pid(c);
  const double out = pid.compute(1.0, 0.0, 0.01);
  EXPECT_EQ(pid.compute(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.01), out);
  EXPECT_EQ(pid.compute(2.0, std::numeric_limits<double>::infinity(), 0.01), out);
  EXPECT_EQ(pid.compute(2.0, 0.0, 0.0), out);
  EXPECT_EQ(pid.compute(2.0, 0.0, -1.0), out);
}

TEST(Pid, GainScheduleNearestKey)
{
  PidConfig c;
  c.p = 100.0;  // ignored while a schedule exists
  c.schedule = {{1.0, 1.0, 0.0, 0.0}, {2.0, 3.0, 0.0, 0.0}};
  Pid pid(c);
  EXPECT_DOUBLE_EQ(pid.compute(0.4, 0.0, 0.01), 0.4);  // |e| 0.4 -> key 1.0 -> p 1
  EXPECT_DOUBLE_EQ(pid.compute(1.6, 0.0, 0.01), 4.8);  // |e| 1.6 -> key 2.0 -> p 3
  EXPECT_DOUBLE_EQ(pid.compute(-5.0, 0.0, 0.01), -15.0);
}

TEST(Pid, ValidateNamesTheField)
{
  PidConfig c;
  c.output_min = 1.0;
  c.output_max = -1.0;
  EXPECT_NE(c.validate("pid/").find("pid/output_min"), std::string::npos);
  PidConfig s;
  s.schedule = {{-1.0, 1.0, 0.0, 0.0}};
  EXPECT_NE(s.validate("pid/").find("pid/schedule[0].error"), std::string::npos);
  PidConfig n;
  n.p = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(n.validate().find("p must"), std::string::npos);
  EXPECT_EQ(PidConfig{}.validate(), "");
}

TEST(Pid, SetpointDelayMatchesAServoThatRespondsNextStep)
{
  // Plant: the command becomes the measured speed one step later (ideal velocity servo seen
  // through a sampled encoder). Feed-forward alone tracks it; with the setpoint delayed to
  // match, the feedback sees no error and adds no overshoot, yet still rejects a weak motor.
  PidConfig c;
  c.p = 0.3;
  c.i = 20.0;
  c.f = 1.0;
  c.setpoint_delay = 1;
  for (double gain : {1.0, 0.8})
  {
    Pid pid(c);
    double measured = 0.0, peak = 0.0;
    for (int k = 0; k < 100; ++k)
    {
      const double u = pid.compute(5.0, measured, 0.02);
      measured = gain * u;
      peak = std::max(peak, measured);
    }
    EXPECT_NEAR(measured, 5.0, 1e-3) << "gain " << gain;
    EXPECT_LE(peak, 5.0 * 1.01) << "gain " << gain;
  }
  // Without the delay the same gains overshoot the ideal servo.
  c.setpoint_delay = 0;
  Pid plain(c);
  const double first = plain.compute(5.0, 0.0, 0.02);
  EXPECT_GT(first, 5.0 * 1.2);
}

TEST(Pid, TwoDegreeOfFreedomReference)
{
  PidConfig c;
  c.p = 1.0;
  c.f = 1.0;
  Pid pid(c);
  // Feed-forward follows the new setpoint, feedback only the reference the measurement
  // can reflect (here still the old one, which it matches): no correction yet.
  EXPECT_DOUBLE_EQ(pid.compute(5.0, 0.0, 0.0, 0.02), 5.0);
  EXPECT_DOUBLE_EQ(pid.compute(5.0, 5.0, 4.0, 0.02), 6.0);
}

TEST(Pid, NoReverseKeepsAWheelBelowItsDeadBandFromSwinging)
{
  // A motor behind the GoPiGo tutorial's motor map: any non-zero request turns the wheel at
  // 1.28 rad/s at least. Asked for 0.3 rad/s, the trim must pulse the wheel forward (mean near
  // the target), not drive it backwards.
  auto run = [](bool no_reverse, double* mean, double* min_speed)
  {
    PidConfig c;
    c.p = 1.0;
    c.i = 10.0;
    c.f = 1.0;
    c.i_clamp_min = -3.0;
    c.i_clamp_max = 3.0;
    c.no_reverse_below = no_reverse ? 1.28 : 0.0;
    Pid pid(c);
    double y = 0.0, sum = 0.0;
    *min_speed = 0.0;
    const double dt = 0.02;
    const int n = 1000;
    std::deque<double> measured(5, 0.0);  // 0.1 s of encoder differencing and transport
    for (int k = 0; k < n; ++k)
    {
      const double u = pid.compute(0.3, measured.front(), dt);
      const double floor_speed = std::abs(u) < 1e-6 ? 0.0 : std::copysign(std::max(std::abs(u), 1.28), u);
      y += dt * (floor_speed - y) / 0.1;
      measured.pop_front();
      measured.push_back(y);
      if (k >= n / 2)
      {
        sum += y;
        *min_speed = std::min(*min_speed, y);
      }
    }
    *mean = sum / (n / 2);
  };
  double mean = 0.0, min_speed = 0.0;
  run(false, &mean, &min_speed);
  EXPECT_LT(min_speed, -0.5);  // the plain loop swings the wheel backwards
  run(true, &mean, &min_speed);
  EXPECT_GE(min_speed, 0.0);
  EXPECT_NEAR(mean, 0.3, 0.1);
}
