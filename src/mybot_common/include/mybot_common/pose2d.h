// SE(2), the one planar pose of the workspace: the controllers' odometry (mybot_control), SLAM,
// AMCL and the planners (mybot_navigation) all use these types. Header-only, no ROS types.
//
// A pose (x, y, theta) is the rigid transform taking points from a child frame into its parent:
// p_parent = R(theta) p_child + (x, y). Composition is the product of those transforms, so
// compose(a, b) is "b, expressed in a's frame, seen from a's parent", and between(a, b) is b seen
// from a: the relative pose odometry and scan matching measure.
#pragma once

#include <cmath>

namespace mybot_common
{

// An angle wrapped to (-pi, pi]. Non-finite angles are returned unchanged, so a NaN stays
// visible to the checks downstream instead of becoming a plausible heading.
inline double wrapAngle(double a)
{
  if (!std::isfinite(a))
    return a;
  a = std::remainder(a, 2.0 * M_PI);  // [-pi, pi]
  return a <= -M_PI ? a + 2.0 * M_PI : a;
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
  double theta = 0.0;  // rad, kept in (-pi, pi] by the functions below
};

// a (+) b: b expressed in a's frame, returned in a's parent frame.
inline Pose2D compose(const Pose2D& a, const Pose2D& b)
{
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, wrapAngle(a.theta + b.theta)};
}

// The pose of a's parent seen from a: compose(a, inverse(a)) is the identity.
inline Pose2D inverse(const Pose2D& p)
{
  const double c = std::cos(p.theta), s = std::sin(p.theta);
  return {-(c * p.x + s * p.y), -(-s * p.x + c * p.y), wrapAngle(-p.theta)};
}

// Pose of b in a's frame.
inline Pose2D between(const Pose2D& a, const Pose2D& b)
{
  return compose(inverse(a), b);
}

// A point of p's frame, in p's parent frame.
inline Point2D transformPoint(const Pose2D& p, const Point2D& q)
{
  const double c = std::cos(p.theta), s = std::sin(p.theta);
  return {p.x + c * q.x - s * q.y, p.y + s * q.x + c * q.y};
}

inline double translationNorm(const Pose2D& p)
{
  return std::hypot(p.x, p.y);
}

}  // namespace mybot_common
