// The SE(2) types of the navigation stack are the workspace's one Pose2D (mybot_common/pose2d.h),
// brought into this namespace. No ROS types.
#pragma once

#include <string>

#include "mybot_common/checks.h"
#include "mybot_common/pose2d.h"

namespace mybot_navigation
{

using mybot_common::between;
using mybot_common::compose;
using mybot_common::inverse;
using mybot_common::Point2D;
using mybot_common::Pose2D;
using mybot_common::transformPoint;
using mybot_common::translationNorm;
using mybot_common::wrapAngle;

// The farthest a pose may be from its frame's origin, in m. Farther is broken input, not a place:
// the 1e30 of a bad script in an initial pose, an overflowed encoder count in the odometry (whose
// jump of 1e308 m turned AMCL's cloud to NaN and made SLAM's grid try to grow to 2^58 bytes).
constexpr double kMaxCoordinate = 1e6;

// "" if a pose can be used (finite, within kMaxCoordinate), else its first bad field, for a message:
// "x is 1e+308, beyond +-1e+06", "yaw is nan". Odometry (amcl, slam_node), goals and the robot's
// pose (move_base) are checked with it.
inline std::string poseError(const Pose2D& p)
{
  return mybot_common::firstInvalid({{"x", p.x}, {"y", p.y}, {"yaw", p.theta}}, kMaxCoordinate);
}

}  // namespace mybot_navigation
