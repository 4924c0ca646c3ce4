#include "mybot_control/swerve_kinematics.hpp"

#include <cmath>
#include <stdexcept>

#include "mybot_control/speed_limiter.hpp"

namespace mybot_control
{

SwerveModuleState optimizeModuleState(const SwerveModuleState& desired, double current_angle)
{
  const double delta = wrapAngle(desired.angle - current_angle);
  if (std::abs(delta) > 0.5 * M_PI)
    return {-desired.speed, wrapAngle(desired.angle + M_PI)};
  return {desired.speed, wrapAngle(desired.angle)};
}

SwerveModuleState cosineScale(const SwerveModuleState& desired, double current_angle)
{
  const double c = std::cos(wrapAngle(desired.angle - current_angle));
  return {desired.speed * std::max(0.0, c), desired.angle};
}

double desaturateModuleSpeeds(std::vector<SwerveModuleState>& states, double max_speed)
{
  std::vector<double> speeds;
  speeds.reserve(states.size());
  for (const auto& s : states)
    speeds.push_back(s.speed);
  const double k = desaturationFactor(speeds, max_speed);
  for (auto& s : states)
    s.speed *= k;
  return k;
}

Twist2D discretize(const Twist2D& twist, double dt)
{
  if (!(dt > 0.0))
    return twist;
  // The straight-then-turn step WPILib assumes, as a pose; log() gives the constant twist
  // that reaches it along an arc.
  const Pose2D step{twist.vx * dt, twist.vy * dt, twist.wz * dt};
  return poseLog(Pose2D{}, step) * (1.0 / dt);
}

Twist2D fromFieldRelative(const Twist2D& field, double yaw)
{
  const double c = std::cos(yaw), s = std::sin(yaw);
  return {c * field.vx + s * field.vy, -s * field.vx + c * field.vy, field.wz};
}

std::string SwerveKinematics::validate(const std::vector<Vec2>& offsets, double min_separation)
{
  if (offsets.size() < 2)
    return "needs at least 2 modules (got " + std::to_string(offsets.size()) + ")";
  for (std::size_t i = 0; i < offsets.size(); ++i)
  {
    if (!std::isfinite(offsets[i].x) || !std::isfinite(offsets[i].y))
      return "module " + std::to_string(i) + " offset is not finite";
    for (std::size_t j = 0; j < i; ++j)
      if (std::hypot(offsets[i].x - offsets[j].x, offsets[i].y - offsets[j].y) < min_separation)
        return "modules " + std::to_string(j) + " and " + std::to_string(i) + " are at the same offset (" +
               std::to_string(offsets[i].x) + ", " + std::to_string(offsets[i].y) + ")";
  }
  return "";
}

SwerveKinematics::SwerveKinematics(const std::vector<Vec2>& offsets) : offsets_(offsets), headings_(offsets.size(), 0.0)
{
  const std::string err = validate(offsets);
  if (!err.empty())
    throw std::invalid_argument("swerve modules: " + err);
  // Rows per module: [1 0 -y; 0 1 x] maps (vx, vy, wz) to the module's velocity.
  const Eigen::Index n = static_cast<Eigen::Index>(offsets.size());
  Eigen::MatrixXd inverse(2 * n, 3);
  for (Eigen::Index i = 0; i < n; ++i)
  {
    const Vec2& r = offsets[static_cast<std::size_t>(i)];
    inverse.row(2 * i) << 1.0, 0.0, -r.y;
    inverse.row(2 * i + 1) << 0.0, 1.0, r.x;
  }
  // Full column rank (two distinct modules suffice), so the pseudo-inverse is the normal-equations one.
  forward_ = (inverse.transpose() * inverse).inverse() * inverse.transpose();
}

std::vector<SwerveModuleState> SwerveKinematics::toModuleStates(const Twist2D& twist, const Vec2& center)
{
  std::vector<SwerveModuleState> states(offsets_.size());
  for (std::size_t i = 0; i < offsets_.size(); ++i)
  {
    const double vx = twist.vx - twist.wz * (offsets_[i].y - center.y);
    const double vy = twist.vy + twist.wz * (offsets_[i].x - center.x);
    const double speed = std::hypot(vx, vy);
    // Heading hold: atan2(0, 0) means nothing, keep the last heading.
    if (speed > 1e-9)
      headings_[i] = std::atan2(vy, vx);
    states[i] = {speed, headings_[i]};
  }
  return states;
}

void SwerveKinematics::resetHeadings(const std::vector<double>& angles)
{
  if (angles.size() != headings_.size())
    throw std::invalid_argument("resetHeadings: expected " + std::to_string(headings_.size()) + " angles");
  for (std::size_t i = 0; i < angles.size(); ++i)
    headings_[i] = wrapAngle(angles[i]);
}

namespace
{
Twist2D solve(const Eigen::Matrix<double, 3, Eigen::Dynamic>& forward, const Eigen::VectorXd& v)
{
  const Eigen::Vector3d t = forward * v;
  return {t(0), t(1), t(2)};
}
}  // namespace

Twist2D SwerveKinematics::toTwist(const std::vector<SwerveModuleState>& states) const
{
  if (states.size() != offsets_.size())
    throw std::invalid_argument("toTwist: expected " + std::to_string(offsets_.size()) + " module states");
  Eigen::VectorXd v(2 * states.size());
  for (std::size_t i = 0; i < states.size(); ++i)
  {
    v(2 * i) = states[i].speed * std::cos(states[i].angle);
    v(2 * i + 1) = states[i].speed * std::sin(states[i].angle);
  }
  return solve(forward_, v);
}

Twist2D SwerveKinematics::toTwist(const std::vector<SwerveModulePosition>& deltas) const
{
  if (deltas.size() != offsets_.size())
    throw std::invalid_argument("toTwist: expected " + std::to_string(offsets_.size()) + " module deltas");
  Eigen::VectorXd v(2 * deltas.size());
  for (std::size_t i = 0; i < deltas.size(); ++i)
  {
    v(2 * i) = deltas[i].distance * std::cos(deltas[i].angle);
    v(2 * i + 1) = deltas[i].distance * std::sin(deltas[i].angle);
  }
  return solve(forward_, v);
}

}  // namespace mybot_control
