#include "mybot_control/swerve_module.hpp"

#include <algorithm>
#include <cmath>

namespace mybot_control
{

std::string SwerveModuleConfig::validate(const std::string& prefix) const
{
  std::string err = pivot.validate(prefix + "pivot_pid/");
  if (err.empty())
    err = drive.validate(prefix + "drive_pid/");
  if (!err.empty())
    return err;
  if (!(wheel_radius > 0.0) || !std::isfinite(wheel_radius))
    return prefix + "wheel_radius must be > 0 (got " + std::to_string(wheel_radius) + ")";
  if (!std::isfinite(pivot_rate_ff))
    return prefix + "pivot_rate_ff must be a finite number";
  if (!(pivot_rate_ff_max_step >= 0.0))
    return prefix + "pivot_rate_ff_max_step must be >= 0";
  return "";
}

SwerveModuleController::SwerveModuleController(const SwerveModuleConfig& config) : config_(config)
{
  config_.pivot.angle_wrap = true;  // the pivot is continuous: never unwind through +/-pi
  pivot_pid_.setConfig(config_.pivot);
  drive_pid_.setConfig(config_.drive);
}

SwerveModuleController::Output SwerveModuleController::update(const SwerveModuleState& requested, double measured_angle,
                                                              double measured_wheel_rate, double dt)
{
  Output out;
  const double angle = wrapAngle(measured_angle);
  out.target = config_.optimize ? optimizeModuleState(requested, angle)
                                : SwerveModuleState{requested.speed, wrapAngle(requested.angle)};
  out.pivot_error = wrapAngle(out.target.angle - angle);

  // Feed-forward of a smoothly moving request (e.g. translating while rotating), so the PID
  // only corrects the residual; steps and flips are left to the PID.
  double ff = 0.0;
  if (have_previous_target_ && dt > 0.0)
  {
    const double step = wrapAngle(out.target.angle - previous_target_angle_);
    if (std::abs(step) <= config_.pivot_rate_ff_max_step)
      ff = config_.pivot_rate_ff * step / dt;
  }
  previous_target_angle_ = out.target.angle;
  have_previous_target_ = true;
  out.pivot_command = std::clamp(pivot_pid_.compute(out.target.angle, angle, dt) + ff, config_.pivot.output_min,
                                 config_.pivot.output_max);

  if (config_.cosine_scale)
    out.target = cosineScale(out.target, angle);
  const double setpoint = out.target.speed / config_.wheel_radius;
  if (setpoint == 0.0)
  {
    // A zero request is a stop: an integral left from the drive would otherwise creep each
    // wheel on its own (the robot turns after it stopped) until it unwound.
    drive_pid_.reset();
    out.wheel_command = 0.0;
  }
  else
    out.wheel_command = drive_pid_.compute(setpoint, measured_wheel_rate, dt);
  out.speed_error = (setpoint - measured_wheel_rate) * config_.wheel_radius;
  return out;
}

void SwerveModuleController::reset()
{
  pivot_pid_.reset();
  drive_pid_.reset();
  have_previous_target_ = false;
}

void MockModuleActuator::step(double pivot_command, double wheel_command, double dt)
{
  if (!(dt > 0.0) || !std::isfinite(pivot_command) || !std::isfinite(wheel_command))
    return;
  // Exact discretisation of the first-order lag; positions integrate the mean velocity.
  const double a = tau_ > 0.0 ? std::exp(-dt / tau_) : 0.0;
  const double pivot_new = pivot_command + (pivot_velocity_ - pivot_command) * a;
  const double wheel_new = wheel_command + (wheel_velocity_ - wheel_command) * a;
  pivot_position_ += 0.5 * (pivot_velocity_ + pivot_new) * dt;
  wheel_position_ += 0.5 * (wheel_velocity_ + wheel_new) * dt;
  pivot_velocity_ = pivot_new;
  wheel_velocity_ = wheel_new;
}

}  // namespace mybot_control
