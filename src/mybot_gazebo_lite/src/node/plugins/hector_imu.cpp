// libhector_gazebo_ros_imu.so: an IMU with hector's error models. The accelerometer and the gyro
// each have a bias that wanders (<accelDrift>, <rateDrift>, ...), white noise and a scale error;
// the orientation is that of an attitude filter fed by them (a pseudo AHRS): the accelerometer's
// bias tilts it (a bias b along x reads as a pitch of b / g) and a wandering heading bias
// (<yawDrift>, <yawOffset>) turns it. Publishes sensor_msgs/Imu on `imu`, the current biases on
// `imu/bias`, and offers `imu/calibrate` (std_srvs/Empty: the gyro's wandering bias to zero).
#include "builtin.h"

#include "mybot_gazebo_lite/imu_model.h"
#include "mybot_gazebo_lite/parsing.h"

#include <sensor_msgs/Imu.h>
#include <std_srvs/Empty.h>

namespace mybot_gazebo_lite
{

namespace
{
class HectorImu : public SimPlugin
{
public:
  explicit HectorImu(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    body_ = hectorBody(c, p);
    const std::string topic = p.str("topicName", "imu");
    std::array<SensorErrorParams, 3> accel = hectorError3(p, "accel"), rate = hectorError3(p, "rate");
    // gazebo_ros_imu's <gaussianNoise>, read by hector too: the white noise of both, unless 0.
    const double gn = p.num("gaussianNoise", 0.0);
    if (gn < 0)
      p.fail("gaussianNoise", "must be >= 0 (a standard deviation)");
    for (int a = 0; a < 3 && gn != 0; ++a)
      accel[a].gaussian_noise = rate[a].gaussian_noise = gn;
    accel_ = SensorError3(accel);
    rate_error_ = SensorError3(rate);
    yaw_ = SensorError(hectorError(p, "yaw"));
    // Offsets of the reported frame: zero ones change nothing; others are not simulated, and said so.
    for (const char* tag : {"xyzOffset", "rpyOffset"})
      if (p.has(tag))
      {
        btVector3 v;
        try
        {
          v = parseVec3(p.str(tag, ""), "");
        }
        catch (const LoadError&)
        {
          p.fail(tag, "expected 3 numbers, got '" + p.str(tag, "") + "'");
        }
        if (v.length() > 0)
          ROS_WARN("%s: plugin '%s': <%s> %s is not simulated by gazebo_lite; ignored", c.robot->spec().source.c_str(),
                   c.spec->name.c_str(), tag, p.str(tag, "").c_str());
      }
    msg_.header.frame_id = hectorFrame(p, body_);
    for (int a = 0; a < 3; ++a)
    {
      msg_.angular_velocity_covariance[a * 4] = rate[a].gaussian_noise * rate[a].gaussian_noise;
      msg_.linear_acceleration_covariance[a * 4] = accel[a].gaussian_noise * accel[a].gaussian_noise;
    }
    // Roll and pitch come from the accelerometer: its noise over g, in radians.
    const double g = c.world->worldSpec().gravity.length();
    msg_.orientation_covariance[0] = g > 0 ? std::pow(accel[0].gaussian_noise / g, 2) : -1;
    msg_.orientation_covariance[4] = g > 0 ? std::pow(accel[1].gaussian_noise / g, 2) : -1;
    msg_.orientation_covariance[8] = std::pow(yaw_.params().gaussian_noise, 2);
    timer_ = HectorTimer(p, 0.0);
    ros::NodeHandle nh(c.ns);
    // An empty <topicName> publishes nothing (upstream's); an empty <biasTopicName> no biases.
    if (!topic.empty())
      pub_ = p.advertise<sensor_msgs::Imu>(nh, "topicName", topic, kEveryStepQueue);
    const std::string bias_topic = p.str("biasTopicName", topic.empty() ? "" : topic + "/bias");
    if (!bias_topic.empty())
      bias_pub_ = p.advertise<sensor_msgs::Imu>(nh, "biasTopicName", bias_topic, kEveryStepQueue);
    const std::string service = p.str("serviceName", topic + "/calibrate");
    if (!service.empty())
    {
      calibrate_ = nh.advertiseService(service, &HectorImu::calibrate, this);
      if (!calibrate_)  // roscpp said only "already advertised", naming no plugin
        p.fail("serviceName", "service '" + nh.resolveName(service) + "' is already offered by another plugin");
    }
    reset();
  }
  void reset() override
  {
    model_.reset();
    accel_.reset(*c_.rng);
    rate_error_.reset(*c_.rng);
    yaw_.reset(*c_.rng);
    timer_.reset();
  }
  void update(double t) override
  {
    const Pose s = c_.robot->linkState(body_);
    model_.step(s, c_.world->stepSize());
    double dt;
    if (!timer_.due(t, dt))
      return;
    const btVector3& gravity = c_.world->worldSpec().gravity;
    const ImuModel::Reading r = model_.read(s, gravity);
    btVector3 accel, rate, accel_bias, rate_bias;
    for (int a = 0; a < 3; ++a)
    {
      accel[a] = accel_[a].measure(r.linear_acceleration[a], dt, *c_.rng);
      rate[a] = rate_error_[a].measure(r.angular_velocity[a], dt, *c_.rng);
      accel_bias[a] = accel_[a].bias();
      rate_bias[a] = rate_error_[a].bias();
    }
    yaw_.measure(0.0, dt, *c_.rng);
    // The pseudo AHRS: the accelerometer's bias, turned into the world, tilts the attitude (a
    // filter levelling on it takes a bias along y for a roll of b / g, along x for a pitch of -b / g);
    // the heading bias turns it about the vertical.
    const btVector3 drift = s.tf.getBasis() * accel_bias;
    const double g = gravity.length();
    btQuaternion tilt(g > 0 ? 0.5 * drift.y() / g : 0.0, g > 0 ? -0.5 * drift.x() / g : 0.0, 0.0, 1.0);
    tilt.normalize();
    btQuaternion error = btQuaternion(btVector3(0, 0, 1), yaw_.bias()) * tilt;
    error.normalize();
    const btQuaternion q = error * r.orientation;

    msg_.header.stamp = ros::Time(t);
    setImu(msg_, q, rate, accel);
    if (pub_)
      pub_.publish(msg_);
    if (bias_pub_)
    {
      sensor_msgs::Imu b;
      b.header = msg_.header;
      setImu(b, error, rate_bias, accel_bias);
      bias_pub_.publish(b);
    }
  }

  SensorUpdates sensorUpdates() const override { return {timer_.fired(), nullptr}; }

private:
  // As upstream: the gyro's wandering bias to zero (its constant <rateOffset> stays).
  bool calibrate(std_srvs::Empty::Request&, std_srvs::Empty::Response&)
  {
    for (int a = 0; a < 3; ++a)
      rate_error_[a].setDrift(0.0);
    return true;
  }

  PluginContext c_;
  std::string body_;
  SensorError3 accel_, rate_error_;
  SensorError yaw_;
  ImuModel model_;
  HectorTimer timer_;
  sensor_msgs::Imu msg_;
  ros::Publisher pub_, bias_pub_;
  ros::ServiceServer calibrate_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeHectorImu(const PluginContext& c)
{
  return std::make_unique<HectorImu>(c);
}

}  // namespace mybot_gazebo_lite
