// libgazebo_ros_diff_drive.so
#include "builtin.h"

#include "mybot_gazebo_lite/kinematics.h"

#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/JointState.h>

#include <cmath>

namespace mybot_gazebo_lite
{

namespace
{
class DiffDrive : public SimPlugin
{
public:
  explicit DiffDrive(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    ros::NodeHandle nh(c.ns);
    left_ = p.joint("leftJoint", "left_joint");
    right_ = p.joint("rightJoint", "right_joint");
    geo_.separation = p.num("wheelSeparation", 0.34);
    geo_.diameter = p.num("wheelDiameter", 0.15);
    if (!(geo_.separation > 0))
      p.fail("wheelSeparation", "must be positive");
    if (!(geo_.diameter > 0))
      p.fail("wheelDiameter", "must be positive");
    if (!p.has("legacyMode"))
      ROS_WARN("%s: diff_drive plugin missing <legacyMode>, defaults to true (left/right swapped, as in gazebo_ros)",
               c.robot->name().c_str());
    geo_.legacy = p.boolean("legacyMode", true);
    accel_ = p.num("wheelAcceleration", 0.0);
    torque_ = p.num("wheelTorque", 5.0);
    if (accel_ < 0)
      p.fail("wheelAcceleration", "must be >= 0");
    if (!(torque_ > 0))
      p.fail("wheelTorque", "must be positive");
    rate_ = Rate(p.num("updateRate", 100.0));
    timeout_ = p.num("commandTimeout", 0.5);
    if (timeout_ < 0)
      p.fail("commandTimeout", "must be >= 0");
    std::string src = p.str("odometrySource", "world");
    if (src == "encoder" || src == "0")
      encoder_ = true;
    else if (src != "world" && src != "1")
      p.fail("odometrySource", "expected 'encoder' or 'world', got '" + src + "'");
    publish_odom_tf_ = p.boolean("publishOdomTF", p.boolean("publishTf", true));  // publishTf: its older name
    publish_wheel_tf_ = p.boolean("publishWheelTF", false);
    publish_wheel_js_ = p.boolean("publishWheelJointState", false);
    odom_frame_ = resolveFrame(c, p.str("odometryFrame", "odom"));
    base_frame_ = resolveFrame(c, p.str("robotBaseFrame", "base_footprint"));
    base_link_ = scopedLink(c, p.str("robotBaseFrame", "base_footprint"));
    if (!c.robot->hasLink(base_link_))
      base_link_ = c.robot->spec().root;
    cmd_ = std::make_unique<TwistCommand>(c_, nh, p.str("commandTopic", "cmd_vel"), timeout_);
    odom_pub_ = nh.advertise<nav_msgs::Odometry>(p.str("odometryTopic", "odom"), 1);
    if (publish_wheel_js_)
      js_pub_ = nh.advertise<sensor_msgs::JointState>("joint_states", 1);
    hold();
  }
  void reset() override
  {
    odo_ = EncoderOdometry();
    cmd_->reset();
    instr_[0] = instr_[1] = 0;
    hold();
  }
  void update(double t) override
  {
    double dt = c_.world->stepSize();
    odo_.update(c_.robot->jointVelocity(left_), c_.robot->jointVelocity(right_), dt, geo_);
    if (!rate_.due(t))
      return;
    const geometry_msgs::Twist& cmd = cmd_->at(t);
    publishOdometry(t);
    auto [vl, vr] = diffDriveWheelSpeeds(cmd.linear.x, cmd.angular.z, geo_);
    double r = geo_.diameter / 2;
    double period = rate_.period > 0 ? rate_.period : dt;
    double target[2] = {vl, vr};
    const std::string* joints[2] = {&left_, &right_};
    for (int i = 0; i < 2; ++i)
    {
      double cur = c_.robot->jointVelocity(*joints[i]) * r;
      instr_[i] = accel_ > 0 ? rampWheelSpeed(instr_[i], target[i], cur, accel_, period) : target[i];
      c_.robot->commandVelocity(*joints[i], instr_[i] / r, torque_);
    }
  }

private:
  void hold()
  {
    c_.robot->commandVelocity(left_, 0, torque_);
    c_.robot->commandVelocity(right_, 0, torque_);
  }
  void publishOdometry(double t)
  {
    nav_msgs::Odometry o;
    o.header.stamp = ros::Time(t);
    o.header.frame_id = odom_frame_;
    o.child_frame_id = base_frame_;
    btTransform pose;
    if (encoder_)
    {
      btQuaternion q;
      q.setEulerZYX(odo_.theta, 0, 0);
      pose = btTransform(q, btVector3(odo_.x, odo_.y, 0));
      o.twist.twist.linear.x = odo_.v;
      o.twist.twist.angular.z = odo_.w;
    }
    else
    {
      Pose s = c_.robot->linkState(c_.robot->spec().root);
      pose = s.tf;
      btScalar yaw, pitch, roll;
      pose.getBasis().getEulerZYX(yaw, pitch, roll);
      o.twist.twist.linear.x = std::cos(yaw) * s.linear.x() + std::sin(yaw) * s.linear.y();
      o.twist.twist.linear.y = std::cos(yaw) * s.linear.y() - std::sin(yaw) * s.linear.x();
      o.twist.twist.angular.z = s.angular.z();
    }
    toMsg(pose, o.pose.pose);
    o.pose.covariance[0] = o.pose.covariance[7] = 0.00001;
    o.pose.covariance[14] = o.pose.covariance[21] = o.pose.covariance[28] = 1e12;
    o.pose.covariance[35] = 0.001;
    odom_pub_.publish(o);
    if (publish_odom_tf_)
      c_.tf->sendTransform(toTf(pose, t, odom_frame_, base_frame_));
    if (publish_wheel_tf_ || publish_wheel_js_)
    {
      sensor_msgs::JointState js;
      js.header.stamp = ros::Time(t);
      for (const std::string* j : {&left_, &right_})
      {
        const JointSpec* spec = c_.robot->joint(*j).spec;
        if (publish_wheel_tf_)
        {
          btTransform rel = c_.robot->linkState(spec->parent).tf.inverse() * c_.robot->linkState(spec->child).tf;
          c_.tf->sendTransform(toTf(rel, t, resolveFrame(c_, spec->parent), resolveFrame(c_, spec->child)));
        }
        js.name.push_back(*j);
        js.position.push_back(c_.robot->jointPosition(*j));
        js.velocity.push_back(c_.robot->jointVelocity(*j));
      }
      if (publish_wheel_js_)
        js_pub_.publish(js);
    }
  }
  PluginContext c_;
  std::string left_, right_, odom_frame_, base_frame_, base_link_;
  DiffDriveGeometry geo_;
  double accel_, torque_, timeout_;
  bool encoder_ = false, publish_odom_tf_, publish_wheel_tf_, publish_wheel_js_;
  Rate rate_;
  double instr_[2] = {0, 0};
  std::unique_ptr<TwistCommand> cmd_;
  EncoderOdometry odo_;
  ros::Publisher odom_pub_, js_pub_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeDiffDrive(const PluginContext& c)
{
  return std::make_unique<DiffDrive>(c);
}

}  // namespace mybot_gazebo_lite
