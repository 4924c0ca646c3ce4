// libhector_gazebo_ros_gps.so: a GNSS receiver on a link (sensor_msgs/NavSatFix on `fix`, its velocity
// as geometry_msgs/Vector3Stamped on `fix_velocity`), placed on the Earth by earth_model.h, with
// hector's error models for position and velocity (<drift>, <gaussianNoise>, ...; <velocityDrift>, ...).
#include "builtin.h"

#include "mybot_gazebo_lite/earth_model.h"

#include <geometry_msgs/Vector3Stamped.h>
#include <sensor_msgs/NavSatFix.h>

namespace mybot_gazebo_lite
{

namespace
{
class HectorGps : public SimPlugin
{
public:
  explicit HectorGps(const PluginContext& c) : c_(c), earth_(GeoReference{})
  {
    PluginParams p(c, c.spec->xml);
    body_ = hectorBody(c, p);
    GeoReference ref;
    ref.latitude_deg = p.num("referenceLatitude", ref.latitude_deg);
    ref.longitude_deg = p.num("referenceLongitude", ref.longitude_deg);
    ref.heading_deg = p.num("referenceHeading", ref.heading_deg);
    ref.altitude = p.num("referenceAltitude", ref.altitude);
    if (std::abs(ref.latitude_deg) >= 90)
      p.fail("referenceLatitude", "must be within (-90, 90) degrees");
    earth_ = LocalTangentPlane(ref);
    const double status = p.num("status", sensor_msgs::NavSatStatus::STATUS_FIX);
    if (status < -1 || status > 2 || status != std::floor(status))
      p.fail("status", "expected a sensor_msgs/NavSatStatus status: -1, 0, 1 or 2");
    const double service = p.num("service", 0);
    if (service < 0 || service > 15 || service != std::floor(service))
      p.fail("service", "expected sensor_msgs/NavSatStatus service bits: 0 to 15");
    fix_.status.status = static_cast<int8_t>(status);
    fix_.status.service = static_cast<uint16_t>(service);
    fix_.header.frame_id = velocity_.header.frame_id = hectorFrame(p, "world");
    position_ = SensorError3(hectorError3(p, ""));
    velocity_error_ = SensorError3(hectorError3(p, "velocity"));
    // The reported covariance: the drift's and the white noise's variances, per axis (upstream's).
    fix_.position_covariance_type = sensor_msgs::NavSatFix::COVARIANCE_TYPE_DIAGONAL_KNOWN;
    for (int a = 0; a < 3; ++a)
    {
      const SensorErrorParams& e = position_[a].params();
      fix_.position_covariance[a * 4] = e.drift * e.drift + e.gaussian_noise * e.gaussian_noise;
    }
    timer_ = HectorTimer(p, 4.0);
    ros::NodeHandle nh(c.ns);
    fix_pub_ = p.advertise<sensor_msgs::NavSatFix>(nh, "topicName", p.str("topicName", "fix"), kEveryStepQueue);
    velocity_pub_ = p.advertise<geometry_msgs::Vector3Stamped>(
        nh, "velocityTopicName", p.str("velocityTopicName", "fix_velocity"), kEveryStepQueue);
    reset();
  }
  void reset() override
  {
    position_.reset(*c_.rng);
    velocity_error_.reset(*c_.rng);
    timer_.reset();
  }
  void update(double t) override
  {
    double dt;
    if (!timer_.due(t, dt))
      return;
    const Pose s = c_.robot->linkState(body_);
    double pos[3], vel[3];
    for (int a = 0; a < 3; ++a)
    {
      vel[a] = velocity_error_[a].measure(s.linear[a], dt, *c_.rng);
      pos[a] = position_[a].measure(s.tf.getOrigin()[a], dt, *c_.rng);
      // A bias in the velocity is a position error that grows: integrated into the next fix.
      position_[a].addDrift(dt * velocity_error_[a].drift());
    }
    const GeoPoint g = earth_.toGeodetic(pos[0], pos[1], pos[2]);
    fix_.header.stamp = velocity_.header.stamp = ros::Time(t);
    fix_.latitude = g.latitude_deg;
    fix_.longitude = g.longitude_deg;
    fix_.altitude = g.altitude;
    const std::array<double, 3> nwu = earth_.toNorthWestUp(vel[0], vel[1], vel[2]);
    velocity_.vector.x = nwu[0];
    velocity_.vector.y = nwu[1];
    velocity_.vector.z = nwu[2];
    fix_pub_.publish(fix_);
    velocity_pub_.publish(velocity_);
  }

  SensorUpdates sensorUpdates() const override { return {timer_.fired(), nullptr}; }

private:
  PluginContext c_;
  std::string body_;
  LocalTangentPlane earth_;
  SensorError3 position_, velocity_error_;
  HectorTimer timer_;
  sensor_msgs::NavSatFix fix_;
  geometry_msgs::Vector3Stamped velocity_;
  ros::Publisher fix_pub_, velocity_pub_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeHectorGps(const PluginContext& c)
{
  return std::make_unique<HectorGps>(c);
}

}  // namespace mybot_gazebo_lite
