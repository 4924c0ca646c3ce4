// IMU (sensor and model plugin)
#include "builtin.h"

#include "mybot_gazebo_lite/imu_model.h"
#include "mybot_gazebo_lite/parsing.h"

#include <sensor_msgs/Imu.h>

#include <cmath>

namespace mybot_gazebo_lite
{

namespace
{
class Imu : public SimPlugin
{
public:
  Imu(const PluginContext& c, bool sensor_plugin) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    if (sensor_plugin)
    {
      if (!c.spec->has_sensor)
        p.fail("sensor", "libgazebo_ros_imu_sensor.so must sit inside a <sensor type=\"imu\">");
      PluginParams s(c, c.spec->sensor);
      body_ = p.link("bodyName", c.spec->reference);
      sensor_pose_ = s.pose("pose");
      rate_ = Rate(p.num("updateRateHZ", s.num("update_rate", 1.0)));
    }
    else
    {
      body_ = p.link("bodyName");
      rate_ = Rate(p.num("updateRate", 0.0));
    }
    frame_ = resolveFrame(c, p.str("frameName", body_));
    noise_ = std::normal_distribution<double>(0.0, p.nonNegative("gaussianNoise", 0.0));
    // Offsets of the reported frame: zero ones (as most URDFs write them) change nothing; others
    // are not simulated, and said so.
    for (const char* tag : {"xyzOffset", "rpyOffset"})
      if (p.has(tag))
      {
        btVector3 v;
        try
        {
          v = parseVec3(p.str(tag, ""), tag);
        }
        catch (const LoadError& e)
        {
          p.fail(tag, e.what());
        }
        if (v.length() > 0)
          ROS_WARN("%s: plugin '%s' on link '%s': <%s> %s is not simulated by gazebo_lite; ignored",
                   c.robot->spec().source.c_str(), c.spec->name.c_str(), body_.c_str(), tag, p.str(tag, "").c_str());
      }
    ros::NodeHandle nh(c.ns);
    pub_ = p.advertise<sensor_msgs::Imu>(nh, "topicName", p.str("topicName", "imu"), kEveryStepQueue);
    model_ = ImuModel(sensor_pose_);
  }
  void reset() override { model_.reset(); }
  void update(double t) override
  {
    const Pose s = c_.robot->linkState(body_);
    model_.step(s, c_.world->stepSize());
    if (!rate_.due(t))
      return;
    const ImuModel::Reading r = model_.read(s, c_.world->worldSpec().gravity);
    const btVector3& w = r.angular_velocity;
    const btVector3& a = r.linear_acceleration;
    sensor_msgs::Imu m;
    m.header.stamp = ros::Time(t);
    m.header.frame_id = frame_;
    const btVector3 noisy_w = addNoise(w, noise_, *c_.rng);  // first the rate, then the acceleration
    setImu(m, r.orientation, noisy_w, addNoise(a, noise_, *c_.rng));
    const double var = noise_.stddev() * noise_.stddev();
    for (int i = 0; i < 3; ++i)
      m.orientation_covariance[i * 4] = m.angular_velocity_covariance[i * 4] = m.linear_acceleration_covariance[i * 4] =
          var;
    pub_.publish(m);
  }

  SensorUpdates sensorUpdates() const override { return {&rate_.fired, nullptr}; }

private:
  PluginContext c_;
  std::string body_, frame_;
  btTransform sensor_pose_ = btTransform::getIdentity();
  Rate rate_;
  ImuModel model_;
  std::normal_distribution<double> noise_;
  ros::Publisher pub_;
};
}  // namespace

void setImu(sensor_msgs::Imu& m, const btQuaternion& q, const btVector3& w, const btVector3& a)
{
  m.orientation = toMsg(q);
  m.angular_velocity = toMsg(w);
  m.linear_acceleration = toMsg(a);
}

std::unique_ptr<SimPlugin> makeImuSensor(const PluginContext& c)
{
  return std::make_unique<Imu>(c, true);
}
std::unique_ptr<SimPlugin> makeImu(const PluginContext& c)
{
  return std::make_unique<Imu>(c, false);
}

}  // namespace mybot_gazebo_lite
