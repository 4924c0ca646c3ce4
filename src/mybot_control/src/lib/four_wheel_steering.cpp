#include "mybot_control/four_wheel_steering.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace mybot_control
{

namespace
{
// A wheel's pivot in the body frame, and which side it is on (+1 left, -1 right).
struct Pivot
{
  double x, y, side;
};

std::array<Pivot, 4> pivots(const FourWheelSteeringGeometry& g)
{
  const double hx = 0.5 * g.wheel_base, hy = 0.5 * g.steering_track;
  return {{{hx, hy, 1.0}, {hx, -hy, -1.0}, {-hx, hy, 1.0}, {-hx, -hy, -1.0}}};
}
}  // namespace

std::string FourWheelSteeringGeometry::validate() const
{
  if (!(wheel_base > 0.0) || !std::isfinite(wheel_base))
    return "wheel_base must be positive";
  if (!(steering_track > 0.0) || !std::isfinite(steering_track))
    return "the steering track (track - 2 wheel_steering_y_offset) must be positive";
  if (!(wheel_radius > 0.0) || !std::isfinite(wheel_radius))
    return "wheel_radius must be positive";
  if (!std::isfinite(steering_y_offset))
    return "wheel_steering_y_offset must be finite";
  return "";
}

std::array<SteeredWheelCommand, 4> fourWheelSteeringCommands(const FourWheelSteeringGeometry& g, const Twist2D& t)
{
  std::array<SteeredWheelCommand, 4> out{};
  if (t.vx == 0.0 && t.vy == 0.0 && t.wz == 0.0)
    return out;
  const std::array<Pivot, 4> ps = pivots(g);
  for (std::size_t i = 0; i < 4; ++i)
  {
    const Pivot& p = ps[i];
    const double vx = t.vx - t.wz * p.y, vy = t.vy + t.wz * p.x;
    double angle = std::atan2(vy, vx), sign = 1.0;
    if (angle > M_PI_2)
      angle -= M_PI, sign = -1.0;
    else if (angle < -M_PI_2)
      angle += M_PI, sign = -1.0;
    out[i].steering = angle;
    out[i].spin = (sign * std::hypot(vx, vy) - t.wz * p.side * g.steering_y_offset) / g.wheel_radius;
  }
  return out;
}

Twist2D fourWheelSteeringTwist(const FourWheelSteeringGeometry& g, double speed, double front, double rear)
{
  front = std::clamp(front, -M_PI_2, M_PI_2);
  rear = std::clamp(rear, -M_PI_2, M_PI_2);
  const double sf = std::sin(front), cf = std::cos(front), sr = std::sin(rear), cr = std::cos(rear);
  // The centre's velocity is midway between the axle centres' (the bicycle model): its direction
  // has the tangent (tan(front) + tan(rear)) / 2, written without dividing by a cosine so that a
  // wheel steered sideways (front or rear at +-pi/2) stays finite.
  if (cf < 1e-9 && cr < 1e-9)  // both axles sideways
  {
    if (sf * sr > 0.0)
      return {0.0, sf > 0.0 ? speed : -speed, 0.0};
    return {0.0, 0.0, (sf > 0.0 ? 2.0 : -2.0) * speed / g.wheel_base};  // opposite ways: on the spot
  }
  const double a = sf * cr + sr * cf, b = 2.0 * cf * cr, n = std::hypot(a, b);
  return {speed * b / n, speed * a / n, 2.0 * speed * (sf * cr - sr * cf) / (n * g.wheel_base)};
}

double equivalentSteering(double left, double right)
{
  if (std::abs(left) <= 0.001 && std::abs(right) <= 0.001)
    return 0.0;
  const double tl = std::tan(left), tr = std::tan(right);
  if (std::abs(tl + tr) < 1e-12)
    return 0.0;
  return std::atan(2.0 * tl * tr / (tl + tr));
}

FourWheelSteeringOdometry::FourWheelSteeringOdometry(const Params& params)
    : IntegratedOdometry(params.velocity_window), params_(params)
{
}

bool FourWheelSteeringOdometry::update(const std::array<double, 4>& wheels, const std::array<double, 4>& steering,
                                       double t)
{
  const auto r = readings_.take(
      {wheels[0], wheels[1], wheels[2], wheels[3], steering[0], steering[1], steering[2], steering[3]}, t);
  if (r != EncoderReadings<8>::STEP)
    return r == EncoderReadings<8>::REFERENCE;
  const FourWheelSteeringGeometry& g = params_.geometry;
  const std::array<Pivot, 4> ps = pivots(g);
  // Each pivot moved (rolled + side * offset * dtheta) along its heading h, and as the body
  // moved it: (dx - p.y dtheta, dy + p.x dtheta). Two equations per wheel, eight for three unknowns.
  Eigen::Matrix<double, 8, 3> A;
  Eigen::Matrix<double, 8, 1> y;
  for (std::size_t i = 0; i < 4; ++i)
  {
    const Pivot& p = ps[i];
    const double rolled = unwrappedDelta(readings_.before()[i], wheels[i], params_.encoder_period) * g.wheel_radius;
    const double angle = 0.5 * (readings_.before()[4 + i] + steering[i]);  // the step's mean heading
    const double hx = std::cos(angle), hy = std::sin(angle), k = p.side * g.steering_y_offset;
    A.row(2 * i) << 1.0, 0.0, -p.y - k * hx;
    A.row(2 * i + 1) << 0.0, 1.0, p.x - k * hy;
    y(2 * i) = rolled * hx;
    y(2 * i + 1) = rolled * hy;
  }
  const Eigen::Vector3d d = (A.transpose() * A).ldlt().solve(A.transpose() * y);
  integrator_.integrate({d(0), d(1), d(2)}, readings_.dt());
  return true;
}

void FourWheelSteeringOdometry::resetEncoders()
{
  readings_.reset();
  integrator_.resetTwist();
}

}  // namespace mybot_control
