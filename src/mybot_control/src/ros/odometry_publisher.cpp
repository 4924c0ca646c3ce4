#include "mybot_control/ros/odometry_publisher.hpp"

#include <cmath>

#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/Twist.h>
#include <mybot_lockstep/ros/participant.h>

#include "mybot_control/ros/swerve.hpp"

namespace mybot_control
{

OdometryPublisher::OdometryPublisher(const ParamReader& p, ros::NodeHandle& nh, ros::NodeHandle& pnh,
                                     std::function<void(const Pose2D&)> set_pose)
    : set_pose_(std::move(set_pose))
{
  odom_frame_ = p.string("odom_frame_id", "odom");
  base_frame_ = p.string("base_frame_id", "base_footprint");
  if (odom_frame_.empty() || base_frame_.empty() || odom_frame_ == base_frame_)
    p.fail("odom_frame_id", "and base_frame_id must be non-empty and different");
  enable_tf_ = p.boolean("enable_odom_tf", true);
  publish_gate_ = RateGate(p.nonNegative("publish_rate", 50.0));
  const auto pose_cov = p.numbers("pose_covariance_diagonal", 6);
  const auto twist_cov = p.numbers("twist_covariance_diagonal", 6);
  for (std::size_t k = 0; k < 6; ++k)
  {
    if (pose_cov[k] < 0.0)
      p.fail("pose_covariance_diagonal", "element " + std::to_string(k) + " must be >= 0");
    if (twist_cov[k] < 0.0)
      p.fail("twist_covariance_diagonal", "element " + std::to_string(k) + " must be >= 0");
    msg_.pose.covariance[7 * k] = pose_cov[k];
    msg_.twist.covariance[7 * k] = twist_cov[k];
  }
  msg_.header.frame_id = odom_frame_;
  msg_.child_frame_id = base_frame_;
  odom_pub_ = nh.advertise<nav_msgs::Odometry>("odom", 20);
  twist_pub_ = nh.advertise<geometry_msgs::Twist>("cmd_vel_enc", 20);
  if (enable_tf_)
    broadcaster_.emplace();
  // Through the participant: under lockstep the services run on the thread of the odometry
  // updates they change, also in a nodelet manager.
  auto& ls = mybot_lockstep::Participant::instance();
  reset_srv_ = ls.advertiseService<std_srvs::Trigger::Request, std_srvs::Trigger::Response>(
      pnh, "reset_odometry", [this](auto& req, auto& res) { return onReset(req, res); });
  set_srv_ = ls.advertiseService<SetPose::Request, SetPose::Response>(
      pnh, "set_pose", [this](auto& req, auto& res) { return onSetPose(req, res); });
}

void OdometryPublisher::update(const ros::Time& stamp, const Pose2D& p, const Twist2D& t)
{
  if (!publish_gate_.due(stamp.toSec()))
    return;
  const double qz = std::sin(0.5 * p.theta), qw = std::cos(0.5 * p.theta);
  msg_.header.stamp = stamp;
  msg_.pose.pose.position.x = p.x;
  msg_.pose.pose.position.y = p.y;
  msg_.pose.pose.orientation.z = qz;
  msg_.pose.pose.orientation.w = qw;
  msg_.twist.twist.linear.x = t.vx;
  msg_.twist.twist.linear.y = t.vy;
  msg_.twist.twist.angular.z = t.wz;
  publishShared(odom_pub_, msg_);
  publishShared(twist_pub_, msg_.twist.twist);
  if (!broadcaster_)
    return;
  geometry_msgs::TransformStamped tf;
  tf.header.stamp = stamp;
  tf.header.frame_id = odom_frame_;
  tf.child_frame_id = base_frame_;
  tf.transform.translation.x = p.x;
  tf.transform.translation.y = p.y;
  tf.transform.rotation.z = qz;
  tf.transform.rotation.w = qw;
  broadcaster_->sendTransform(tf);
}

bool OdometryPublisher::onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
{
  set_pose_(Pose2D{});
  res.success = true;
  res.message = "odometry reset to (0, 0, 0)";
  return true;
}

bool OdometryPublisher::onSetPose(SetPose::Request& req, SetPose::Response& res)
{
  res.success = std::isfinite(req.x) && std::isfinite(req.y) && std::isfinite(req.yaw);
  if (res.success)
    set_pose_({req.x, req.y, req.yaw});
  res.message = res.success ? "pose set" : "x, y and yaw must be finite";
  return true;
}

}  // namespace mybot_control
