#include "mybot_control/odometry.hpp"

#include <cmath>

namespace mybot_control
{

double unwrappedDelta(double previous, double current, double period)
{
  const double d = current - previous;
  return period > 0.0 ? std::remainder(d, period) : d;
}

RollingMean::RollingMean(std::size_t window) : window_(window == 0 ? 1 : window) {}

void RollingMean::setWindow(std::size_t window)
{
  window_ = window == 0 ? 1 : window;
  reset();
}

void RollingMean::push(double v)
{
  values_.push_back(v);
  if (values_.size() > window_)
    values_.pop_front();
}

void RollingMean::reset()
{
  values_.clear();
}

double RollingMean::mean() const
{
  if (values_.empty())
    return 0.0;
  // Summed afresh (windows are short): no running-sum drift, exact zero for zeros.
  double s = 0.0;
  for (double v : values_)
    s += v;
  return s / static_cast<double>(values_.size());
}

WheelEncoder::WheelEncoder(std::size_t window, double period) : window_(window == 0 ? 1 : window), period_(period) {}

bool WheelEncoder::update(double position, double t)
{
  if (!std::isfinite(position) || !std::isfinite(t))
    return false;
  if (samples_.empty())
  {
    samples_.push_back({t, position});
    raw_previous_ = position;
    return true;
  }
  if (t <= samples_.back().t)
    return false;
  const double unwrapped = samples_.back().position + unwrappedDelta(raw_previous_, position, period_);
  raw_previous_ = position;
  samples_.push_back({t, unwrapped});
  if (samples_.size() > window_ + 1)
    samples_.pop_front();
  velocity_ = (samples_.back().position - samples_.front().position) / (samples_.back().t - samples_.front().t);
  return true;
}

void WheelEncoder::reset()
{
  samples_.clear();
  velocity_ = 0.0;
}

DiffDriveOdometry::DiffDriveOdometry(const Params& params)
    : params_(params),
      kin_(params.wheel_separation, params.left_radius, params.right_radius),
      integrator_(params.velocity_window)
{
}

bool DiffDriveOdometry::update(double left_position, double right_position, double t)
{
  if (!std::isfinite(left_position) || !std::isfinite(right_position) || !std::isfinite(t))
    return false;
  if (!have_reference_)
  {
    left_prev_ = left_position;
    right_prev_ = right_position;
    t_prev_ = t;
    have_reference_ = true;
    return true;
  }
  const double dt = t - t_prev_;
  if (dt <= 0.0)
    return false;

  const double dl = unwrappedDelta(left_prev_, left_position, params_.encoder_period) * params_.left_radius;
  const double dr = unwrappedDelta(right_prev_, right_position, params_.encoder_period) * params_.right_radius;
  left_prev_ = left_position;
  right_prev_ = right_position;
  t_prev_ = t;

  const Twist2D delta = kin_.fromWheelTangent({dl, dr});
  integrator_.integrate(delta, dt);
  wheel_tangent_ = {dl / dt, dr / dt};
  return true;
}

void DiffDriveOdometry::resetEncoders()
{
  have_reference_ = false;
  integrator_.resetTwist();
  wheel_tangent_ = {};
}

void DiffDriveOdometry::setPose(const Pose2D& pose)
{
  integrator_.setPose(pose);
}

}  // namespace mybot_control
