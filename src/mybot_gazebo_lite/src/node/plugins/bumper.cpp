// libgazebo_ros_bumper.so: the contacts of the link holding a <sensor type="contact">, as a
// gazebo_msgs/ContactsState, as gazebo_ros_bumper publishes it. Positions and
// normals are in the world frame, or in the link's frame when frameName names a link.
#include "builtin.h"

#include <gazebo_msgs/ContactsState.h>

#include <cmath>

namespace mybot_gazebo_lite
{

namespace
{
using gazebo_msgs::ContactsState;
using gazebo_msgs::ContactState;

class Bumper : public SimPlugin
{
public:
  explicit Bumper(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    if (!c.spec->has_sensor)
      p.fail("sensor", "the bumper plugin must sit inside a <sensor type=\"contact\">");
    PluginParams s(c, c.spec->sensor);
    link_ = c.spec->reference;
    collision_ = s.str("contact/collision", link_ + "_collision");
    rate_ = Rate(s.num("update_rate", 0.0));
    frame_ = p.str("frameName", "world");
    frame_link_ = scopedLink(c, frame_);
    in_link_frame_ = c.robot->hasLink(frame_link_);
    ros::NodeHandle nh(c.ns);
    pub_ = p.advertise<ContactsState>(nh, "bumperTopicName", p.str("bumperTopicName", "bumper_states"), 1);
    c.robot->recordContactPoints(true);
  }
  void update(double t) override
  {
    if (!rate_.due(t))
      return;
    ContactsState m;
    m.header.stamp = ros::Time(t);
    m.header.frame_id = in_link_frame_ ? resolveFrame(c_, frame_) : "world";
    const btTransform to_frame =
        in_link_frame_ ? c_.robot->linkState(frame_link_).tf.inverse() : btTransform::getIdentity();
    const double dt = c_.world->stepSize();
    for (const auto& pt : c_.robot->contacts().points)
    {
      if (std::find(pt.links.begin(), pt.links.end(), link_) == pt.links.end())
        continue;
      ContactState* st = nullptr;
      for (auto& s : m.states)
        if (s.collision2_name == pt.other)
          st = &s;
      if (!st)
      {
        m.states.emplace_back();
        st = &m.states.back();
        st->collision1_name = c_.robot->name() + "::" + link_ + "::" + collision_;
        st->collision2_name = pt.other;
        st->info = "Debug:  i:(0/1)     my geom:" + st->collision1_name + "   other geom:" + pt.other;
      }
      const btVector3 pos = to_frame * pt.position, n = to_frame.getBasis() * pt.normal;
      const btVector3 f = n * (pt.impulse / dt);
      geometry_msgs::Vector3 v;
      v.x = pos.x(), v.y = pos.y(), v.z = pos.z();
      st->contact_positions.push_back(v);
      v.x = n.x(), v.y = n.y(), v.z = n.z();
      st->contact_normals.push_back(v);
      st->depths.push_back(pt.depth);
      geometry_msgs::Wrench w;
      w.force.x = f.x(), w.force.y = f.y(), w.force.z = f.z();
      st->wrenches.push_back(w);
      st->total_wrench.force.x += f.x();
      st->total_wrench.force.y += f.y();
      st->total_wrench.force.z += f.z();
    }
    pub_.publish(m);
  }

  SensorUpdates sensorUpdates() const override { return {&rate_.fired, nullptr}; }

private:
  PluginContext c_;
  std::string link_, collision_, frame_, frame_link_;
  bool in_link_frame_;
  Rate rate_;
  ros::Publisher pub_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeBumper(const PluginContext& c)
{
  return std::make_unique<Bumper>(c);
}

}  // namespace mybot_gazebo_lite
