// libhector_gazebo_ros_magnetic.so: a magnetometer on a link. The Earth's field (earth_model.h:
// <magnitude>, <declination>, <inclination>, <referenceHeading>, degrees, by default the world's
// <spherical_coordinates>') seen in the link's axes,
// with hector's error model, as geometry_msgs/Vector3Stamped on `magnetic`, or as
// sensor_msgs/MagneticField with <useMagneticFieldMsgs>.
#include "builtin.h"

#include "mybot_gazebo_lite/earth_model.h"

#include <geometry_msgs/Vector3Stamped.h>
#include <sensor_msgs/MagneticField.h>

namespace mybot_gazebo_lite
{

namespace
{
constexpr double kDeg = M_PI / 180.0;

class HectorMagnetic : public SimPlugin
{
public:
  explicit HectorMagnetic(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    body_ = hectorBody(c, p);
    frame_ = hectorFrame(p, body_);
    // Upstream's default heading is the world's <spherical_coordinates>' (its heading_deg is
    // anticlockwise from east; 0, x east, is a compass heading of 90 degrees).
    const double world_heading = 90.0 - c.world->worldSpec().spherical.heading_deg;
    const std::array<double, 3> f =
        magneticFieldInWorld(p.num("magnitude", 1.0), p.num("referenceHeading", world_heading) * kDeg,
                             p.num("declination", 0.0) * kDeg, p.num("inclination", 60.0) * kDeg);
    field_ = btVector3(f[0], f[1], f[2]);
    error_ = SensorError3(hectorError3(p, ""));
    timer_ = HectorTimer(p, 0.0);
    field_msgs_ = p.boolean("useMagneticFieldMsgs", false);
    const std::string topic = p.str("topicName", "magnetic");
    ros::NodeHandle nh(c.ns);
    pub_ = field_msgs_ ? p.advertise<sensor_msgs::MagneticField>(nh, "topicName", topic, kEveryStepQueue)
                       : p.advertise<geometry_msgs::Vector3Stamped>(nh, "topicName", topic, kEveryStepQueue);
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
    const btVector3 in_body = c_.robot->linkPose(body_).getBasis().transpose() * field_;
    geometry_msgs::Vector3 v;
    v.x = error_[0].measure(in_body.x(), dt, *c_.rng);
    v.y = error_[1].measure(in_body.y(), dt, *c_.rng);
    v.z = error_[2].measure(in_body.z(), dt, *c_.rng);
    std_msgs::Header h;
    h.stamp = ros::Time(t);
    h.frame_id = frame_;
    if (field_msgs_)
    {
      sensor_msgs::MagneticField m;  // covariance all zero: unknown, as upstream
      m.header = h;
      m.magnetic_field = v;
      pub_.publish(m);
    }
    else
    {
      geometry_msgs::Vector3Stamped m;
      m.header = h;
      m.vector = v;
      pub_.publish(m);
    }
  }

  SensorUpdates sensorUpdates() const override { return {timer_.fired(), nullptr}; }

private:
  PluginContext c_;
  std::string body_, frame_;
  btVector3 field_;
  SensorError3 error_;
  HectorTimer timer_;
  bool field_msgs_;
  ros::Publisher pub_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeHectorMagnetic(const PluginContext& c)
{
  return std::make_unique<HectorMagnetic>(c);
}

}  // namespace mybot_gazebo_lite
