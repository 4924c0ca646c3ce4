#include "mybot_control/swerve_odometry.hpp"

#include <cmath>
#include <stdexcept>

namespace mybot_control
{

namespace
{
const SwerveOdometry::Params& checked(const SwerveOdometry::Params& p)
{
  if (!(p.wheel_radius > 0.0) || !std::isfinite(p.wheel_radius))
    throw std::invalid_argument("wheel_radius must be > 0 (got " + std::to_string(p.wheel_radius) + ")");
  if (!(p.imu_weight >= 0.0 && p.imu_weight <= 1.0))
    throw std::invalid_argument("imu_weight must be within [0, 1]");
  if (!(p.encoder_period >= 0.0))
    throw std::invalid_argument("encoder_period must be >= 0");
  return p;
}
}  // namespace

SwerveOdometry::SwerveOdometry(const Params& params)
    : IntegratedOdometry(params.velocity_window),
      params_(checked(params)),
      kin_(params.offsets),
      deltas_(params.offsets.size())
{
}

bool SwerveOdometry::update(const std::vector<double>& wheels, const std::vector<double>& pivots, double t,
                            std::optional<double> imu_yaw)
{
  const std::size_t n = kin_.size();
  if (wheels.size() != n || pivots.size() != n || !std::isfinite(t))
    return false;
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(wheels[i]) || !std::isfinite(pivots[i]))
      return false;
  if (imu_yaw && !std::isfinite(*imu_yaw))
    imu_yaw.reset();  // a bad IMU sample: fall back to the wheels for this step

  if (!have_reference_)
  {
    wheel_prev_ = wheels;
    pivot_prev_ = pivots;
    imu_prev_ = imu_yaw;
    t_prev_ = t;
    have_reference_ = true;
    return true;
  }
  if (t <= t_prev_)
    return false;

  for (std::size_t i = 0; i < n; ++i)
  {
    const double rolled = unwrappedDelta(wheel_prev_[i], wheels[i], params_.encoder_period);
    // The pivot's mid-step angle (WPILib uses the end angle): second-order accurate while the
    // module turns during the step.
    const double mid = pivot_prev_[i] + 0.5 * wrapAngle(pivots[i] - pivot_prev_[i]);
    deltas_[i] = {rolled * params_.wheel_radius, mid};
  }
  Twist2D d = kin_.toTwist(deltas_);
  if (imu_yaw && imu_prev_ && params_.imu_weight > 0.0)
  {
    const double imu_d = wrapAngle(*imu_yaw - *imu_prev_);
    d.wz = (1.0 - params_.imu_weight) * d.wz + params_.imu_weight * imu_d;
  }
  integrator_.integrate(d, t - t_prev_);

  wheel_prev_ = wheels;
  pivot_prev_ = pivots;
  imu_prev_ = imu_yaw;  // a missed IMU sample restarts its reference: no multi-step delta
  t_prev_ = t;
  return true;
}

void SwerveOdometry::resetEncoders()
{
  have_reference_ = false;
  imu_prev_.reset();
  integrator_.resetTwist();
}

void SwerveOdometry::reset()
{
  setPose(Pose2D{});
  resetEncoders();
  integrator_.resetDistance();
}

}  // namespace mybot_control
