// Swerve dead reckoning from stamped pivot and wheel joint positions (joint_states), with
// optional IMU yaw fusion: odom (nav_msgs/Odometry), tf odom -> base_footprint, cmd_vel_enc,
// and the services ~reset_odometry (std_srvs/Trigger) and ~set_pose (mybot_control/SetPose),
// as diffdrive_odom.
#include <mybot_lockstep/ros/participant.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>

#include <memory>

#include "mybot_control/ros/odometry_publisher.hpp"
#include "mybot_control/ros/params.hpp"
#include "mybot_control/step_scheduler.hpp"
#include "mybot_control/swerve_odometry.hpp"
#include "mybot_control/ros/swerve.hpp"
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
    odometry_pub_ =
        std::make_unique<OdometryPublisher>(p, nh_, pnh_, [this](const Pose2D& pose) { odom_->setPose(pose); });

    std::vector<std::string> joints;
    for (std::size_t i = 0; i < g.modules.size(); ++i)
    {
      joints.push_back(g.pivot_joints[i]);
      joints.push_back(g.wheel_joints[i]);
    }
    index_ = JointIndex(joints);
    wheels_.resize(g.modules.size());
    pivots_.resize(g.modules.size());

    sub_ = mybot_lockstep::Participant::instance().subscribe<sensor_msgs::JointState>(
        nh_, "joint_states", 50, [this](const sensor_msgs::JointState& m) { onJointStates(m); },
        ros::TransportHints().tcpNoDelay());
    if (use_imu_)
      imu_sub_ = mybot_lockstep::Participant::instance().subscribe<sensor_msgs::Imu>(
          nh_, "imu", 50, [this](const sensor_msgs::Imu& m) { onImu(m); }, ros::TransportHints().tcpNoDelay());
    ROS_INFO("swerve_odom: %zu modules, wheel_radius %.4f m, %s -> %s%s%s", g.modules.size(), g.wheel_radius,
             odometry_pub_->odomFrame().c_str(), odometry_pub_->baseFrame().c_str(),
             odometry_pub_->tfEnabled() ? " (+tf)" : "", use_imu_ ? ", IMU yaw fused" : "");
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
    odometry_pub_->update(stamp, odom_->pose(), odom_->twist());
  }

  ros::NodeHandle nh_, pnh_;
  std::unique_ptr<SwerveOdometry> odom_;
  JointIndex index_;
  std::vector<double> wheels_, pivots_;
  bool use_imu_ = false;
  std::optional<double> yaw_;
  ros::Time last_stamp_;
  ros::Subscriber sub_, imu_sub_;
  std::unique_ptr<OdometryPublisher> odometry_pub_;
};

std::shared_ptr<void> makeSwerveOdom(const ros::NodeHandle& nh, const ros::NodeHandle& pnh)
{
  return std::make_shared<SwerveOdomNode>(nh, pnh);
}
}  // namespace mybot_control_nodes

#ifndef MYBOT_CONTROL_NODE_LIBRARY
int main(int argc, char** argv)
{
  return runNode(argc, argv, "swerve_odom",
                 []
                 {
                   const auto node = mybot_control_nodes::makeSwerveOdom(ros::NodeHandle(), ros::NodeHandle("~"));
                   ros::spin();
                 });
}
#endif
