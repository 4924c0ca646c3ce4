// libgazebo_ros_block_laser.so: a 3D laser (horizontal x vertical samples of a <sensor type="ray">)
// as a sensor_msgs/PointCloud in the sensor frame, with an "intensity" channel, as upstream. Each
// ray is cast through Bullet (walls, robots, the ground); a ray that hits nothing gives a point at
// the maximum range, as upstream does.
#include "builtin.h"

#include <sensor_msgs/PointCloud.h>

#include <cmath>

namespace mybot_gazebo_lite
{

namespace
{
class BlockLaser : public SimPlugin
{
public:
  explicit BlockLaser(const PluginContext& c) : c_(c), noise_(0, 1)
  {
    PluginParams p(c, c.spec->xml);
    if (!c.spec->has_sensor)
      p.fail("sensor", "the block laser plugin must sit inside a <sensor type=\"ray\">");
    PluginParams s(c, c.spec->sensor);
    link_ = c.spec->reference;
    sensor_pose_ = s.pose("pose");
    rate_ = Rate(p.num("updateRate", s.num("update_rate", 0.0)));
    rays_ = SensorRays::fromSensor(s);
    gn_ = p.num("gaussianNoise", 0.0);
    if (gn_ < 0)
      p.fail("gaussianNoise", "must be >= 0");
    frame_ = resolveFrame(c, p.str("frameName", "/world"));
    ros::NodeHandle nh(c.ns);
    pub_ = p.advertise<sensor_msgs::PointCloud>(nh, "topicName", p.str("topicName", "/world"), 1);
  }
  void update(double t) override
  {
    if (!rate_.due(t) || pub_.getNumSubscribers() == 0)
      return;
    const btTransform tf = c_.robot->linkState(link_).tf * sensor_pose_;
    const std::vector<double> ranges = rays_.cast(*c_.world, tf, c_.robot);
    sensor_msgs::PointCloud m;
    m.header.stamp = ros::Time(t);
    m.header.frame_id = frame_;
    m.channels.resize(1);
    m.channels[0].name = "intensity";
    for (std::size_t k = 0; k < ranges.size(); ++k)
    {
      const double r = std::min(rays_.max, ranges[k] + (gn_ > 0 ? gn_ * noise_(*c_.rng) : 0.0));
      geometry_msgs::Point32 pt;
      pt.x = static_cast<float>(rays_.dirs[k].x() * r);
      pt.y = static_cast<float>(rays_.dirs[k].y() * r);
      pt.z = static_cast<float>(rays_.dirs[k].z() * r);
      m.points.push_back(pt);
      m.channels[0].values.push_back(0.0f);
    }
    pub_.publish(m);
  }

  SensorUpdates sensorUpdates() const override { return {&rate_.fired, nullptr}; }

private:
  PluginContext c_;
  std::string link_, frame_;
  btTransform sensor_pose_;
  Rate rate_;
  SensorRays rays_;
  double gn_;
  std::normal_distribution<double> noise_;
  ros::Publisher pub_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeBlockLaser(const PluginContext& c)
{
  return std::make_unique<BlockLaser>(c);
}

}  // namespace mybot_gazebo_lite
