// roboticsgroup_gazebo_plugins' mimic joint (libroboticsgroup_gazebo_mimic_joint_plugin.so, and
// its fork's libroboticsgroup_upatras_gazebo_mimic_joint_plugin.so): what a URDF <mimic> says and
// Gazebo classic does not do, a gripper's second finger following the first. <mimicJoint> is held
// at <multiplier> (1) x <joint> + <offset> (0) whenever it is <sensitiveness> (0) or more away.
//
// Upstream sets the follower's position outright at every step; here a position servo takes it
// there (a few steps after a jump, and on time while it moves: the leader's speed is fed
// forward), as strong as the follower's URDF <limit effort> (1000 without one), so the follower
// pushes what it touches as a real finger would. With <hasPID>, as upstream, a PID on the error
// (gains p, i, d from <robot ns>/gazebo_ros_control/pid_gains/<mimicJoint>) gives the follower an
// effort, clamped to <maxEffort> (1).
#include "builtin.h"

#include <algorithm>
#include <cmath>

namespace mybot_gazebo_lite
{

namespace
{
class MimicJoint : public SimPlugin
{
public:
  explicit MimicJoint(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    for (const char* tag : {"joint", "mimicJoint"})
      if (!p.has(tag))
        p.fail(tag, "required");
    leader_ = p.joint("joint", "");
    follower_ = p.joint("mimicJoint", "");
    if (leader_ == follower_)
      p.fail("mimicJoint", "a joint cannot mimic itself");
    multiplier_ = p.num("multiplier", 1.0);
    offset_ = p.num("offset", 0.0);
    sensitiveness_ = p.nonNegative("sensitiveness", 0.0);
    max_effort_ = p.positive("maxEffort", 1.0);
    const JointSpec& spec = *c.robot->joint(follower_).spec;
    servo_effort_ = spec.has_effort && spec.effort > 0 ? spec.effort : 1000.0;
    pid_ = p.has("hasPID");
    if (pid_)
    {
      ros::NodeHandle gains(ros::NodeHandle(c.ns), "gazebo_ros_control/pid_gains/" + follower_);
      gains.param("p", kp_, 0.0);
      gains.param("i", ki_, 0.0);
      gains.param("d", kd_, 0.0);
    }
  }
  void reset() override { integral_ = 0, last_error_ = NAN; }
  void preStep(double) override
  {
    const double target = multiplier_ * c_.robot->jointPosition(leader_) + offset_;
    const double error = target - c_.robot->jointPosition(follower_);
    if (std::abs(error) < sensitiveness_)
      return;
    if (!pid_)
    {
      c_.robot->commandPosition(follower_, target, servo_effort_, multiplier_ * c_.robot->jointVelocity(leader_));
      return;
    }
    // control_toolbox::Pid's computeCommand(error, dt): the derivative from the last error.
    const double dt = c_.world->stepSize();
    integral_ += error * dt;
    const double derivative = std::isnan(last_error_) ? 0.0 : (error - last_error_) / dt;
    last_error_ = error;
    const double effort = kp_ * error + ki_ * integral_ + kd_ * derivative;
    c_.robot->commandEffort(follower_, std::max(-max_effort_, std::min(max_effort_, effort)));
  }
  void update(double) override {}

private:
  PluginContext c_;
  std::string leader_, follower_;
  double multiplier_, offset_, sensitiveness_, max_effort_, servo_effort_;
  bool pid_ = false;
  double kp_ = 0, ki_ = 0, kd_ = 0, integral_ = 0, last_error_ = NAN;
};
}  // namespace

std::unique_ptr<SimPlugin> makeMimicJoint(const PluginContext& c)
{
  return std::make_unique<MimicJoint>(c);
}

}  // namespace mybot_gazebo_lite
