// The SE(2) types of the navigation stack are the workspace's one Pose2D (mybot_common/pose2d.h),
// brought into this namespace. No ROS types.
#pragma once

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

}  // namespace mybot_navigation
