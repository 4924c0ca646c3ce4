// libgazebo_ros_control.so for gazebo_lite (loaded as libgazebo_lite_gazebo_ros_control.so):
// the URDF's transmissions as a simulated robot hardware, and a controller manager running
// its controllers every <controlPeriod> of sim time, before the physics step, as upstream.
#include "mybot_ros_control/ros/controller_manager.h"

#include <mybot_common/ros/params.h>
#include <std_msgs/Bool.h>

#include <cmath>

namespace mybot_ros_control
{

namespace mgl = mybot_gazebo_lite;

class GazeboRosControl : public mgl::SimPlugin
{
public:
  explicit GazeboRosControl(const mgl::PluginContext& c) : c_(c)
  {
    mgl::PluginParams p(c_, c_.spec->xml);
    const std::string sim_type = p.str("robotSimType", "gazebo_ros_control/DefaultRobotHWSim");
    if (sim_type != "gazebo_ros_control/DefaultRobotHWSim")
      p.fail("robotSimType", "only gazebo_ros_control/DefaultRobotHWSim is emulated, got '" + sim_type + "'");
    const double step = c_.world->stepSize();
    period_ = p.num("controlPeriod", step);
    if (period_ < step * (1 - 1e-9))
    {
      // As upstream: a control period shorter than the physics step cannot be kept.
      ROS_WARN("%s: <controlPeriod> %g s is shorter than the physics step; using %g s", c_.robot->name().c_str(),
               period_, step);
      period_ = step;
    }
    if (!std::isfinite(period_))
      p.fail("controlPeriod", "must be finite");
    std::vector<std::string> warnings;
    hw_ = std::make_unique<RobotHWSim>(c_.robot->spec(), warnings);
    for (const auto& w : warnings)
      ROS_WARN("%s", w.c_str());
    if (hw_->joints().empty())
      ROS_WARN("%s: libgazebo_ros_control.so: the URDF has no <transmission>: no joint to control",
               c_.robot->spec().source.c_str());
    root_ = ros::NodeHandle(c_.ns);
    readPidGains();
    if (p.has("eStopTopic"))
      estop_sub_ = root_.subscribe<std_msgs::Bool>(p.str("eStopTopic", ""), 1,
                                                   [this](const std_msgs::Bool::ConstPtr& m) { estop_ = m->data; });
    hw_->read(*c_.robot);
    hw_->reset(*c_.robot);
    hw_->write(*c_.robot, period_);
    cm_ = std::make_unique<ControllerManager>(*hw_, c_, root_);
    mgl::warnUnknownTags(c_, {"controlPeriod", "robotParam", "robotSimType", "legacyModeNS", "eStopTopic"});
    ROS_INFO("%s: gazebo_ros_control: %zu joints, control period %g s, controller_manager in '%s'",
             c_.robot->name().c_str(), hw_->joints().size(), period_, root_.getNamespace().c_str());
  }
  void preStep(double t) override
  {
    if (t + 1e-9 < next_)
      return;
    next_ = (next_ + period_ < t) ? t + period_ : next_ + period_;
    hw_->read(*c_.robot);
    cm_->update(t, period_);
    if (estop_)
      for (auto& j : hw_->joints())
        j.command = j.mode == Interface::POSITION ? j.position : 0.0;
    hw_->write(*c_.robot, period_);
  }
  void update(double) override {}
  void reset() override
  {
    next_ = 0;
    hw_->reset(*c_.robot);
    cm_->restart(c_.world->time());
    hw_->write(*c_.robot, period_);
  }

private:
  // gazebo_ros_control/pid_gains/<joint>: {p, i, d, i_clamp}: position and velocity commands
  // of that joint go through a PID to an effort (upstream's POSITION_PID / VELOCITY_PID).
  void readPidGains()
  {
    ros::NodeHandle gains(root_, "gazebo_ros_control/pid_gains");
    for (auto& j : hw_->joints())
    {
      if (!gains.hasParam(j.name + "/p"))
        continue;
      mybot_control::PidConfig cfg;
      try
      {
        cfg.p = mybot_common::readParamOrThrow<double>(gains, j.name + "/p", 0.0);
        cfg.i = mybot_common::readParamOrThrow<double>(gains, j.name + "/i", 0.0);
        cfg.d = mybot_common::readParamOrThrow<double>(gains, j.name + "/d", 0.0);
        const double clamp = std::abs(mybot_common::readParamOrThrow<double>(gains, j.name + "/i_clamp", 0.0));
        cfg.i_clamp_max = clamp;
        cfg.i_clamp_min = -clamp;
      }
      catch (const mybot_common::ParamError& e)
      {
        throw mgl::LoadError(c_.robot->spec().source + ": " + e.what());
      }
      cfg.angle_wrap = j.continuous;
      if (std::isfinite(j.max_effort))
      {
        cfg.output_max = j.max_effort;
        cfg.output_min = -j.max_effort;
      }
      j.use_pid = true;
      j.pid.setConfig(cfg);
    }
  }
  mgl::PluginContext c_;
  double period_ = 0.001, next_ = 0;
  bool estop_ = false;
  std::unique_ptr<RobotHWSim> hw_;
  ros::NodeHandle root_;
  std::unique_ptr<ControllerManager> cm_;
  ros::Subscriber estop_sub_;
};

}  // namespace mybot_ros_control

MYBOT_GAZEBO_LITE_PLUGIN(mybot_ros_control::GazeboRosControl)
