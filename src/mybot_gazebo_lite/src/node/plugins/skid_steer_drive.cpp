// libgazebo_ros_skid_steer_drive.so: four wheels, two per side, each side at the speed of a
// differential drive (no legacy swap here: upstream never had one). Odometry is the model's
// world pose, as upstream publishes it. And hector_gazebo_plugins' libdiffdrive_plugin_multi_wheel.so:
// the same with any number of wheels a side.
#include "builtin.h"

#include "mybot_gazebo_lite/kinematics.h"

#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>

#include <cmath>

namespace mybot_gazebo_lite
{

namespace
{
// Each side's wheels at that side's differential-drive speed for (v, w), their motors `torque`.
template <class Joints>
void driveSides(const PluginContext& c, const Joints& left, const Joints& right, double v, double w,
                const DiffDriveGeometry& geo, double torque)
{
  const auto [vl, vr] = diffDriveWheelSpeeds(v, w, geo);
  const double r = geo.diameter / 2;
  for (const auto& j : left)
    c.robot->commandVelocity(j, vl / r, torque);
  for (const auto& j : right)
    c.robot->commandVelocity(j, vr / r, torque);
}

class SkidSteerDrive : public SimPlugin
{
public:
  explicit SkidSteerDrive(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    ros::NodeHandle nh(c.ns);
    left_ = {p.joint("leftFrontJoint", "left_front_joint"), p.joint("leftRearJoint", "left_rear_joint")};
    right_ = {p.joint("rightFrontJoint", "right_front_joint"), p.joint("rightRearJoint", "right_rear_joint")};
    geo_.separation = p.num("wheelSeparation", 0.4);
    geo_.diameter = p.num("wheelDiameter", 0.15);
    geo_.legacy = false;
    if (!(geo_.separation > 0))
      p.fail("wheelSeparation", "must be positive");
    if (!(geo_.diameter > 0))
      p.fail("wheelDiameter", "must be positive");
    torque_ = p.num("torque", p.num("MaxForce", 5.0));
    if (!(torque_ > 0))
      p.fail("torque", "must be positive");
    rate_ = Rate(p.num("updateRate", 100.0));
    timeout_ = p.num("commandTimeout", 0.5);
    if (timeout_ < 0)
      p.fail("commandTimeout", "must be >= 0");
    broadcast_tf_ = p.boolean("broadcastTF", false);
    cov_[0] = p.num("covariance_x", 0.0001);
    cov_[1] = p.num("covariance_y", 0.0001);
    cov_[2] = p.num("covariance_yaw", 0.01);
    odom_frame_ = resolveFrame(c, p.str("odometryFrame", "odom"));
    base_frame_ = resolveFrame(c, p.str("robotBaseFrame", "base_footprint"));
    cmd_ = std::make_unique<TwistCommand>(c_, nh, p.topic("commandTopic", "cmd_vel"), timeout_);
    odom_pub_ = p.advertise<nav_msgs::Odometry>(nh, "odometryTopic", p.str("odometryTopic", "odom"), 1);
    drive(0, 0);
  }
  void reset() override
  {
    cmd_->reset();
    drive(0, 0);
  }
  void update(double t) override
  {
    if (!rate_.due(t))
      return;
    const geometry_msgs::Twist& cmd = cmd_->at(t);
    publishOdometry(t);
    drive(cmd.linear.x, cmd.angular.z);
  }

private:
  void drive(double v, double w) { driveSides(c_, left_, right_, v, w, geo_, torque_); }
  void publishOdometry(double t)
  {
    const nav_msgs::Odometry o = worldPoseOdometry(c_, t, odom_frame_, base_frame_, cov_);
    odom_pub_.publish(o);
    if (broadcast_tf_)
      c_.tf->sendTransform(toTf(c_.robot->linkState(c_.robot->spec().root).tf, t, odom_frame_, base_frame_));
  }
  PluginContext c_;
  std::array<std::string, 2> left_, right_;
  DiffDriveGeometry geo_;
  double torque_, timeout_, cov_[3];
  bool broadcast_tf_;
  std::string odom_frame_, base_frame_;
  Rate rate_;
  std::unique_ptr<TwistCommand> cmd_;
  ros::Publisher odom_pub_;
};

// hector's multi-wheel differential drive: <leftJoints> and <rightJoints> (space-separated, required),
// <wheelSeparation> 0.34, <wheelDiameter> 0.15, <torque> 5, <updateRate> 100, the odometry as
// the model's world pose (<publishOdometryTf>, <publishOdometryMsg>: true), upstream's names and
// defaults. Upstream sets each wheel's velocity outright; here a motor of <torque> drives it.
class HectorMultiWheelDrive : public SimPlugin
{
public:
  explicit HectorMultiWheelDrive(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    ros::NodeHandle nh(c.ns);
    for (const char* tag : {"leftJoints", "rightJoints"})
    {
      if (!p.has(tag))
        p.fail(tag, "required: the side's wheel joints, space-separated");
      std::vector<std::string>& side = std::string(tag) == "leftJoints" ? left_ : right_;
      for (const std::string& j : p.jointList(tag, " \t\n"))
        side.push_back(scopedJoint(c, j));
      if (side.empty())
        p.fail(tag, "no joint named");
    }
    geo_.separation = p.positive("wheelSeparation", 0.34);
    geo_.diameter = p.positive("wheelDiameter", 0.15);
    geo_.legacy = false;
    torque_ = p.positive("torque", 5.0);
    rate_ = Rate(p.num("updateRate", 100.0));
    out_ = WheelDriveOutputs(c_, p, nh, "base_footprint", {});
    out_.odom_tf = p.boolean("publishOdometryTf", true);
    out_.odom_msg = p.boolean("publishOdometryMsg", true);
    cmd_ = std::make_unique<TwistCommand>(c_, nh, p.topic("commandTopic", "cmd_vel"),
                                          p.nonNegative("commandTimeout", 0.5));
    driveSides(c_, left_, right_, 0, 0, geo_, torque_);
  }
  void reset() override
  {
    cmd_->reset();
    driveSides(c_, left_, right_, 0, 0, geo_, torque_);
  }
  void update(double t) override
  {
    if (!rate_.due(t))
      return;
    out_.publish(t, nullptr);
    const geometry_msgs::Twist& cmd = cmd_->at(t);
    driveSides(c_, left_, right_, cmd.linear.x, cmd.angular.z, geo_, torque_);
  }

private:
  PluginContext c_;
  std::vector<std::string> left_, right_;
  DiffDriveGeometry geo_;
  double torque_;
  Rate rate_;
  std::unique_ptr<TwistCommand> cmd_;
  WheelDriveOutputs out_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeHectorMultiWheelDrive(const PluginContext& c)
{
  return std::make_unique<HectorMultiWheelDrive>(c);
}

std::unique_ptr<SimPlugin> makeSkidSteerDrive(const PluginContext& c)
{
  return std::make_unique<SkidSteerDrive>(c);
}

}  // namespace mybot_gazebo_lite
