// Pure pieces of the emulated gazebo_ros plugins (diff drive, laser model).
#pragma once

#include <cmath>
#include <limits>
#include <utility>

namespace mybot_gazebo_lite
{

struct DiffDriveGeometry
{
  double separation = 0.34;  // gazebo_ros_diff_drive defaults
  double diameter = 0.15;
  bool legacy = true;
};

// Wheel tangential speeds (left, right) in m/s for a body twist. legacyMode
// swaps the sign of the turn, exactly as gazebo_ros_diff_drive does.
inline std::pair<double, double> diffDriveWheelSpeeds(double v, double w, const DiffDriveGeometry& g)
{
  double d = w * g.separation / 2.0;
  return g.legacy ? std::make_pair(v + d, v - d) : std::make_pair(v - d, v + d);
}

// gazebo_ros_diff_drive's wheelAcceleration ramp (m/s^2 on the wheel rim; 0 = none).
inline double rampWheelSpeed(double instructed, double target, double current, double accel, double dt)
{
  if (accel <= 0 || std::abs(target - current) < 0.01)
    return target;
  double step = target - current;
  double lim = accel * dt;
  return instructed + std::max(-lim, std::min(lim, step));
}

// Dead reckoning from wheel joint velocities (the plugin's odometrySource=encoder).
struct EncoderOdometry
{
  double x = 0, y = 0, theta = 0, v = 0, w = 0;
  void update(double wl, double wr, double dt, const DiffDriveGeometry& g)
  {
    if (dt <= 0)
      return;
    double sl = wl * g.diameter / 2.0 * dt, sr = wr * g.diameter / 2.0 * dt;
    double ssum = sl + sr;
    double sdiff = g.legacy ? sl - sr : sr - sl;
    double dx = ssum / 2.0 * std::cos(theta + sdiff / (2.0 * g.separation));
    double dy = ssum / 2.0 * std::sin(theta + sdiff / (2.0 * g.separation));
    double dth = sdiff / g.separation;
    x += dx;
    y += dy;
    theta += dth;
    v = ssum / 2.0 / dt;
    w = dth / dt;
  }
};

// Gazebo classic's ray semantics (REP 117): at or beyond max -> +inf, at or
// below min -> -inf, otherwise noise is added and the result clamped.
inline double laserRange(double truth, double range_min, double range_max, double noise)
{
  if (!(truth < range_max))
    return std::numeric_limits<double>::infinity();
  if (truth <= range_min)
    return -std::numeric_limits<double>::infinity();
  return std::max(range_min, std::min(range_max, truth + noise));
}

}  // namespace mybot_gazebo_lite
