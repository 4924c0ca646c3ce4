// Velocity/acceleration/jerk limits on a holonomic twist that keep the shape of the path:
// the output moves along the straight line (in twist space) from the last output to the
// command, by the largest common fraction every axis allows. From rest, the direction of
// travel and the translation/rotation ratio (the curvature) are those of the command, where
// per-axis limiting would bend the path while one axis is still ramping. Built on the
// per-axis SpeedLimiter (diff_drive_controller's parameters).
#pragma once

#include <array>

#include "mybot_control/kinematics.hpp"
#include "mybot_control/speed_limiter.hpp"

namespace mybot_control
{

class SwerveTwistLimiter
{
public:
  SwerveTwistLimiter() = default;
  SwerveTwistLimiter(const SpeedLimits& vx, const SpeedLimits& vy, const SpeedLimits& wz)
      : axes_{SpeedLimiter(vx), SpeedLimiter(vy), SpeedLimiter(wz)}
  {
  }

  Twist2D limit(const Twist2D& command, double dt);
  void overrideLast(const Twist2D& twist) { last_ = twist; }
  void reset(const Twist2D& current = Twist2D{});
  const Twist2D& last() const { return last_; }

private:
  std::array<SpeedLimiter, 3> axes_;
  Twist2D last_, before_last_;
  double last_dt_ = 0.0;
};

}  // namespace mybot_control
