// forward_command_controller's family: the value on `command` goes to the joint's interface
// (position_controllers/JointPositionController, velocity_controllers/JointVelocityController,
// effort_controllers/JointEffortController and their JointGroup versions).
#include "controllers.h"

#include <std_msgs/Float64.h>
#include <std_msgs/Float64MultiArray.h>

#include <cmath>

namespace mybot_ros_control
{

namespace
{

// A position controller starts by holding where the joint is; the others at rest.
double restingCommand(const SimJoint& j, Interface i)
{
  return i == Interface::POSITION ? j.position : 0.0;
}

class ForwardGroupController : public Controller
{
public:
  ForwardGroupController(const ControllerContext& c, Interface i, bool group) : name_(c.name), interface_(i)
  {
    const std::vector<std::string> names =
        group ? c.stringList("joints", true) : std::vector<std::string>{c.requiredString("joint")};
    for (const auto& n : names)
    {
      joints_.push_back(&c.joint(group ? "joints" : "joint", n, i));
      claimed_[interfaceName(i)].push_back(n);
    }
    hw_ = c.hw;
    ros::NodeHandle nh = c.nh;
    if (group)
      sub_ = mybot_gazebo_lite::subscribeCommand<std_msgs::Float64MultiArray>(
          *c.plugin, nh, "command", [this](const std_msgs::Float64MultiArray::ConstPtr& m) { onCommand(m->data); });
    else
      sub_ = mybot_gazebo_lite::subscribeCommand<std_msgs::Float64>(
          *c.plugin, nh, "command", [this](const std_msgs::Float64::ConstPtr& m) { onCommand({m->data}); });
  }
  void starting(double) override
  {
    commands_.clear();
    for (SimJoint* j : joints_)
    {
      hw_->claim(*j, interface_);
      commands_.push_back(restingCommand(*j, interface_));
    }
  }
  void update(double, double) override
  {
    for (size_t k = 0; k < joints_.size(); ++k)
      joints_[k]->command = commands_[k];
  }

private:
  void onCommand(const std::vector<double>& v)
  {
    if (v.size() != joints_.size())
    {
      ROS_ERROR_THROTTLE(1.0, "%s: command has %zu values for %zu joints; ignored", name_.c_str(), v.size(),
                         joints_.size());
      return;
    }
    for (double x : v)
      if (!std::isfinite(x))
      {
        ROS_WARN_THROTTLE(1.0, "%s: ignoring a non-finite command", name_.c_str());
        return;
      }
    commands_ = v;
  }
  std::string name_;
  Interface interface_;
  RobotHWSim* hw_;
  std::vector<SimJoint*> joints_;
  std::vector<double> commands_;
  ros::Subscriber sub_;
};
}  // namespace

std::unique_ptr<Controller> makeForwardController(const ControllerContext& c, Interface i)
{
  return std::make_unique<ForwardGroupController>(c, i, false);
}

std::unique_ptr<Controller> makeForwardGroupController(const ControllerContext& c, Interface i)
{
  return std::make_unique<ForwardGroupController>(c, i, true);
}

}  // namespace mybot_ros_control
