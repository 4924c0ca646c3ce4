// Planar kinematics value types shared by the diff-drive and swerve stacks.
// No ROS types: these are plain structs and pure functions.
#pragma once

#include <cmath>

#include "mybot_common/pose2d.h"

namespace mybot_control
{

// Body twist: vx, vy (m/s) in the body frame, wz (rad/s).
struct Twist2D
{
  double vx = 0.0;
  double vy = 0.0;
  double wz = 0.0;

  Twist2D operator*(double s) const { return {vx * s, vy * s, wz * s}; }
  bool finite() const { return std::isfinite(vx) && std::isfinite(vy) && std::isfinite(wz); }
};

// The workspace's one SE(2) pose and angle wrap (to (-pi, pi]), shared with the navigation stack.
using mybot_common::Pose2D;
using mybot_common::wrapAngle;

// Integrate a body-frame displacement (dx, dy, dtheta) -- a twist times dt -- from `pose`
// along the constant-twist path (the SE(2) exponential). Exact for any dtheta; when
// |dtheta| < small_angle the closed form is numerically unstable and a second-order
// (midpoint heading) step is used instead, whose error is O(dtheta^3).
Pose2D poseExp(const Pose2D& pose, const Twist2D& delta, double small_angle = 1e-6);

// The inverse: the body displacement that takes `from` to `to` along a constant twist.
Twist2D poseLog(const Pose2D& from, const Pose2D& to);

// Wheel velocities of a differential drive, tangential (m/s) at the wheel rim.
struct WheelVelocities
{
  double left = 0.0;
  double right = 0.0;
};

class DiffDriveKinematics
{
public:
  DiffDriveKinematics() = default;
  DiffDriveKinematics(double wheel_separation, double left_radius, double right_radius);

  double wheelSeparation() const { return separation_; }
  double leftRadius() const { return left_radius_; }
  double rightRadius() const { return right_radius_; }

  // Body twist (vy ignored: a diff drive cannot strafe) -> rim speeds (m/s).
  WheelVelocities toWheelTangent(const Twist2D& twist) const;
  // Rim speeds (m/s) -> body twist.
  Twist2D fromWheelTangent(const WheelVelocities& wheels) const;
  // Same in wheel angular velocity (rad/s), using each wheel's radius.
  WheelVelocities toWheelAngular(const Twist2D& twist) const;
  Twist2D fromWheelAngular(const WheelVelocities& wheels) const;

private:
  double separation_ = 1.0;
  double left_radius_ = 1.0;
  double right_radius_ = 1.0;
};

}  // namespace mybot_control
