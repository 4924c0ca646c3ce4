// The ROS side both odometry nodes share (diff_drive_controller's parameter names): frames,
// covariances and publish rate from parameters; odom, cmd_vel_enc and the odom -> base tf out;
// the reset_odometry and set_pose services. What differs between a diff drive and a swerve base
// (how the pose is dead-reckoned) stays in the node.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>

#include "mybot_control/SetPose.h"
#include "mybot_control/kinematics.hpp"
#include "mybot_control/ros/params.hpp"
#include "mybot_control/step_scheduler.hpp"

namespace mybot_control
{

class OdometryPublisher
{
public:
  // Reads odom_frame_id (odom), base_frame_id (base_footprint), enable_odom_tf (true),
  // publish_rate (50) and pose_/twist_covariance_diagonal (required, 6 numbers >= 0) from `p`;
  // advertises on `nh` and the services on `pnh`. `set_pose` moves the node's odometry.
  OdometryPublisher(const ParamReader& p, ros::NodeHandle& nh, ros::NodeHandle& pnh,
                    std::function<void(const Pose2D&)> set_pose);

  // Publishes when the publish rate is due at `stamp`.
  void update(const ros::Time& stamp, const Pose2D& pose, const Twist2D& twist);
  const std::string& odomFrame() const { return odom_frame_; }
  const std::string& baseFrame() const { return base_frame_; }
  bool tfEnabled() const { return enable_tf_; }

private:
  bool onReset(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool onSetPose(SetPose::Request& req, SetPose::Response& res);

  std::function<void(const Pose2D&)> set_pose_;
  std::string odom_frame_, base_frame_;
  bool enable_tf_ = true;
  RateGate publish_gate_{50.0};
  nav_msgs::Odometry msg_;
  ros::Publisher odom_pub_, twist_pub_;
  ros::ServiceServer reset_srv_, set_srv_;
  // Made once the parameters are valid, and only with enable_odom_tf: a member constructed
  // before them advertised /tf from a node that was about to refuse its configuration, or that
  // never sends a transform.
  std::optional<tf2_ros::TransformBroadcaster> broadcaster_;
};

}  // namespace mybot_control
