// libgazebo_ros_joint_state_publisher.so
#include "builtin.h"

#include <sensor_msgs/JointState.h>

#include <cmath>

namespace mybot_gazebo_lite
{

namespace
{
class JointStatePub : public SimPlugin
{
public:
  explicit JointStatePub(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    if (p.has("jointName"))
    {
      names_ = p.jointList("jointName", ",");  // as given: a nested model's plugin names its own joints so
      for (const std::string& j : names_)
        joints_.push_back(scopedJoint(c, j));
    }
    else
    {
      joints_ = names_ = c.robot->movableJoints();
    }
    rate_ = Rate(p.num("updateRate", 100.0));
    ros::NodeHandle nh(c.ns);
    pub_ = p.advertise<sensor_msgs::JointState>(nh, "", "joint_states", 10);
  }
  void update(double t) override
  {
    if (!rate_.due(t))
      return;
    sensor_msgs::JointState js;
    js.header.stamp = ros::Time(t);
    js.name = names_;
    for (const auto& j : joints_)
    {
      js.position.push_back(c_.robot->jointPosition(j));
      js.velocity.push_back(c_.robot->jointVelocity(j));
    }
    pub_.publish(js);
  }

private:
  PluginContext c_;
  std::vector<std::string> joints_, names_;  // the robot's joints, and as the plugin names them
  Rate rate_;
  ros::Publisher pub_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeJointStatePublisher(const PluginContext& c)
{
  return std::make_unique<JointStatePub>(c);
}

}  // namespace mybot_gazebo_lite
