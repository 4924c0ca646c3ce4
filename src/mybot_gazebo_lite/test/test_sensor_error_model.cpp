// hector's sensor error model: offset, scale, white noise, and a bias that wanders with its spread
// and forgets itself at its frequency, whatever the update rate. Seeded: the same figures every run;
// each bound is several standard errors of the estimate it checks.
#include "mybot_gazebo_lite/sensor_error_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using mybot_gazebo_lite::SensorError;
using mybot_gazebo_lite::SensorErrorParams;

namespace
{
double mean(const std::vector<double>& v)
{
  double s = 0;
  for (double x : v)
    s += x;
  return s / v.size();
}

double stddev(const std::vector<double>& v)
{
  const double m = mean(v);
  double s = 0;
  for (double x : v)
    s += (x - m) * (x - m);
  return std::sqrt(s / (v.size() - 1));
}

// Correlation of v with itself `lag` samples later.
double autocorrelation(const std::vector<double>& v, size_t lag)
{
  const double m = mean(v), var = stddev(v) * stddev(v);
  double s = 0;
  for (size_t i = 0; i + lag < v.size(); ++i)
    s += (v[i] - m) * (v[i + lag] - m);
  return s / (v.size() - lag) / var;
}

// The bias, sampled every dt for `duration` seconds.
std::vector<double> biasSeries(const SensorErrorParams& p, double dt, double duration, unsigned seed)
{
  std::mt19937 rng(seed);
  SensorError e(p);
  e.reset(rng);
  std::vector<double> out;
  for (double t = 0; t < duration; t += dt)
  {
    e.measure(0.0, dt, rng);
    out.push_back(e.bias());
  }
  return out;
}
}  // namespace

TEST(SensorError, WithoutErrorsItMeasuresTheTruth)
{
  std::mt19937 rng(1);
  SensorError e;
  e.reset(rng);
  for (double truth : {0.0, -3.5, 1e6})
    EXPECT_EQ(e.measure(truth, 0.01, rng), truth);
}

TEST(SensorError, OffsetAndScaleAreAppliedExactly)
{
  std::mt19937 rng(1);
  SensorErrorParams p;
  p.offset = 0.1;
  p.scale = 1.02;
  SensorError e(p);
  e.reset(rng);
  EXPECT_DOUBLE_EQ(e.measure(10.0, 0.01, rng), 10.3);
  EXPECT_DOUBLE_EQ(e.bias(), 0.1);
}

TEST(SensorError, WhiteNoiseHasItsStandardDeviationAndNoMean)
{
  std::mt19937 rng(7);
  SensorErrorParams p;
  p.gaussian_noise = 0.05;
  SensorError e(p);
  e.reset(rng);
  std::vector<double> v;
  for (int i = 0; i < 40000; ++i)
    v.push_back(e.measure(2.0, 0.01, rng) - 2.0);
  // Standard errors: 0.05 / 200 = 2.5e-4 for the mean, 0.35 % for the spread.
  EXPECT_NEAR(mean(v), 0.0, 1e-3);
  EXPECT_NEAR(stddev(v), 0.05, 0.05 * 0.015);
  EXPECT_NEAR(autocorrelation(v, 1), 0.0, 0.02);  // white: no memory from one sample to the next
}

// The point of the exact discretisation: one <drift> and <driftFrequency> describe one sensor, at
// 100 Hz as at one update every half correlation time.
TEST(SensorError, TheBiasWandersWithItsSpreadAndForgetsAtItsFrequencyAtAnyRate)
{
  SensorErrorParams p;
  p.drift = 0.02;
  p.drift_frequency = 0.1;  // a correlation time of 10 s
  for (double dt : {0.01, 5.0})
  {
    SCOPED_TRACE("dt " + std::to_string(dt));
    const std::vector<double> b = biasSeries(p, dt, 40000.0, 3);  // 4000 correlation times
    // About 2000 independent stretches: the spread's standard error is 1.6 %.
    EXPECT_NEAR(stddev(b), 0.02, 0.02 * 0.06);
    EXPECT_NEAR(mean(b), 0.0, 0.02 * 0.1);
    // One correlation time later, e^-1 of it is left.
    EXPECT_NEAR(autocorrelation(b, static_cast<size_t>(std::lround(10.0 / dt))), std::exp(-1.0), 0.05);
  }
}

TEST(SensorError, ResetDrawsTheBiasFromItsSpreadAroundTheOffset)
{
  std::mt19937 rng(11);
  SensorErrorParams p;
  p.offset = -0.3;
  p.drift = 0.01;
  SensorError e(p);
  std::vector<double> v;
  for (int i = 0; i < 20000; ++i)
  {
    e.reset(rng);
    v.push_back(e.bias());
  }
  EXPECT_NEAR(mean(v), -0.3, 0.01 * 0.03);
  EXPECT_NEAR(stddev(v), 0.01, 0.01 * 0.02);
}

TEST(SensorError, WithoutADriftFrequencyTheBiasStaysWhereItWasDrawn)
{
  std::mt19937 rng(5);
  SensorErrorParams p;
  p.drift = 0.01;
  p.drift_frequency = 0.0;
  SensorError e(p);
  e.reset(rng);
  const double b = e.bias();
  EXPECT_NE(b, 0.0);
  for (int i = 0; i < 1000; ++i)
    e.measure(0.0, 0.1, rng);
  EXPECT_EQ(e.bias(), b);
}

TEST(SensorError, CalibrationClearsTheWanderingPartNotTheOffset)
{
  std::mt19937 rng(5);
  SensorErrorParams p;
  p.offset = 0.2;
  p.drift = 0.05;
  SensorError e(p);
  e.reset(rng);
  EXPECT_NE(e.bias(), 0.2);
  e.setDrift(0.0);
  EXPECT_EQ(e.bias(), 0.2);
}
