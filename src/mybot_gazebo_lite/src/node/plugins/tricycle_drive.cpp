// libgazebo_ros_tricycle_drive.so: a steered, driven front wheel and two free rear wheels that
// count (a tugger's, a forklift's). As upstream, cmd_vel's linear.x is the driven wheel's rim
// speed and its angular.z is the steering ANGLE (rad, clamped to +-pi/2), not a turn rate.
//
// Steering: with <steeringSpeed> 0 (the default) upstream sets the joint's angle outright; here a
// position servo takes it there within a few steps (limited by the joint's URDF <limit effort>,
// else <wheelTorque>). With <steeringSpeed> > 0 the joint turns at that speed until it is within
// <steeringAngleTolerance> of the angle. The driven wheel: a velocity motor of <wheelTorque>,
// ramped by <wheelAcceleration> / <wheelDeceleration> (rad/s^2 of the wheel, as upstream) unless
// within <wheelSpeedTolerance> (rad/s). Upstream's two ramps compare a difference with the target
// itself (a slip that sends them the wrong way); these go toward the target.
//
// Odometry: the model's world pose (odometrySource world, the default) or dead reckoning from the
// rear wheels (encoder: <encoderWheelDiameter>, <encoderWheelSeparation>). Upstream's heading
// rate there is (left - right) / separation, which turns its odometry the wrong way for wheels
// rolling forward about +y; it is (right - left) / separation here. Its tf is always published.
// As gazebo_lite's diff drive, a command older than <commandTimeout> (0.5 s of sim time) stops the
// wheel; upstream keeps the last one for ever.
#include "builtin.h"

#include <algorithm>
#include <cmath>

namespace mybot_gazebo_lite
{

namespace
{
class TricycleDrive : public SimPlugin
{
public:
  explicit TricycleDrive(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    ros::NodeHandle nh(c.ns);
    steering_ = p.joint("steeringJoint", "front_steering_joint");
    wheel_ = p.joint("actuatedWheelJoint", "front_wheel_joint");
    left_ = p.joint("encoderWheelLeftJoint", "left_wheel_joint");
    right_ = p.joint("encoderWheelRightJoint", "right_wheel_joint");
    wheel_radius_ = p.positive("actuatedWheelDiameter", 0.15) / 2;
    geo_.diameter = p.positive("encoderWheelDiameter", 0.15);
    geo_.separation = p.positive("encoderWheelSeparation", 0.5);
    geo_.legacy = false;
    torque_ = p.positive("wheelTorque", 5.0);
    const JointSpec& steer = *c.robot->joint(steering_).spec;
    steer_torque_ = steer.has_effort && steer.effort > 0 ? steer.effort : torque_;
    accel_ = p.nonNegative("wheelAcceleration", 0.0);
    decel_ = p.nonNegative("wheelDeceleration", accel_);
    speed_tolerance_ = p.nonNegative("wheelSpeedTolerance", 0.01);
    steering_speed_ = p.nonNegative("steeringSpeed", 0.0);
    angle_tolerance_ = p.nonNegative("steeringAngleTolerance", 0.01);
    rate_ = Rate(p.num("updateRate", 100.0));
    const std::string src = p.str("odometrySource", "world");
    if (src != "world" && src != "encoder")
      p.fail("odometrySource", "expected 'encoder' or 'world', got '" + src + "'");
    encoder_ = src == "encoder";
    out_ = WheelDriveOutputs(c_, p, nh, "base_link", {steering_, wheel_, left_, right_});
    cmd_ = std::make_unique<TwistCommand>(c_, nh, p.topic("commandTopic", "cmd_vel"),
                                          p.nonNegative("commandTimeout", 0.5));
    hold();
  }
  void reset() override
  {
    odo_ = EncoderOdometry();
    cmd_->reset();
    hold();
  }
  void update(double t) override
  {
    const double dt = c_.world->stepSize();
    if (encoder_)
      odo_.update(c_.robot->jointVelocity(left_), c_.robot->jointVelocity(right_), dt, geo_);
    if (!rate_.due(t))
      return;
    out_.publish(t, encoder_ ? &odo_ : nullptr);
    const geometry_msgs::Twist& cmd = cmd_->at(t);
    const double period = rate_.period > 0 ? rate_.period : dt;
    drive(cmd.linear.x / wheel_radius_, period);
    steer(std::max(-M_PI / 2, std::min(M_PI / 2, cmd.angular.z)));
  }

private:
  void hold()
  {
    c_.robot->commandVelocity(wheel_, 0, torque_);
    c_.robot->commandPosition(steering_, c_.robot->jointPosition(steering_), steer_torque_);
  }
  // The driven wheel toward `target` rad/s, by the ramp when there is one.
  void drive(double target, double period)
  {
    const double current = c_.robot->jointVelocity(wheel_);
    double applied = target;
    if (accel_ > 0 && std::abs(current - target) >= speed_tolerance_)
      applied =
          current < target ? std::min(target, current + accel_ * period) : std::max(target, current - decel_ * period);
    c_.robot->commandVelocity(wheel_, applied, torque_);
  }
  void steer(double angle)
  {
    if (steering_speed_ <= 0)
    {
      c_.robot->commandPosition(steering_, angle, steer_torque_);
      return;
    }
    const double off = angle - c_.robot->jointPosition(steering_);
    const double speed = std::abs(off) < angle_tolerance_ ? 0.0 : std::copysign(steering_speed_, off);
    c_.robot->commandVelocity(steering_, speed, steer_torque_);
  }

  PluginContext c_;
  std::string steering_, wheel_, left_, right_;
  double wheel_radius_, torque_, steer_torque_, accel_, decel_, speed_tolerance_, steering_speed_, angle_tolerance_;
  DiffDriveGeometry geo_;
  bool encoder_ = false;
  Rate rate_;
  std::unique_ptr<TwistCommand> cmd_;
  EncoderOdometry odo_;
  WheelDriveOutputs out_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeTricycleDrive(const PluginContext& c)
{
  return std::make_unique<TricycleDrive>(c);
}

}  // namespace mybot_gazebo_lite
