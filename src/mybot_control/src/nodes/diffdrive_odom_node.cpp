// Dead reckoning from stamped wheel joint positions (joint_states): odom (nav_msgs/Odometry),
// tf odom -> base_footprint, cmd_vel_enc (the twist recovered from the encoders), and
// services to reset or set the pose.
#include <mybot_lockstep/ros/participant.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>

#include <array>
#include <memory>

#include "mybot_control/odometry.hpp"
#include "mybot_control/ros/odometry_publisher.hpp"
#include "diffdrive_nodes.hpp"
#include "mybot_control/ros/params.hpp"
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
    odometry_pub_ =
        std::make_unique<OdometryPublisher>(p, nh_, pnh_, [this](const Pose2D& pose) { odom_.setPose(pose); });

    sub_ = mybot_lockstep::Participant::instance().subscribe<sensor_msgs::JointState>(
        nh_, "joint_states", 50, [this](const sensor_msgs::JointState& m) { onJointStates(m); },
        ros::TransportHints().tcpNoDelay());
    ROS_INFO("diffdrive_odom: separation %.4f m, radius %.4f/%.4f m, %s -> %s%s", g.separation, g.left_radius,
             g.right_radius, odometry_pub_->odomFrame().c_str(), odometry_pub_->baseFrame().c_str(),
             odometry_pub_->tfEnabled() ? " (+tf)" : "");
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
    odometry_pub_->update(stamp, odom_.pose(), odom_.twist());
  }

  ros::NodeHandle nh_, pnh_;
  std::string left_joint_, right_joint_;
  std::array<int, 2> index_{-1, -1};
  DiffDriveOdometry odom_;
  ros::Time last_stamp_;
  ros::Subscriber sub_;
  std::unique_ptr<OdometryPublisher> odometry_pub_;
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
  return runNode(argc, argv, "diffdrive_odom",
                 []
                 {
                   const auto node = mybot_control_nodes::makeDiffDriveOdom(ros::NodeHandle(), ros::NodeHandle("~"));
                   ros::spin();
                 });
}
#endif
