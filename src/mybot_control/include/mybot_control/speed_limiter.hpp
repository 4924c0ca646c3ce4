// Velocity / acceleration / deceleration / jerk limiting of a commanded speed, per axis
// (diff_drive_controller's SpeedLimiter parameters), a twist limiter built from three of
// them (vx, vy, wz: usable by the diff-drive and the holonomic swerve controller), and
// proportional desaturation of wheel speeds.
#pragma once

#include <string>
#include <vector>

#include "mybot_control/kinematics.hpp"

namespace mybot_control
{

struct SpeedLimits
{
  bool has_velocity_limits = false;
  double min_velocity = 0.0;  // signed lower bound (diff_drive_controller: defaults to -max)
  double max_velocity = 0.0;
  bool has_acceleration_limits = false;
  double min_acceleration = 0.0;  // signed (<= 0) lower bound on dv/dt
  double max_acceleration = 0.0;
  // Braking limit (magnitude) used instead of the acceleration limits whenever the speed
  // magnitude decreases, so a robot can be allowed to stop harder than it may start.
  bool has_deceleration_limits = false;
  double max_deceleration = 0.0;
  bool has_jerk_limits = false;
  double min_jerk = 0.0;
  double max_jerk = 0.0;

  // Symmetric limits helper: min_* = -max_*.
  static SpeedLimits symmetric(double max_velocity, double max_acceleration = 0.0, double max_jerk = 0.0);
  // Empty when consistent, else a message naming the offending field (prefix + field).
  std::string validate(const std::string& prefix = "") const;
};

class SpeedLimiter
{
public:
  SpeedLimiter() = default;
  SpeedLimiter(const SpeedLimits& limits) : limits_(limits) {}  // NOLINT: implicit on purpose (arrays of limiters)

  const SpeedLimits& limits() const { return limits_; }

  // Limit `v` given the two previous outputs v0 (last) and v1 (before last) and the period dt
  // (dt_prev: the period between v1 and v0, when it differs; <= 0 means equal to dt).
  // Returns the factor v_out / v_in (1 when v_in == 0).
  double limit(double& v, double v0, double v1, double dt, double dt_prev = 0.0) const;
  double limitVelocity(double& v) const;
  double limitAcceleration(double& v, double v0, double dt) const;
  double limitJerk(double& v, double v0, double v1, double dt, double dt_prev = 0.0) const;

private:
  SpeedLimits limits_;
};

// Limits a body twist axis by axis and keeps the output history needed for the
// acceleration and jerk limits.
class TwistLimiter
{
public:
  TwistLimiter() = default;
  TwistLimiter(const SpeedLimits& vx, const SpeedLimits& vy, const SpeedLimits& wz);

  Twist2D limit(const Twist2D& command, double dt);
  // Replace the last output (e.g. after wheel desaturation scaled it further down).
  void overrideLast(const Twist2D& twist) { last_ = twist; }
  void reset(const Twist2D& current = Twist2D{});
  const Twist2D& last() const { return last_; }

private:
  SpeedLimiter vx_, vy_, wz_;
  Twist2D last_, before_last_;
  double last_dt_ = 0.0;
};

// Factor in (0, 1] by which all speeds must be scaled so that none exceeds max_speed in
// magnitude; scaling all wheels by the same factor keeps the path's curvature (v/w for a
// diff drive, the direction of travel for a swerve). max_speed <= 0 disables.
double desaturationFactor(const std::vector<double>& speeds, double max_speed);
// Diff-drive convenience: scales the wheels in place, returns the factor applied.
double desaturate(WheelVelocities& wheels, double max_speed);

}  // namespace mybot_control
