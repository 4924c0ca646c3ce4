// libhector_gazebo_ros_sonar.so: an ultrasound ranger (sensor_msgs/Range on `sonar`) from a
// <sensor type="ray">: the nearest of its rays, through hector's error model (<gaussianNoise>,
// <offset>, <drift>, ...) and clamped to the ray's range when something is in range; max_range
// when nothing is. Its field of view is the lesser of the sensor's horizontal and vertical spans
// (upstream's: 0 for a sensor with one vertical sample). At 10 Hz unless <updateRate> says otherwise.
#include "builtin.h"

#include <sensor_msgs/Range.h>

namespace mybot_gazebo_lite
{

namespace
{
class HectorSonar : public SimPlugin
{
public:
  explicit HectorSonar(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    if (!c.spec->has_sensor)
      p.fail("sensor", "libhector_gazebo_ros_sonar.so must sit inside a <sensor type=\"ray\">");
    PluginParams s(c, c.spec->sensor);
    link_ = c.spec->reference;
    sensor_pose_ = s.pose("pose");
    rays_ = SensorRays::fromSensor(s);
    msg_.min_range = rays_.min;
    msg_.max_range = rays_.max;
    msg_.radiation_type = sensor_msgs::Range::ULTRASOUND;
    const double h = s.num("ray/scan/horizontal/max_angle", 0.0) - s.num("ray/scan/horizontal/min_angle", 0.0);
    const double v = s.num("ray/scan/vertical/max_angle", 0.0) - s.num("ray/scan/vertical/min_angle", 0.0);
    msg_.field_of_view = std::min(std::abs(h), std::abs(v));
    msg_.header.frame_id = hectorFrame(p, "sonar_link");
    error_ = SensorError(hectorError(p, ""));
    timer_ = HectorTimer(p, 10.0);
    ros::NodeHandle nh(c.ns);
    pub_ = p.advertise<sensor_msgs::Range>(nh, "topicName", p.str("topicName", "sonar"), kEveryStepQueue);
    reset();
  }
  void reset() override
  {
    error_.reset(*c_.rng);
    timer_.reset();
  }
  void update(double t) override
  {
    double dt;
    if (!timer_.due(t, dt))
      return;
    const btTransform tf = c_.robot->linkPose(link_) * sensor_pose_;
    const double nearest = rays_.nearest(*c_.world, tf, c_.robot);
    msg_.header.stamp = ros::Time(t);
    msg_.range = nearest;
    if (nearest < rays_.max)  // the double the rays were cast to, not the message's float
      msg_.range =
          std::max<double>(msg_.min_range, std::min<double>(msg_.max_range, error_.measure(nearest, dt, *c_.rng)));
    pub_.publish(msg_);
  }

  SensorUpdates sensorUpdates() const override { return {timer_.fired(), nullptr}; }

private:
  PluginContext c_;
  std::string link_;
  btTransform sensor_pose_;
  SensorRays rays_;
  SensorError error_;
  HectorTimer timer_;
  sensor_msgs::Range msg_;
  ros::Publisher pub_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeHectorSonar(const PluginContext& c)
{
  return std::make_unique<HectorSonar>(c);
}

}  // namespace mybot_gazebo_lite
