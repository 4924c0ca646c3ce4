// libgazebo_ros_p3d.so
#include "builtin.h"

#include "mybot_gazebo_lite/parsing.h"

#include <nav_msgs/Odometry.h>

#include <cmath>

namespace mybot_gazebo_lite
{

namespace
{
class P3D : public SimPlugin
{
public:
  explicit P3D(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    body_ = p.link("bodyName");
    std::string topic = p.requiredStr("topicName");
    frame_ = p.str("frameName", "world");
    if (frame_ != "world" && frame_ != "/world" && frame_ != "map" && frame_ != "/map")
      p.fail("frameName", "only the world frame is supported, got '" + frame_ + "'");
    while (!frame_.empty() && frame_[0] == '/')
      frame_.erase(0, 1);
    rate_ = Rate(p.num("updateRate", 0.0));
    noise_ = std::normal_distribution<double>(0.0, p.nonNegative("gaussianNoise", 0.0));
    btVector3 xyz(0, 0, 0), rpy(0, 0, 0);
    try
    {
      if (p.has("xyzOffsets"))
        xyz = parseVec3(p.str("xyzOffsets", ""), "xyzOffsets");
      if (p.has("rpyOffsets"))
        rpy = parseVec3(p.str("rpyOffsets", ""), "rpyOffsets");
    }
    catch (const LoadError& e)
    {
      p.fail("xyzOffsets/rpyOffsets", e.what());
    }
    offset_ = makeTransform(xyz, rpy);
    ros::NodeHandle nh(c.ns);
    pub_ = p.advertise<nav_msgs::Odometry>(nh, "topicName", topic, kEveryStepQueue);
  }
  void update(double t) override
  {
    if (!rate_.due(t))
      return;
    Pose s = c_.robot->linkState(body_);
    nav_msgs::Odometry o;
    o.header.stamp = ros::Time(t);
    o.header.frame_id = frame_;
    o.child_frame_id = resolveFrame(c_, body_);
    btTransform pose = offset_ * s.tf;
    pose.setOrigin(addNoise(pose.getOrigin(), noise_, *c_.rng));  // position, linear, angular in turn
    toMsg(pose, o.pose.pose);
    o.twist.twist.linear = toMsg(addNoise(s.linear, noise_, *c_.rng));
    o.twist.twist.angular = toMsg(addNoise(s.angular, noise_, *c_.rng));
    const double var = noise_.stddev() * noise_.stddev();
    for (int i = 0; i < 6; ++i)
      o.pose.covariance[i * 7] = o.twist.covariance[i * 7] = var;
    pub_.publish(o);
  }

private:
  PluginContext c_;
  std::string body_, frame_;
  Rate rate_;
  btTransform offset_;
  std::normal_distribution<double> noise_;
  ros::Publisher pub_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeP3D(const PluginContext& c)
{
  return std::make_unique<P3D>(c);
}

}  // namespace mybot_gazebo_lite
