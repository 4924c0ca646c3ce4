// The diff-drive chain's node objects, for the four executables, the nodelets and
// diffdrive_chain (all in one process). Each takes (node handle, private node handle) and
// throws ParamError on a bad configuration.
#pragma once

#include <ros/node_handle.h>

#include <memory>

namespace mybot_control_nodes
{
std::shared_ptr<void> makeTwistMux(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);
std::shared_ptr<void> makeDiffDriveController(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);
std::shared_ptr<void> makeWheelController(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);
std::shared_ptr<void> makeDiffDriveOdom(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);
}  // namespace mybot_control_nodes
