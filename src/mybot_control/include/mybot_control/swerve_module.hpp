// One swerve module's servo loops: a pivot PID on the (continuous) pivot angle with a
// feed-forward of the requested angle's rate, and a drive PID on the wheel speed with
// feed-forward. Outputs are joint velocity commands (rad/s). Plus the mock actuator used
// when no hardware or simulator is attached. No ROS types.
#pragma once

#include <string>

#include "mybot_control/pid.hpp"
#include "mybot_control/swerve_kinematics.hpp"

namespace mybot_control
{

struct SwerveModuleConfig
{
  PidConfig pivot;             // setpoint/measurement in rad, output pivot joint velocity (rad/s)
  PidConfig drive;             // setpoint/measurement in wheel rad/s, output wheel joint velocity (rad/s)
  double wheel_radius = 0.05;  // m
  // Gain on the requested angle's rate (rad/s per rad/s). Requested-angle steps larger than
  // rate_ff_max_step (rad, e.g. a new direction or a wheel flip) are left to the PID.
  double pivot_rate_ff = 1.0;
  double pivot_rate_ff_max_step = 0.2;
  bool optimize = true;      // never turn more than 90 degrees (flip the wheel instead)
  bool cosine_scale = true;  // scale the wheel speed by cos(pivot angle error)

  // Empty when valid, else one message naming the field (prefix + field).
  std::string validate(const std::string& prefix = "") const;
};

class SwerveModuleController
{
public:
  struct Output
  {
    double pivot_command = 0.0;  // pivot joint velocity, rad/s
    double wheel_command = 0.0;  // wheel joint velocity, rad/s
    SwerveModuleState target;    // after optimisation and cosine scaling (speed m/s)
    double pivot_error = 0.0;    // rad, wrapped
    double speed_error = 0.0;    // m/s at the rim
  };

  explicit SwerveModuleController(const SwerveModuleConfig& config);

  // requested: speed (m/s) and angle (rad); measured pivot angle (rad, any winding) and wheel
  // speed (rad/s); dt the control period (s).
  Output update(const SwerveModuleState& requested, double measured_angle, double measured_wheel_rate, double dt);
  void reset();
  const SwerveModuleConfig& config() const { return config_; }

private:
  SwerveModuleConfig config_;
  Pid pivot_pid_, drive_pid_;
  bool have_previous_target_ = false;
  double previous_target_angle_ = 0.0;
};

// Mock actuator for running without hardware: each joint's velocity follows its command
// through a first-order lag of time constant tau (a motor), positions integrate it, so the
// measured angle and speed follow the request through the closed loops.
class MockModuleActuator
{
public:
  explicit MockModuleActuator(double tau = 0.05) : tau_(tau) {}
  void step(double pivot_command, double wheel_command, double dt);
  double pivotPosition() const { return pivot_position_; }
  double pivotVelocity() const { return pivot_velocity_; }
  double wheelPosition() const { return wheel_position_; }
  double wheelVelocity() const { return wheel_velocity_; }

private:
  double tau_;
  double pivot_position_ = 0.0, pivot_velocity_ = 0.0;
  double wheel_position_ = 0.0, wheel_velocity_ = 0.0;
};

}  // namespace mybot_control
