// PID controller: output clamp, integral clamp and conditional-integration anti-windup,
// derivative on measurement with a first-order low-pass, optional angle wrap (continuous
// pivot angles), reset, feed-forward on the setpoint and an optional gain schedule.
// Parameter names follow control_toolbox (p, i, d, i_clamp_min/max) plus output_min/max.
#pragma once

#include <deque>
#include <limits>
#include <string>
#include <vector>

namespace mybot_control
{

struct PidScheduleEntry
{
  double error = 0.0;  // key: |setpoint - measurement|
  double p = 0.0;
  double i = 0.0;
  double d = 0.0;
};

struct PidConfig
{
  double p = 0.0;
  double i = 0.0;
  double d = 0.0;
  double f = 0.0;                                                 // feed-forward gain on the setpoint
  double i_clamp_min = -std::numeric_limits<double>::infinity();  // bounds on the integral term
  double i_clamp_max = std::numeric_limits<double>::infinity();
  double output_min = -std::numeric_limits<double>::infinity();
  double output_max = std::numeric_limits<double>::infinity();
  double d_filter_tau = 0.0;  // s, time constant of the derivative low-pass; 0 = unfiltered
  bool angle_wrap = false;    // error and measurement steps wrapped to (-pi, pi]
  // Velocity loops: while |setpoint| is below this (a motor's dead-band speed), the output never
  // opposes the setpoint's sign. There the motor cannot turn as slowly as asked, and a trim
  // free to reverse swings the wheel between directions; held to one sign it pulses forward at
  // the requested mean. Above it, reverse output is braking and stays allowed. 0 = off.
  double no_reverse_below = 0.0;
  // Control steps by which the measurement lags the command (transport delay, encoder
  // differencing). The feedback error compares the measurement with the setpoint of that
  // many steps ago, so a plant that follows the feed-forward is not "corrected" while its
  // response is still in flight -- which otherwise overshoots a fast velocity servo.
  int setpoint_delay = 0;
  std::vector<PidScheduleEntry> schedule;  // nearest key wins; empty = fixed gains

  // Empty when valid, else one message naming the offending field (prefix + field).
  std::string validate(const std::string& prefix = "") const;
};

class Pid
{
public:
  Pid() = default;
  explicit Pid(const PidConfig& config) : config_(config) {}

  void setConfig(const PidConfig& config) { config_ = config; }
  const PidConfig& config() const { return config_; }

  // One control step of period dt (s). dt <= 0 or non-finite inputs return the last output
  // without changing the state.
  double compute(double setpoint, double measurement, double dt);
  // Two-degree-of-freedom form: feed-forward on `setpoint`, feedback on `reference -
  // measurement`, where the caller supplies the setpoint the measurement can reflect (e.g.
  // the one in force when the measurement was taken, minus the plant's response time).
  double compute(double setpoint, double reference, double measurement, double dt);
  void reset();

  // Introspection of the last step.
  double error() const { return error_; }
  double pTerm() const { return p_term_; }
  double iTerm() const { return i_term_; }
  double dTerm() const { return d_term_; }
  double output() const { return output_; }
  bool saturated() const { return saturated_; }

private:
  const PidScheduleEntry gainsFor(double abs_error) const;

  PidConfig config_;
  std::deque<double> setpoints_;  // the last setpoint_delay setpoints
  bool have_previous_ = false;
  double previous_measurement_ = 0.0;
  double d_filtered_ = 0.0;  // filtered d(measurement)/dt
  double error_ = 0.0, p_term_ = 0.0, i_term_ = 0.0, d_term_ = 0.0, output_ = 0.0;
  bool saturated_ = false;
};

}  // namespace mybot_control
