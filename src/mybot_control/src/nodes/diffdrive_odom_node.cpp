// Dead reckoning from stamped wheel joint positions (joint_states): odom (nav_msgs/Odometry),
// tf odom -> base_footprint, cmd_vel_enc (the twist recovered from the encoders), and
// services to reset or set the pose.
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <mybot_lockstep/participant.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>

#include <array>

#include "mybot_control/SetPose.h"
#include "mybot_control/odometry.hpp"
#include "diffdrive_nodes.hpp"
#include "mybot_control/ros_params.hpp"
#include "mybot_control/step_scheduler.hpp"

using namespace mybot_control;

namespace
{
class DiffDriveOdomNode
{
public:
  DiffDriveOdomNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) : nh_(nh), pnh_(pnh)
  {
    const ParamReader p(pnh_);
    left_joint_ = p.string("left_wheel", "left_wheel_hinge");
    right_joint_ = p.string("right_wheel", "right_wheel_hinge");
    const WheelGeometry g = loadWheelGeometry(p, left_joint_, right_joint_, true, true);
    DiffDriveOdometry::Params op;
    op.wheel_separation = g.separation;
    op.left_radius = g.left_radius;
    op.right_radius = g.right_radius;
    op.encoder_period = p.nonNegative("encoder_period", 0.0);
    op.velocity_window = static_cast<std::size_t>(p.positive("velocity_rolling_window_size", 10));
    odom_ = DiffDriveOdometry(op);
    odom_frame_ = p.string("odom_frame_id", "odom");
    base_frame_ = p.string("base_frame_id", "base_footprint");
    if (odom_frame_.empty() || base_frame_.empty() || odom_frame_ == base_frame_)
      p.fail("odom_frame_id", "and base_frame_id must be non-empty and different");
    enable_tf_ = p.boolean("enable_odom_tf", true);
    const double rate = p.nonNegative("publish_rate", 50.0);
    publish_gate_ = RateGate(rate);
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

    odom_pub_ = nh_.advertise<nav_msgs::Odometry>("odom", 20);
    twist_pub_ = nh_.advertise<geometry_msgs::Twist>("cmd_vel_enc", 20);
    sub_ = mybot_lockstep::Participant::instance().subscribe<sensor_msgs::JointState>(nh_, "joint_states", 50, [this](const sensor_msgs::JointState& m) { onJointStates(m); }, ros::TransportHints().tcpNoDelay());
    reset_srv_ = pnh_.advertiseService("reset_odometry", &DiffDriveOdomNode::onReset, this);
    set_srv_ = pnh_.advertiseService("set_pose", &DiffDriveOdomNode::onSetPose, this);
    ROS_INFO("diffdrive_odom: separation %.4f m, radius %.4f/%.4f m, %s -> %s%s", g.separation, g.left_radius,
             g.right_radius, odom_frame_.c_str(), base_frame_.c_str(), enable_tf_ ? " (+tf)" : "");
  }

private:
  bool findJoints(const sensor_msgs::JointState& msg)
  {
    const std::array<const std::string*, 2> names{&left_joint_, &right_joint_};
    for (std::size_t w = 0; w < 2; ++w)
    {
      int& idx = index_[w];
      if (idx >= 0 && static_cast<std::size_t>(idx) < msg.name.size() && msg.name[idx] == *names[w])
        continue;
      idx = -1;
      for (std::size_t i = 0; i < msg.name.size(); ++i)
        if (msg.name[i] == *names[w])
          idx = static_cast<int>(i);
      if (idx < 0 || static_cast<std::size_t>(idx) >= msg.position.size())
        return false;
    }
    return true;
  }

  void onJointStates(const sensor_msgs::JointState& msg)
  {
    if (!findJoints(msg))
      return;  // joint_states of other joints (e.g. a separate publisher)
    const ros::Time stamp = msg.header.stamp.isZero() ? ros::Time::now() : msg.header.stamp;
    if (!last_stamp_.isZero() && stamp < last_stamp_)
    {
      ROS_WARN("diffdrive_odom: time went backwards (%.3f -> %.3f s); restarting from the current pose",
               last_stamp_.toSec(), stamp.toSec());
      odom_.resetEncoders();
    }
    last_stamp_ = stamp;
    const double l = msg.position[index_[0]], r = msg.position[index_[1]];
    if (!odom_.update(l, r, stamp.toSec()))
    {
      if (!std::isfinite(l) || !std::isfinite(r))
        ROS_WARN_THROTTLE(1.0, "diffdrive_odom: ignoring NaN/inf wheel positions");
      return;
    }
    if (!publish_gate_.due(stamp.toSec()))
      return;
    publish(stamp);
  }

  void publish(const ros::Time& stamp)
  {
    const Pose2D& p = odom_.pose();
    const Twist2D t = odom_.twist();
    const double qz = std::sin(0.5 * p.theta), qw = std::cos(0.5 * p.theta);
    msg_.header.stamp = stamp;
    msg_.pose.pose.position.x = p.x;
    msg_.pose.pose.position.y = p.y;
    msg_.pose.pose.orientation.z = qz;
    msg_.pose.pose.orientation.w = qw;
    msg_.twist.twist.linear.x = t.vx;
    msg_.twist.twist.angular.z = t.wz;
    odom_pub_.publish(msg_);
    twist_pub_.publish(msg_.twist.twist);
    if (enable_tf_)
    {
      geometry_msgs::TransformStamped tf;
      tf.header.stamp = stamp;
      tf.header.frame_id = odom_frame_;
      tf.child_frame_id = base_frame_;
      tf.transform.translation.x = p.x;
      tf.transform.translation.y = p.y;
      tf.transform.rotation.z = qz;
      tf.transform.rotation.w = qw;
      broadcaster_.sendTransform(tf);
    }
  }

  bool onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    odom_.setPose(Pose2D{});
    res.success = true;
    res.message = "odometry reset to (0, 0, 0)";
    return true;
  }

  bool onSetPose(SetPose::Request& req, SetPose::Response& res)
  {
    if (!std::isfinite(req.x) || !std::isfinite(req.y) || !std::isfinite(req.yaw))
    {
      res.success = false;
      res.message = "x, y and yaw must be finite";
      return true;
    }
    odom_.setPose({req.x, req.y, req.yaw});
    res.success = true;
    res.message = "pose set";
    return true;
  }

  ros::NodeHandle nh_, pnh_;
  std::string left_joint_, right_joint_, odom_frame_, base_frame_;
  std::array<int, 2> index_{-1, -1};
  DiffDriveOdometry odom_;
  bool enable_tf_ = true;
  RateGate publish_gate_{50.0};
  ros::Time last_stamp_;
  nav_msgs::Odometry msg_;
  ros::Publisher odom_pub_, twist_pub_;
  ros::Subscriber sub_;
  ros::ServiceServer reset_srv_, set_srv_;
  tf2_ros::TransformBroadcaster broadcaster_;
};

}  // namespace

namespace mybot_control_nodes
{
std::shared_ptr<void> makeDiffDriveOdom(const ros::NodeHandle& nh, const ros::NodeHandle& pnh)
{
  return std::make_shared<DiffDriveOdomNode>(nh, pnh);
}
}  // namespace mybot_control_nodes

#ifndef MYBOT_CONTROL_NODE_LIBRARY
int main(int argc, char** argv)
{
  return runNode(argc, argv, "diffdrive_odom", [] {
    const auto node = mybot_control_nodes::makeDiffDriveOdom(ros::NodeHandle(), ros::NodeHandle("~"));
    ros::spin();
  });
}
#endif
