// libgazebo_ros_f3d.so: the external wrench on <bodyName> (geometry_msgs/WrenchStamped on
// <topicName>), as upstream reads it from the body's force accumulator: what gazebo_ros_force and
// apply_body_wrench put on it over the last step, in the world's axes about its centre of mass;
// not the contact or joint forces. Every step while someone subscribes. Stamped with <frameName>
// (world; upstream too writes it in the header and gives the values in the world's axes).
#include "builtin.h"

#include <geometry_msgs/WrenchStamped.h>

namespace mybot_gazebo_lite
{

namespace
{
class F3D : public SimPlugin
{
public:
  explicit F3D(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    body_ = p.link("bodyName");
    msg_.header.frame_id = resolveFrame(c, p.str("frameName", "world"));
    ros::NodeHandle nh(c.ns);
    pub_ = p.advertise<geometry_msgs::WrenchStamped>(nh, "topicName", p.requiredStr("topicName"), kEveryStepQueue);
  }
  void update(double t) override
  {
    if (pub_.getNumSubscribers() == 0)
      return;
    const auto w = c_.robot->externalWrench(body_);
    msg_.header.stamp = ros::Time(t);
    msg_.wrench.force = toMsg(w.first);
    msg_.wrench.torque = toMsg(w.second);
    pub_.publish(msg_);
  }

private:
  PluginContext c_;
  std::string body_;
  geometry_msgs::WrenchStamped msg_;
  ros::Publisher pub_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeF3D(const PluginContext& c)
{
  return std::make_unique<F3D>(c);
}

}  // namespace mybot_gazebo_lite
