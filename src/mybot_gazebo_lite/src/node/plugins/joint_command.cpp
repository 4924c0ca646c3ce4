// libmybot_joint_command.so (ours)
#include "builtin.h"

#include <std_msgs/Float64.h>

#include <cmath>

namespace mybot_gazebo_lite
{

namespace
{
class JointCommand : public SimPlugin
{
public:
  explicit JointCommand(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    timeout_ = p.num("commandTimeout", 0.5);
    if (timeout_ < 0)
      p.fail("commandTimeout", "must be >= 0");
    ros::NodeHandle nh(c.ns);
    auto blocks = p.all("joint");
    if (blocks.empty())
      p.fail("joint", "at least one <joint> block is required");
    for (const XmlNode* b : blocks)
    {
      PluginParams jp(c, *b);
      auto e = std::make_unique<Entry>();
      e->name = scopedJoint(c, jp.requiredStr("name"));
      if (!c.robot->hasJoint(e->name))
        jp.fail("joint/name", "no movable joint named '" + e->name + "'");
      std::string type = jp.requiredStr("type");
      if (type == "velocity")
        e->position = false;
      else if (type == "position")
        e->position = true;
      else
        jp.fail("joint/type", "expected 'velocity' or 'position', got '" + type + "'");
      double urdf_effort = c.robot->joint(e->name).spec->effort;
      e->effort = jp.num("effortLimit", urdf_effort);
      if (!(e->effort > 0))
        jp.fail("joint/effortLimit",
                "must be positive (URDF <limit effort> of '" + e->name + "' is " + std::to_string(urdf_effort) + ")");
      // Motor strength relative to the command: 0.8 models a worn motor 20% weaker.
      e->gain = jp.num("gain", 1.0);
      if (!(e->gain > 0))
        jp.fail("joint/gain", "must be positive");
      Entry* raw = e.get();
      e->sub = subscribeCommand<std_msgs::Float64>(c, nh, jp.str("topicName", e->name + "/command"),
                                                   [this, raw](const std_msgs::Float64::ConstPtr& m)
                                                   { onCmd(raw, m->data); });
      entries_.push_back(std::move(e));
    }
    reset();
  }
  void reset() override
  {
    for (auto& e : entries_)
    {
      e->target = e->position ? c_.robot->jointPosition(e->name) : 0.0;
      e->have = false;
      apply(*e);
    }
  }
  void update(double t) override
  {
    if (timeout_ <= 0)
      return;
    for (auto& e : entries_)
      if (e->have && !e->position && t - e->stamp > timeout_)
      {
        e->target = 0;  // a velocity joint whose commands stop must stop
        e->have = false;
        apply(*e);
      }
  }

private:
  struct Entry
  {
    std::string name;
    bool position = false, have = false;
    double effort = 0, target = 0, stamp = 0, gain = 1;
    ros::Subscriber sub;
  };
  void onCmd(Entry* e, double v)
  {
    if (!std::isfinite(v))
    {
      ROS_WARN_THROTTLE(1.0, "%s: ignoring non-finite command for joint '%s'", c_.robot->name().c_str(),
                        e->name.c_str());
      return;
    }
    e->target = v;
    e->stamp = c_.world->time();
    e->have = true;
    apply(*e);
  }
  void apply(const Entry& e)
  {
    if (e.position)
      c_.robot->commandPosition(e.name, e.target, e.effort);
    else
      c_.robot->commandVelocity(e.name, e.gain * e.target, e.effort);
  }
  PluginContext c_;
  double timeout_;
  std::vector<std::unique_ptr<Entry>> entries_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeJointCommand(const PluginContext& c)
{
  return std::make_unique<JointCommand>(c);
}

}  // namespace mybot_gazebo_lite
