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
  const auto r = readings_.take({position}, t);
  if (r == EncoderReadings<1>::REJECTED)
    return false;
  if (r == EncoderReadings<1>::REFERENCE)
  {
    samples_.push_back({t, position});
    return true;
  }
  samples_.push_back({t, samples_.back().position + unwrappedDelta(readings_.before()[0], position, period_)});
  if (samples_.size() > window_ + 1)
    samples_.pop_front();
  velocity_ = (samples_.back().position - samples_.front().position) / (samples_.back().t - samples_.front().t);
  return true;
}

void WheelEncoder::reset()
{
  readings_.reset();
  samples_.clear();
  velocity_ = 0.0;
}

DiffDriveOdometry::DiffDriveOdometry(const Params& params)
    : IntegratedOdometry(params.velocity_window),
      params_(params),
      kin_(params.wheel_separation, params.left_radius, params.right_radius)
{
}

bool DiffDriveOdometry::update(double left_position, double right_position, double t)
{
  const auto r = readings_.take({left_position, right_position}, t);
  if (r != EncoderReadings<2>::STEP)
    return r == EncoderReadings<2>::REFERENCE;
  const double dt = readings_.dt();
  const double dl = unwrappedDelta(readings_.before()[0], left_position, params_.encoder_period) * params_.left_radius;
  const double dr =
      unwrappedDelta(readings_.before()[1], right_position, params_.encoder_period) * params_.right_radius;
  const Twist2D delta = kin_.fromWheelTangent({dl, dr});
  integrator_.integrate(delta, dt);
  wheel_tangent_ = {dl / dt, dr / dt};
  return true;
}

void DiffDriveOdometry::resetEncoders()
{
  readings_.reset();
  integrator_.resetTwist();
  wheel_tangent_ = {};
}

AckermannOdometry::AckermannOdometry(const Params& params) : IntegratedOdometry(params.velocity_window), params_(params)
{
}

bool AckermannOdometry::update(double wheel_position, double steering_angle, double t)
{
  const auto r = readings_.take({wheel_position, steering_angle}, t);
  if (r != EncoderReadings<2>::STEP)
    return r == EncoderReadings<2>::REFERENCE;
  const double s = unwrappedDelta(readings_.before()[0], wheel_position, params_.encoder_period) * params_.wheel_radius;
  const double delta = 0.5 * (readings_.before()[1] + steering_angle);
  integrator_.integrate({s, 0.0, s * std::tan(delta) / params_.wheelbase}, readings_.dt());
  return true;
}

void AckermannOdometry::resetEncoders()
{
  readings_.reset();
  integrator_.resetTwist();
}

}  // namespace mybot_control
