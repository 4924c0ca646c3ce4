// The swerve chain's node objects, for the three executables, the nodelets and swerve_chain
// (all three in one process). Each takes (node handle, private node handle) and throws
// ParamError on a bad configuration.
#pragma once

#include <ros/node_handle.h>

#include <memory>

namespace mybot_control_nodes
{
std::shared_ptr<void> makeSwerveController(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);
std::shared_ptr<void> makeSwerveModule(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);
std::shared_ptr<void> makeSwerveOdom(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);
}  // namespace mybot_control_nodes
