// libgazebo_ros_vacuum_gripper.so: a suction cup on <bodyName>. Switched by the std_srvs/Empty
// services `on` and `off` in the robot's namespace (off at spawn and after a reset); while on, at
// each step every link of another model whose frame is within 5 cm of the cup's is held: it is
// given the cup's velocity, snapped onto the cup's position (its orientation kept) within 1 cm,
// and pulled toward the cup with min(1 / distance, 20) N, as upstream holds it. <topicName>
// (std_msgs/Bool, every step while subscribed): whether it holds anything.
//
// What is not upstream's: upstream pulls along the offset expressed in the held link's own axes
// (a turned box is pulled askew); here along the offset in the world. Static models are left
// where they are (upstream would move a static link within 1 cm onto the cup). A link another
// robot's joints place is pulled but not moved or given the cup's velocity (set_link_state's
// rule: its joints place it).
#include "builtin.h"

#include <std_msgs/Bool.h>
#include <std_srvs/Empty.h>

namespace mybot_gazebo_lite
{

namespace
{
constexpr double kReach = 0.05, kSnap = 0.01, kMaxPull = 20.0;  // m, m, N: upstream's

class VacuumGripper : public SimPlugin
{
public:
  explicit VacuumGripper(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    body_ = p.link("bodyName");
    ros::NodeHandle nh(c.ns);
    pub_ = p.advertise<std_msgs::Bool>(nh, "topicName", p.requiredStr("topicName"), kEveryStepQueue);
    on_srv_ = nh.advertiseService("on", &VacuumGripper::switchOn, this);
    off_srv_ = nh.advertiseService("off", &VacuumGripper::switchOff, this);
    if (!on_srv_ || !off_srv_)  // roscpp said only "already advertised", naming no plugin
      p.fail("", "services '" + nh.resolveName("on") + "' and '" + nh.resolveName("off") +
                     "' are already offered by another vacuum gripper (give each its own <robotNamespace>)");
  }
  void reset() override { on_ = grasping_ = false; }
  void preStep(double t) override
  {
    grasping_ = false;
    if (!on_)
      return;
    const Pose cup = c_.robot->linkState(body_);
    for (const auto& [name, s] : c_.world->movingLinksNear(cup.tf.getOrigin(), kReach, c_.robot->name()))
    {
      const btVector3 offset = cup.tf.getOrigin() - s.tf.getOrigin();
      const double distance = offset.length();
      btTransform pose = s.tf;
      if (distance < kSnap)
        pose.setOrigin(cup.tf.getOrigin());
      c_.world->setLinkState(name, pose, cup.linear, cup.angular);  // refused for a jointed link
      if (distance > 0)
        c_.world->applyBodyWrench(name, offset / distance * std::min(1.0 / distance, kMaxPull), btVector3(0, 0, 0), t,
                                  0.0);
      grasping_ = true;
    }
  }
  void update(double) override
  {
    if (pub_.getNumSubscribers() == 0)
      return;
    std_msgs::Bool m;
    m.data = grasping_;
    pub_.publish(m);
  }

private:
  bool switchOn(std_srvs::Empty::Request&, std_srvs::Empty::Response&)
  {
    if (on_)
      ROS_WARN("gazebo_lite: vacuum gripper of '%s': already on", c_.robot->name().c_str());
    on_ = true;
    return true;
  }
  bool switchOff(std_srvs::Empty::Request&, std_srvs::Empty::Response&)
  {
    if (!on_)
      ROS_WARN("gazebo_lite: vacuum gripper of '%s': already off", c_.robot->name().c_str());
    on_ = false;
    return true;
  }
  PluginContext c_;
  std::string body_;
  bool on_ = false, grasping_ = false;
  ros::Publisher pub_;
  ros::ServiceServer on_srv_, off_srv_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeVacuumGripper(const PluginContext& c)
{
  return std::make_unique<VacuumGripper>(c);
}

}  // namespace mybot_gazebo_lite
