#include "mybot_control/swerve_limiter.hpp"

#include <algorithm>
#include <cmath>

namespace mybot_control
{

namespace
{
std::array<double, 3> arr(const Twist2D& t)
{
  return {t.vx, t.vy, t.wz};
}
}  // namespace

Twist2D SwerveTwistLimiter::limit(const Twist2D& command, double dt)
{
  if (!(dt > 0.0) || !command.finite())
    return last_;
  const auto c = arr(command), l = arr(last_), b = arr(before_last_);

  // Velocity limits: one factor for all axes (the direction of the command is kept).
  double k = 1.0;
  for (std::size_t i = 0; i < 3; ++i)
  {
    double v = c[i];
    axes_[i].limitVelocity(v);
    if (c[i] != 0.0)
      k = std::min(k, std::max(0.0, v / c[i]));
  }
  std::array<double, 3> target{c[0] * k, c[1] * k, c[2] * k};

  // Acceleration and jerk: the step each axis may take, then the smallest common fraction.
  double f = 1.0;
  for (std::size_t i = 0; i < 3; ++i)
  {
    const double step = target[i] - l[i];
    if (std::abs(step) < 1e-12)
      continue;
    double v = target[i];
    axes_[i].limitJerk(v, l[i], b[i], dt, last_dt_);
    axes_[i].limitAcceleration(v, l[i], dt);
    f = std::min(f, std::clamp((v - l[i]) / step, 0.0, 1.0));
  }
  const Twist2D out{l[0] + f * (target[0] - l[0]), l[1] + f * (target[1] - l[1]), l[2] + f * (target[2] - l[2])};
  before_last_ = last_;
  last_ = out;
  last_dt_ = dt;
  return out;
}

void SwerveTwistLimiter::reset(const Twist2D& current)
{
  last_ = current;
  before_last_ = current;
  last_dt_ = 0.0;
}

}  // namespace mybot_control
