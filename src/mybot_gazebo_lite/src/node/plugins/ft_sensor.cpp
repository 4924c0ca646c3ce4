// libgazebo_ros_ft_sensor.so: the wrench a joint transmits (geometry_msgs/WrenchStamped on
// <topicName>): the parent's push on the child link, in the child link's axes, its torque about
// the joint, as upstream reads Gazebo's Joint::GetForceTorque(0).body2Force / body2Torque. Stamped
// with the child link's name (tf_prefix applied). Constraint and actuation alike: a servo holding
// an arm shows its torque, a free joint none about its axis (Robot::jointWrench). A fixed joint
// needs its <gazebo reference> to keep it (<preserveFixedJoint>), as in Gazebo. <gaussianNoise>
// is added to each of the six values. At <updateRate> (0: every step) while someone subscribes.
#include "builtin.h"

#include <geometry_msgs/WrenchStamped.h>

namespace mybot_gazebo_lite
{

namespace
{
class FTSensor : public SimPlugin
{
public:
  explicit FTSensor(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    // A movable joint, or a fixed one Gazebo keeps (a wrist sensor's: <preserveFixedJoint>).
    const std::string kept = scopedJoint(c, p.requiredStr("jointName"));
    joint_ = c.robot->hasKeptFixedJoint(kept) ? kept : p.joint("jointName", "");
    const std::string topic = p.requiredStr("topicName");
    noise_ = std::normal_distribution<double>(0.0, p.nonNegative("gaussianNoise", 0.0));
    rate_ = Rate(p.num("updateRate", 0.0));
    msg_.header.frame_id = resolveFrame(c, c.robot->spec().joint(joint_)->child);
    c.robot->watchJointWrench(joint_);
    ros::NodeHandle nh(c.ns);
    pub_ = p.advertise<geometry_msgs::WrenchStamped>(nh, "topicName", topic, kEveryStepQueue);
  }
  void update(double t) override
  {
    if (pub_.getNumSubscribers() == 0 || !rate_.due(t))
      return;
    const auto [force, torque] = c_.robot->jointWrench(joint_);
    msg_.header.stamp = ros::Time(t);
    msg_.wrench.force = toMsg(addNoise(force, noise_, *c_.rng));
    msg_.wrench.torque = toMsg(addNoise(torque, noise_, *c_.rng));
    pub_.publish(msg_);
  }

private:
  PluginContext c_;
  std::string joint_;
  std::normal_distribution<double> noise_;
  Rate rate_;
  geometry_msgs::WrenchStamped msg_;
  ros::Publisher pub_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeFTSensor(const PluginContext& c)
{
  return std::make_unique<FTSensor>(c);
}

}  // namespace mybot_gazebo_lite
