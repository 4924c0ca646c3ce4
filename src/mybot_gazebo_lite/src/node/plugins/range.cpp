// libgazebo_ros_range.so: a sonar or infrared ranger (sensor_msgs/Range) from a <sensor type="ray">.
// Every ray of the sensor's horizontal x vertical samples is cast through Bullet (walls, robots,
// the ground); the reading is the nearest, plus noise, and max_range when nothing is in range,
// as upstream reports it.
#include "builtin.h"

#include <sensor_msgs/Range.h>

#include <cmath>

namespace mybot_gazebo_lite
{

namespace
{
class Range : public SimPlugin
{
public:
  explicit Range(const PluginContext& c) : c_(c), noise_(0, 1)
  {
    PluginParams p(c, c.spec->xml);
    if (!c.spec->has_sensor)
      p.fail("sensor", "the range plugin must sit inside a <sensor type=\"ray\">");
    PluginParams s(c, c.spec->sensor);
    link_ = c.spec->reference;
    sensor_pose_ = s.pose("pose");
    rate_ = Rate(p.num("updateRate", s.num("update_rate", 0.0)));
    rays_ = SensorRays::fromSensor(s);
    msg_.min_range = rays_.min;
    msg_.max_range = rays_.max;
    gn_ = p.num("gaussianNoise", 0.0);
    if (gn_ < 0)
      p.fail("gaussianNoise", "must be >= 0");
    const std::string radiation = p.str("radiation", "infrared");
    if (radiation == "ultrasound")
      msg_.radiation_type = sensor_msgs::Range::ULTRASOUND;
    else if (radiation == "infrared")
      msg_.radiation_type = sensor_msgs::Range::INFRARED;
    else
      p.fail("radiation", "expected 'ultrasound' or 'infrared', got '" + radiation + "'");
    msg_.field_of_view =
        p.num("fov", s.num("ray/scan/horizontal/max_angle", 0.0) - s.num("ray/scan/horizontal/min_angle", 0.0));
    msg_.header.frame_id = resolveFrame(c, p.str("frameName", c.spec->reference));
    ros::NodeHandle nh(c.ns);
    pub_ = p.advertise<sensor_msgs::Range>(nh, "topicName", p.str("topicName", "sonar"), 1);
  }
  void update(double t) override
  {
    if (!rate_.due(t))
      return;
    const btTransform tf = c_.robot->linkState(link_).tf * sensor_pose_;
    const double nearest = rays_.nearest(*c_.world, tf, c_.robot);
    msg_.header.stamp = ros::Time(t);
    msg_.range =
        nearest < rays_.max  // the double the rays were cast to, not the message's float
            ? std::max<double>(msg_.min_range, std::min<double>(msg_.max_range, nearest + gn_ * noise_(*c_.rng)))
            : msg_.max_range;
    pub_.publish(msg_);
  }

  SensorUpdates sensorUpdates() const override { return {&rate_.fired, nullptr}; }

private:
  PluginContext c_;
  std::string link_;
  btTransform sensor_pose_;
  Rate rate_;
  double gn_;
  SensorRays rays_;
  sensor_msgs::Range msg_;
  std::normal_distribution<double> noise_;
  ros::Publisher pub_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeRange(const PluginContext& c)
{
  return std::make_unique<Range>(c);
}

}  // namespace mybot_gazebo_lite
