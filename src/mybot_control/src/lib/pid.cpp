#include "mybot_control/pid.hpp"

#include <algorithm>
#include <cmath>

#include "mybot_control/kinematics.hpp"

namespace mybot_control
{

std::string PidConfig::validate(const std::string& prefix) const
{
  auto bad = [&](const std::string& field, const char* why) { return prefix + field + " " + why; };
  const double gains[] = {p, i, d, f};
  const char* names[] = {"p", "i", "d", "f"};
  for (int k = 0; k < 4; ++k)
    if (!std::isfinite(gains[k]))
      return bad(names[k], "must be a finite number");
  if (std::isnan(i_clamp_min) || std::isnan(i_clamp_max) || i_clamp_min > i_clamp_max)
    return bad("i_clamp_min", "must not exceed i_clamp_max");
  if (i_clamp_min > 0.0 || i_clamp_max < 0.0)
    return bad("i_clamp_min", "and i_clamp_max must bracket 0");
  if (std::isnan(output_min) || std::isnan(output_max) || output_min >= output_max)
    return bad("output_min", "must be below output_max");
  if (setpoint_delay < 0 || setpoint_delay > 100)
    return bad("setpoint_delay", "must be an integer number of steps in [0, 100]");
  if (!(no_reverse_below >= 0.0))
    return bad("no_reverse_below", "must be >= 0 (a speed; 0 = off)");
  if (!(d_filter_tau >= 0.0) || !std::isfinite(d_filter_tau))
    return bad("d_filter_tau", "must be >= 0 s");
  for (std::size_t k = 0; k < schedule.size(); ++k)
  {
    const auto& e = schedule[k];
    const std::string field = "schedule[" + std::to_string(k) + "]";
    if (!(e.error >= 0.0) || !std::isfinite(e.error))
      return bad(field + ".error", "must be a finite number >= 0");
    if (!std::isfinite(e.p) || !std::isfinite(e.i) || !std::isfinite(e.d))
      return bad(field, "gains must be finite numbers");
  }
  return "";
}

const PidScheduleEntry Pid::gainsFor(double abs_error) const
{
  if (config_.schedule.empty())
    return {0.0, config_.p, config_.i, config_.d};
  const PidScheduleEntry* best = &config_.schedule.front();
  for (const auto& e : config_.schedule)
    if (std::abs(e.error - abs_error) < std::abs(best->error - abs_error))
      best = &e;
  return *best;
}

double Pid::compute(double setpoint, double measurement, double dt)
{
  return compute(setpoint, setpoint, measurement, dt);
}

double Pid::compute(double setpoint, double reference, double measurement, double dt)
{
  if (!(dt > 0.0) || !std::isfinite(dt) || !std::isfinite(setpoint) || !std::isfinite(reference) ||
      !std::isfinite(measurement))
    return output_;

  // Feedback reference: the setpoint the measurement can already reflect.
  if (config_.setpoint_delay > 0)
  {
    const double delayed = setpoints_.empty() ? measurement : setpoints_.front();
    setpoints_.push_back(reference);
    reference = delayed;
    if (static_cast<int>(setpoints_.size()) > config_.setpoint_delay)
      setpoints_.pop_front();
  }
  error_ = reference - measurement;
  if (config_.angle_wrap)
    error_ = wrapAngle(error_);
  const PidScheduleEntry g = gainsFor(std::abs(error_));

  // Derivative on measurement: no kick when the setpoint steps.
  double rate = 0.0;
  if (have_previous_)
  {
    double step = measurement - previous_measurement_;
    if (config_.angle_wrap)
      step = wrapAngle(step);
    rate = step / dt;
  }
  previous_measurement_ = measurement;
  if (!have_previous_)
  {
    have_previous_ = true;
    d_filtered_ = 0.0;
  }
  else
  {
    const double alpha = dt / (config_.d_filter_tau + dt);
    d_filtered_ += alpha * (rate - d_filtered_);
  }

  p_term_ = g.p * error_;
  d_term_ = -g.d * d_filtered_;
  const double ff = config_.f * setpoint;

  // Conditional integration: integrate only if that does not push a saturated output
  // further into saturation. The integral term itself is also clamped (i_clamp).
  double lo = config_.output_min, hi = config_.output_max;
  if (std::abs(setpoint) < config_.no_reverse_below)
  {
    if (setpoint > 0.0)
      lo = std::max(lo, 0.0);
    else if (setpoint < 0.0)
      hi = std::min(hi, 0.0);
  }
  const double candidate_i = std::clamp(i_term_ + g.i * error_ * dt, config_.i_clamp_min, config_.i_clamp_max);
  const double unsat_with = ff + p_term_ + candidate_i + d_term_;
  // The no-reverse bound is not a saturation: there the integral keeps acting on the mean
  // error, which sets the pulse duty below the dead band (i_clamp bounds it).
  const bool pushes_high = unsat_with > config_.output_max && candidate_i > i_term_;
  const bool pushes_low = unsat_with < config_.output_min && candidate_i < i_term_;
  if (!pushes_high && !pushes_low)
    i_term_ = candidate_i;
  else
    i_term_ = std::clamp(i_term_, config_.i_clamp_min, config_.i_clamp_max);

  const double unsat = ff + p_term_ + i_term_ + d_term_;
  output_ = std::clamp(unsat, lo, hi);
  saturated_ = output_ != unsat;
  return output_;
}

void Pid::reset()
{
  setpoints_.clear();
  have_previous_ = false;
  previous_measurement_ = 0.0;
  d_filtered_ = 0.0;
  error_ = p_term_ = i_term_ = d_term_ = output_ = 0.0;
  saturated_ = false;
}

}  // namespace mybot_control
