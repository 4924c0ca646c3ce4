#include "mybot_control/kinematics.hpp"

namespace mybot_control
{

namespace
{
// sin(t)/t and (1 - cos(t))/t with Taylor series near 0.
void arcCoefficients(double t, double small_angle, double& s, double& c)
{
  if (std::abs(t) < small_angle)
  {
    s = 1.0 - t * t / 6.0;
    c = t / 2.0;
  }
  else
  {
    const double h = std::sin(0.5 * t);
    s = std::sin(t) / t;
    c = 2.0 * h * h / t;  // (1 - cos t) / t without the cancellation
  }
}
}  // namespace

Pose2D poseExp(const Pose2D& pose, const Twist2D& d, double small_angle)
{
  double lx, ly;
  if (std::abs(d.wz) < small_angle)
  {
    // Second-order fallback: translate along the mid-step heading.
    const double ch = std::cos(0.5 * d.wz), sh = std::sin(0.5 * d.wz);
    lx = ch * d.vx - sh * d.vy;
    ly = sh * d.vx + ch * d.vy;
  }
  else
  {
    double s, c;
    arcCoefficients(d.wz, 0.0, s, c);
    lx = s * d.vx - c * d.vy;
    ly = c * d.vx + s * d.vy;
  }
  const double ct = std::cos(pose.theta), st = std::sin(pose.theta);
  return {pose.x + ct * lx - st * ly, pose.y + st * lx + ct * ly, wrapAngle(pose.theta + d.wz)};
}

Twist2D poseLog(const Pose2D& from, const Pose2D& to)
{
  const double ct = std::cos(from.theta), st = std::sin(from.theta);
  const double gx = to.x - from.x, gy = to.y - from.y;
  const double tx = ct * gx + st * gy, ty = -st * gx + ct * gy;
  const double dtheta = wrapAngle(to.theta - from.theta);
  double s, c;
  arcCoefficients(dtheta, 1e-4, s, c);
  const double k = 1.0 / (s * s + c * c);  // inverse of [[s, -c], [c, s]]
  return {k * (s * tx + c * ty), k * (-c * tx + s * ty), dtheta};
}

DiffDriveKinematics::DiffDriveKinematics(double wheel_separation, double left_radius, double right_radius)
    : separation_(wheel_separation), left_radius_(left_radius), right_radius_(right_radius)
{
}

WheelVelocities DiffDriveKinematics::toWheelTangent(const Twist2D& t) const
{
  const double half = 0.5 * separation_ * t.wz;
  return {t.vx - half, t.vx + half};
}

Twist2D DiffDriveKinematics::fromWheelTangent(const WheelVelocities& w) const
{
  return {0.5 * (w.left + w.right), 0.0, (w.right - w.left) / separation_};
}

WheelVelocities DiffDriveKinematics::toWheelAngular(const Twist2D& t) const
{
  const WheelVelocities v = toWheelTangent(t);
  return {v.left / left_radius_, v.right / right_radius_};
}

Twist2D DiffDriveKinematics::fromWheelAngular(const WheelVelocities& w) const
{
  return fromWheelTangent({w.left * left_radius_, w.right * right_radius_});
}

}  // namespace mybot_control
