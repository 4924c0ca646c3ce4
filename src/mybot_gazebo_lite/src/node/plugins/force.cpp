// libgazebo_ros_force.so: the last geometry_msgs/Wrench on <topicName> pushes <bodyName> at every
// step, the force at its body's centre of mass, both in the world's axes (as upstream's AddForce
// and AddTorque). A wrench with a NaN or inf is ignored with a warning. Unlike upstream, a world
// or simulation reset lets go of it: a robot put back is not pushed by a command from before.
#include "builtin.h"

#include <geometry_msgs/Wrench.h>

namespace mybot_gazebo_lite
{

namespace
{
class Force : public SimPlugin
{
public:
  explicit Force(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    body_ = p.link("bodyName");
    topic_ = p.requiredStr("topicName");
    ros::NodeHandle nh(c.ns);
    sub_ = subscribeCommand<geometry_msgs::Wrench>(c, nh, topic_,
                                                   [this](const geometry_msgs::Wrench::ConstPtr& m) { onWrench(*m); });
  }
  void preStep(double) override
  {
    if (force_.fuzzyZero() && torque_.fuzzyZero())
      return;
    c_.robot->addWrench(body_, force_, torque_);
  }
  void update(double) override {}
  void reset() override { force_ = torque_ = btVector3(0, 0, 0); }

private:
  void onWrench(const geometry_msgs::Wrench& m)
  {
    const double v[6] = {m.force.x, m.force.y, m.force.z, m.torque.x, m.torque.y, m.torque.z};
    for (double x : v)
      if (!std::isfinite(x))
      {
        ROS_WARN_THROTTLE(1.0, "gazebo_lite: %s: a wrench with a NaN or inf; ignored", topic_.c_str());
        return;
      }
    force_ = btVector3(v[0], v[1], v[2]);
    torque_ = btVector3(v[3], v[4], v[5]);
  }

  PluginContext c_;
  std::string body_, topic_;
  btVector3 force_{0, 0, 0}, torque_{0, 0, 0};
  ros::Subscriber sub_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeForce(const PluginContext& c)
{
  return std::make_unique<Force>(c);
}

}  // namespace mybot_gazebo_lite
