// The error of a real inertial or GNSS sensor, one axis at a time, as hector_gazebo_plugins
// parameterises it (its SensorModel: <offset>, <drift>, <driftFrequency>, <gaussianNoise>,
// <scaleError>, each optionally prefixed, e.g. <accelDrift>). No ROS.
//
//   measured = scale * true + offset + bias(t) + white(t)
//
// bias(t) is a first-order Gauss-Markov process: it wanders with a standard deviation of `drift`
// and forgets itself with a time constant of 1 / drift_frequency (an hour by default), the usual
// model of a gyro's or accelerometer's bias instability. white(t) is drawn anew at every sample with
// a standard deviation of `gaussian_noise`.
//
// The bias is advanced with the exact discretisation of that process,
//   b' = a b + drift sqrt(1 - a^2) n,   a = exp(-drift_frequency dt),   n ~ N(0, 1),
// so its spread and its correlation time are the same at 1 Hz and at 1 kHz. (Upstream adds
// dt * N(0, sqrt(2 f) drift) instead: at small dt its bias hardly moves, at large dt it overshoots,
// so a given <drift> meant another sensor at each update rate.) Like upstream, the bias starts
// drawn from its stationary spread, N(0, drift), at load and at every reset.
#pragma once

#include <array>
#include <random>

namespace mybot_gazebo_lite
{

struct SensorErrorParams
{
  double offset = 0.0;                  // constant bias, in the measured unit
  double drift = 0.0;                   // standard deviation of the wandering bias
  double drift_frequency = 1.0 / 3600;  // 1 / its correlation time (Hz)
  double gaussian_noise = 0.0;          // standard deviation of the white noise
  double scale = 1.0;                   // scale factor (1 = none)
};

class SensorError
{
public:
  explicit SensorError(const SensorErrorParams& p = {}) : p_(p) {}

  // Draws the bias from its stationary spread.
  void reset(std::mt19937& rng);
  // Sets the wandering part of the bias (hector's calibrate service sets it to 0).
  void setDrift(double drift) { drift_ = drift; }
  void addDrift(double d) { drift_ += d; }

  // Advances the bias by dt seconds and returns `truth` as the sensor measures it.
  double measure(double truth, double dt, std::mt19937& rng);

  // The bias now: offset plus its wandering part (no white noise).
  double bias() const { return p_.offset + drift_; }
  double drift() const { return drift_; }
  const SensorErrorParams& params() const { return p_; }

private:
  SensorErrorParams p_;
  double drift_ = 0.0;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

// Three independent axes (an accelerometer's, a gyro's, a GNSS position's).
class SensorError3
{
public:
  SensorError3() = default;
  explicit SensorError3(const std::array<SensorErrorParams, 3>& p)
      : axes_{SensorError(p[0]), SensorError(p[1]), SensorError(p[2])}
  {
  }

  void reset(std::mt19937& rng)
  {
    for (SensorError& a : axes_)
      a.reset(rng);
  }
  SensorError& operator[](int i) { return axes_[i]; }
  const SensorError& operator[](int i) const { return axes_[i]; }

private:
  std::array<SensorError, 3> axes_;
};

}  // namespace mybot_gazebo_lite
