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
  const double values[] = {min_velocity,     max_velocity, min_acceleration, max_acceleration,
                           max_deceleration, min_jerk,     max_jerk};
  const char* names[] = {"min_velocity",     "max_velocity", "min_acceleration", "max_acceleration",
                         "max_deceleration", "min_jerk",     "max_jerk"};
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

double SpeedLimiter::limit(double& v, double v0, double v1, double dt, double dt_prev) const
{
  const double requested = v;
  // Aim at the reachable target: the jerk-limited ramp then lands on the velocity limit
  // instead of being cut off by it (which would be an unbounded jerk).
  limitVelocity(v);
  limitJerk(v, v0, v1, dt, dt_prev);
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

double SpeedLimiter::limitJerk(double& v, double v0, double v1, double dt, double dt_prev) const
{
  const double requested = v;
  if (limits_.has_jerk_limits && dt > 0.0)
  {
    // The acceleration may change by at most jerk * dt from the previous step's (taken over
    // its own period, so uneven steps are handled). With equal periods this is upstream's
    // bound on the change of the per-step increment (without its extra factor 2).
    const double a0 = (v0 - v1) / (dt_prev > 0.0 ? dt_prev : dt);
    // Approach the target no faster than the acceleration can be ramped back to zero at the
    // jerk limit on arrival: with steps a = n*j*dt, n*j*dt, (n-1)*j*dt, ... the remaining
    // change covered is j*dt^2*n*(n+1)/2, so no overshoot at a stop or a limit.
    const double dv = v - v0;
    const double j_out = dv > 0.0 ? -limits_.min_jerk : limits_.max_jerk;
    const double jdt2 = j_out * dt * dt;
    const double n = 0.5 * (std::sqrt(1.0 + 8.0 * std::abs(dv) / jdt2) - 1.0);
    const double a_cap = n * j_out * dt;
    const double a_wanted = std::clamp(dv / dt, -a_cap, a_cap);
    const double a = std::clamp(a_wanted, a0 + limits_.min_jerk * dt, a0 + limits_.max_jerk * dt);
    v = v0 + a * dt;
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
    vx_.limit(out.vx, last_.vx, before_last_.vx, dt, last_dt_);
    vy_.limit(out.vy, last_.vy, before_last_.vy, dt, last_dt_);
    wz_.limit(out.wz, last_.wz, before_last_.wz, dt, last_dt_);
    last_dt_ = dt;
  }
  else
  {
    return last_;
  }
  before_last_ = last_;
  last_ = out;
  return out;
}

void TwistLimiter::reset(const Twist2D& current)
{
  last_ = current;
  before_last_ = current;
  last_dt_ = 0.0;
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
