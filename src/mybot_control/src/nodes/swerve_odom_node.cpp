// Swerve dead reckoning from stamped pivot and wheel joint positions (joint_states), with
// optional IMU yaw fusion: odom (nav_msgs/Odometry), tf odom -> base_footprint, cmd_vel_enc,
// and the services ~reset_odometry (std_srvs/Trigger) and ~set_pose (mybot_control/SetPose),
// as diffdrive_odom.
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <mybot_lockstep/participant.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>

#include <memory>

#include "mybot_control/SetPose.h"
#include "mybot_control/ros_params.hpp"
#include "mybot_control/step_scheduler.hpp"
#include "mybot_control/swerve_odometry.hpp"
#include "mybot_control/swerve_ros.hpp"
#include "swerve_nodes.hpp"

using namespace mybot_control;

namespace mybot_control_nodes
{
class SwerveOdomNode
{
public:
  SwerveOdomNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) : nh_(nh), pnh_(pnh)
  {
    const ParamReader p(pnh_);
    const SwerveGeometry g = loadSwerveGeometry(p, true, true);
    SwerveOdometry::Params op;
    op.offsets = g.offsets;
    op.wheel_radius = g.wheel_radius;
    op.encoder_period = p.nonNegative("encoder_period", 0.0);
    op.velocity_window = static_cast<std::size_t>(p.positive("velocity_rolling_window_size", 2));
    use_imu_ = p.boolean("use_imu", false);
    op.imu_weight = p.nonNegative("imu_weight", 1.0);
    if (op.imu_weight > 1.0)
      p.fail("imu_weight", "must be within [0, 1]");
    odom_ = std::make_unique<SwerveOdometry>(op);
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

    std::vector<std::string> joints;
    for (std::size_t i = 0; i < g.modules.size(); ++i)
    {
      joints.push_back(g.pivot_joints[i]);
      joints.push_back(g.wheel_joints[i]);
    }
    index_ = JointIndex(joints);
    wheels_.resize(g.modules.size());
    pivots_.resize(g.modules.size());

    odom_pub_ = nh_.advertise<nav_msgs::Odometry>("odom", 20);
    twist_pub_ = nh_.advertise<geometry_msgs::Twist>("cmd_vel_enc", 20);
    sub_ = mybot_lockstep::Participant::instance().subscribe<sensor_msgs::JointState>(nh_, "joint_states", 50, [this](const sensor_msgs::JointState& m) { onJointStates(m); }, ros::TransportHints().tcpNoDelay());
    if (use_imu_)
      imu_sub_ = mybot_lockstep::Participant::instance().subscribe<sensor_msgs::Imu>(nh_, "imu", 50, [this](const sensor_msgs::Imu& m) { onImu(m); }, ros::TransportHints().tcpNoDelay());
    reset_srv_ = pnh_.advertiseService("reset_odometry", &SwerveOdomNode::onReset, this);
    set_srv_ = pnh_.advertiseService("set_pose", &SwerveOdomNode::onSetPose, this);
    ROS_INFO("swerve_odom: %zu modules, wheel_radius %.4f m, %s -> %s%s%s", g.modules.size(), g.wheel_radius,
             odom_frame_.c_str(), base_frame_.c_str(), enable_tf_ ? " (+tf)" : "", use_imu_ ? ", IMU yaw fused" : "");
  }

private:
  void onImu(const sensor_msgs::Imu& msg)
  {
    const double yaw = yawOf(msg.orientation);
    if (std::isfinite(yaw))
      yaw_ = yaw;
  }

  void onJointStates(const sensor_msgs::JointState& msg)
  {
    if (!index_.update(msg.name, msg.position.size()))
      return;  // joint_states of other joints
    const ros::Time stamp = msg.header.stamp.isZero() ? ros::Time::now() : msg.header.stamp;
    if (!last_stamp_.isZero() && stamp < last_stamp_)
    {
      ROS_WARN("swerve_odom: time went backwards (%.3f -> %.3f s); restarting from the current pose",
               last_stamp_.toSec(), stamp.toSec());
      odom_->resetEncoders();
    }
    last_stamp_ = stamp;
    for (std::size_t i = 0; i < wheels_.size(); ++i)
    {
      pivots_[i] = msg.position[index_[2 * i]];
      wheels_[i] = msg.position[index_[2 * i + 1]];
    }
    if (!odom_->update(wheels_, pivots_, stamp.toSec(), use_imu_ ? yaw_ : std::nullopt))
      return;
    if (!publish_gate_.due(stamp.toSec()))
      return;
    publish(stamp);
  }

  void publish(const ros::Time& stamp)
  {
    const Pose2D& p = odom_->pose();
    const Twist2D t = odom_->twist();
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
    if (!enable_tf_)
      return;
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

  bool onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    odom_->setPose(Pose2D{});
    res.success = true;
    res.message = "odometry reset to (0, 0, 0)";
    return true;
  }

  bool onSetPose(SetPose::Request& req, SetPose::Response& res)
  {
    res.success = std::isfinite(req.x) && std::isfinite(req.y) && std::isfinite(req.yaw);
    if (res.success)
      odom_->setPose({req.x, req.y, req.yaw});
    res.message = res.success ? "pose set" : "x, y and yaw must be finite";
    return true;
  }

  ros::NodeHandle nh_, pnh_;
  std::unique_ptr<SwerveOdometry> odom_;
  JointIndex index_;
  std::vector<double> wheels_, pivots_;
  std::string odom_frame_, base_frame_;
  bool enable_tf_ = true, use_imu_ = false;
  std::optional<double> yaw_;
  RateGate publish_gate_{50.0};
  ros::Time last_stamp_;
  nav_msgs::Odometry msg_;
  ros::Publisher odom_pub_, twist_pub_;
  ros::Subscriber sub_, imu_sub_;
  ros::ServiceServer reset_srv_, set_srv_;
  tf2_ros::TransformBroadcaster broadcaster_;
};


std::shared_ptr<void> makeSwerveOdom(const ros::NodeHandle& nh, const ros::NodeHandle& pnh)
{
  return std::make_shared<SwerveOdomNode>(nh, pnh);
}
}  // namespace mybot_control_nodes

#ifndef MYBOT_CONTROL_NODE_LIBRARY
int main(int argc, char** argv)
{
  return runNode(argc, argv, "swerve_odom", [] {
    const auto node = mybot_control_nodes::makeSwerveOdom(ros::NodeHandle(), ros::NodeHandle("~"));
    ros::spin();
  });
}
#endif
