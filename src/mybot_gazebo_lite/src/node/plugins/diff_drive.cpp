// libgazebo_ros_diff_drive.so
#include "builtin.h"

#include "mybot_gazebo_lite/kinematics.h"

#include <geometry_msgs/Twist.h>

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
    out_ = WheelDriveOutputs(c_, p, nh, "base_footprint", {left_, right_});
    out_.odom_tf = p.boolean("publishOdomTF", p.boolean("publishTf", true));  // publishTf: its older name
    cmd_ = std::make_unique<TwistCommand>(c_, nh, p.topic("commandTopic", "cmd_vel"), timeout_);
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
    out_.publish(t, encoder_ ? &odo_ : nullptr);
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
  PluginContext c_;
  std::string left_, right_;
  DiffDriveGeometry geo_;
  double accel_, torque_, timeout_;
  bool encoder_ = false;
  Rate rate_;
  double instr_[2] = {0, 0};
  std::unique_ptr<TwistCommand> cmd_;
  EncoderOdometry odo_;
  WheelDriveOutputs out_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeDiffDrive(const PluginContext& c)
{
  return std::make_unique<DiffDrive>(c);
}

}  // namespace mybot_gazebo_lite
