// SE(2) value types shared by SLAM, AMCL and the planners. No ROS types.
#pragma once

#include <cmath>

namespace mybot_navigation
{

inline double normalizeAngle(double a)
{
  return std::remainder(a, 2.0 * M_PI);
}

struct Point2D
{
  double x = 0.0;
  double y = 0.0;
};

struct Pose2D
{
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;
};

// a (+) b: b expressed in a's frame, returned in a's parent frame.
inline Pose2D compose(const Pose2D& a, const Pose2D& b)
{
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, normalizeAngle(a.theta + b.theta)};
}

inline Pose2D inverse(const Pose2D& p)
{
  const double c = std::cos(p.theta), s = std::sin(p.theta);
  return {-(c * p.x + s * p.y), -(-s * p.x + c * p.y), normalizeAngle(-p.theta)};
}

// Pose of b in a's frame.
inline Pose2D between(const Pose2D& a, const Pose2D& b)
{
  return compose(inverse(a), b);
}

inline Point2D transformPoint(const Pose2D& p, const Point2D& q)
{
  const double c = std::cos(p.theta), s = std::sin(p.theta);
  return {p.x + c * q.x - s * q.y, p.y + s * q.x + c * q.y};
}

inline double translationNorm(const Pose2D& p)
{
  return std::hypot(p.x, p.y);
}

}  // namespace mybot_navigation
