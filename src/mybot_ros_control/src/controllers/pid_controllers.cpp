// The PID family of ros_controllers: effort_controllers/JointPositionController,
// effort_controllers/JointVelocityController, velocity_controllers/JointPositionController and
// effort_controllers/JointGroupPositionController. Gains from `pid: {p, i, d, i_clamp}` (or
// i_clamp_min/i_clamp_max), the target on `command`, the loop on `state` every 10th update.
#include "controllers.h"

#include <control_msgs/JointControllerState.h>
#include <std_msgs/Float64.h>
#include <std_msgs/Float64MultiArray.h>

#include <cmath>

namespace mybot_ros_control
{

namespace
{

class PidGroupController : public Controller
{
public:
  // on_position: the target is a position (else a velocity); output: the interface commanded.
  PidGroupController(const ControllerContext& c, Interface output, bool on_position, bool group)
      : name_(c.name), output_(output), on_position_(on_position), hw_(c.hw)
  {
    const std::vector<std::string> names =
        group ? c.stringList("joints", true) : std::vector<std::string>{c.requiredString("joint")};
    for (const auto& n : names)
    {
      Loop l;
      l.joint = &c.joint(group ? "joints" : "joint", n, output);
      l.pid.setConfig(readPid(c, group ? n + "/pid" : "pid", on_position && l.joint->continuous));
      loops_.push_back(l);
      claimed_[interfaceName(output)].push_back(n);
    }
    ros::NodeHandle nh = c.nh;
    if (group)
    {
      sub_ = mybot_gazebo_lite::subscribeCommand<std_msgs::Float64MultiArray>(
          *c.plugin, nh, "command", [this](const std_msgs::Float64MultiArray::ConstPtr& m) { onCommand(m->data); });
    }
    else
    {
      sub_ = mybot_gazebo_lite::subscribeCommand<std_msgs::Float64>(
          *c.plugin, nh, "command", [this](const std_msgs::Float64::ConstPtr& m) { onCommand({m->data}); });
      state_pub_ = nh.advertise<control_msgs::JointControllerState>("state", 1);
    }
  }
  void starting(double) override
  {
    for (auto& l : loops_)
    {
      hw_->claim(*l.joint, output_);
      l.target = on_position_ ? l.joint->position : 0.0;
      l.pid.reset();
    }
    count_ = 0;
  }
  void update(double t, double dt) override
  {
    for (auto& l : loops_)
    {
      SimJoint& j = *l.joint;
      const double target = on_position_ ? clampPosition(j, l.target) : l.target;
      const double measured = on_position_ ? j.position : j.velocity;
      j.command = l.pid.compute(target, measured, dt);
    }
    if (state_pub_ && count_++ % 10 == 0)
      publishState(t, dt);
  }
  void stopping(double) override
  {
    for (auto& l : loops_)
      l.joint->command = 0.0;
  }

private:
  struct Loop
  {
    SimJoint* joint;
    mybot_control::Pid pid;
    double target = 0;
  };
  void onCommand(const std::vector<double>& v)
  {
    if (v.size() != loops_.size())
    {
      ROS_ERROR_THROTTLE(1.0, "%s: command has %zu values for %zu joints; ignored", name_.c_str(), v.size(),
                         loops_.size());
      return;
    }
    for (double x : v)
      if (!std::isfinite(x))
      {
        ROS_WARN_THROTTLE(1.0, "%s: ignoring a non-finite command", name_.c_str());
        return;
      }
    for (size_t k = 0; k < v.size(); ++k)
      loops_[k].target = v[k];
  }
  void publishState(double t, double dt)
  {
    const Loop& l = loops_.front();
    const auto& cfg = l.pid.config();
    control_msgs::JointControllerState s;
    s.header.stamp = ros::Time(t);
    s.set_point = on_position_ ? clampPosition(*l.joint, l.target) : l.target;
    s.process_value = on_position_ ? l.joint->position : l.joint->velocity;
    s.process_value_dot = on_position_ ? l.joint->velocity : 0.0;
    s.error = l.pid.error();
    s.time_step = dt;
    s.command = l.joint->command;
    s.p = cfg.p;
    s.i = cfg.i;
    s.d = cfg.d;
    s.i_clamp = cfg.i_clamp_max;
    s.antiwindup = false;
    state_pub_.publish(s);
  }
  std::string name_;
  Interface output_;
  bool on_position_;
  RobotHWSim* hw_;
  std::vector<Loop> loops_;
  unsigned count_ = 0;
  ros::Subscriber sub_;
  ros::Publisher state_pub_;
};
}  // namespace

std::unique_ptr<Controller> makePidController(const ControllerContext& c, Interface output, bool on_position)
{
  return std::make_unique<PidGroupController>(c, output, on_position, false);
}

std::unique_ptr<Controller> makePidGroupPositionController(const ControllerContext& c, Interface output)
{
  return std::make_unique<PidGroupController>(c, output, true, true);
}

}  // namespace mybot_ros_control
