#include "mybot_control/speed_limiter.hpp"

#include <algorithm>
#include <cmath>

namespace mybot_control
{

SpeedLimits SpeedLimits::symmetric(double max_velocity, double max_acceleration, double max_jerk)
{
  SpeedLimits l;
  l.has_velocity_limits = max_velocity > 0.0;
  l.max_velocity = max_velocity;
  l.min_velocity = -max_velocity;
  l.has_acceleration_limits = max_acceleration > 0.0;
  l.max_acceleration = max_acceleration;
  l.min_acceleration = -max_acceleration;
  l.has_jerk_limits = max_jerk > 0.0;
  l.max_jerk = max_jerk;
  l.min_jerk = -max_jerk;
  return l;
}

std::string SpeedLimits::validate(const std::string& prefix) const
{
  auto bad = [&](const char* field, const char* why) { return prefix + field + " " + why; };
  const double values[] = {min_velocity, max_velocity, min_acceleration, max_acceleration,
                           max_deceleration, min_jerk, max_jerk};
  const char* names[] = {"min_velocity", "max_velocity", "min_acceleration", "max_acceleration",
                         "max_deceleration", "min_jerk", "max_jerk"};
  for (int k = 0; k < 7; ++k)
    if (!std::isfinite(values[k]))
      return bad(names[k], "must be a finite number");
  if (has_velocity_limits && min_velocity > max_velocity)
    return bad("min_velocity", "must not exceed max_velocity");
  if (has_acceleration_limits && !(min_acceleration < 0.0 && max_acceleration > 0.0))
    return bad("max_acceleration", "must be > 0 (and min_acceleration < 0)");
  if (has_deceleration_limits && !(max_deceleration > 0.0))
    return bad("max_deceleration", "must be > 0 (a magnitude)");
  if (has_jerk_limits && !(min_jerk < 0.0 && max_jerk > 0.0))
    return bad("max_jerk", "must be > 0 (and min_jerk < 0)");
  return "";
}

double SpeedLimiter::limit(double& v, double v0, double v1, double dt) const
{
  const double requested = v;
  limitJerk(v, v0, v1, dt);
  limitAcceleration(v, v0, dt);
  limitVelocity(v);
  return requested != 0.0 ? v / requested : 1.0;
}

double SpeedLimiter::limitVelocity(double& v) const
{
  const double requested = v;
  if (limits_.has_velocity_limits)
    v = std::clamp(v, limits_.min_velocity, limits_.max_velocity);
  return requested != 0.0 ? v / requested : 1.0;
}

double SpeedLimiter::limitAcceleration(double& v, double v0, double dt) const
{
  const double requested = v;
  double dv_min = -std::numeric_limits<double>::infinity();
  double dv_max = std::numeric_limits<double>::infinity();
  if (limits_.has_acceleration_limits)
  {
    dv_min = limits_.min_acceleration * dt;
    dv_max = limits_.max_acceleration * dt;
  }
  if (limits_.has_deceleration_limits)
  {
    // Slowing down towards zero (and through it within this step) is braking.
    const double brake = limits_.max_deceleration * dt;
    if (v0 > 0.0 && v < v0)
      dv_min = -brake;
    else if (v0 < 0.0 && v > v0)
      dv_max = brake;
  }
  v = v0 + std::clamp(v - v0, dv_min, dv_max);
  return requested != 0.0 ? v / requested : 1.0;
}

double SpeedLimiter::limitJerk(double& v, double v0, double v1, double dt) const
{
  const double requested = v;
  if (limits_.has_jerk_limits && dt > 0.0)
  {
    // Change of the per-step velocity increment: jerk * dt^2.
    const double dv = v - v0, dv0 = v0 - v1;
    const double dt2 = dt * dt;
    v = v0 + dv0 + std::clamp(dv - dv0, limits_.min_jerk * dt2, limits_.max_jerk * dt2);
  }
  return requested != 0.0 ? v / requested : 1.0;
}

TwistLimiter::TwistLimiter(const SpeedLimits& vx, const SpeedLimits& vy, const SpeedLimits& wz)
  : vx_(vx), vy_(vy), wz_(wz)
{
}

Twist2D TwistLimiter::limit(const Twist2D& command, double dt)
{
  Twist2D out = command;
  if (dt > 0.0)
  {
    vx_.limit(out.vx, last_.vx, before_last_.vx, dt);
    vy_.limit(out.vy, last_.vy, before_last_.vy, dt);
    wz_.limit(out.wz, last_.wz, before_last_.wz, dt);
  }
  else
  {
    out = last_;
  }
  before_last_ = last_;
  last_ = out;
  return out;
}

void TwistLimiter::reset(const Twist2D& current)
{
  last_ = current;
  before_last_ = current;
}

double desaturationFactor(const std::vector<double>& speeds, double max_speed)
{
  if (!(max_speed > 0.0))
    return 1.0;
  double largest = 0.0;
  for (double s : speeds)
    largest = std::max(largest, std::abs(s));
  return largest > max_speed ? max_speed / largest : 1.0;
}

double desaturate(WheelVelocities& wheels, double max_speed)
{
  const double k = desaturationFactor({wheels.left, wheels.right}, max_speed);
  wheels.left *= k;
  wheels.right *= k;
  return k;
}

}  // namespace mybot_control
