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
  Imu(const PluginContext& c, bool sensor_plugin) : c_(c), noise_(0, 1)
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
    gn_ = p.num("gaussianNoise", 0.0);
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
    if (gn_ < 0)
      p.fail("gaussianNoise", "must be >= 0");
    pub_ = ros::NodeHandle(c.ns).advertise<sensor_msgs::Imu>(p.str("topicName", "imu"), kEveryStepQueue);
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
    auto n = [&]() { return gn_ > 0 ? gn_ * noise_(*c_.rng) : 0.0; };
    sensor_msgs::Imu m;
    m.header.stamp = ros::Time(t);
    m.header.frame_id = frame_;
    // One draw after another, in this order (a constructor's arguments are evaluated in any order).
    btVector3 noisy_w = w, noisy_a = a;
    for (int i = 0; i < 3; ++i)
      noisy_w[i] += n();
    for (int i = 0; i < 3; ++i)
      noisy_a[i] += n();
    setImu(m, r.orientation, noisy_w, noisy_a);
    double var = gn_ * gn_;
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
  double gn_;
  ImuModel model_;
  std::normal_distribution<double> noise_;
  ros::Publisher pub_;
};
}  // namespace

void setImu(sensor_msgs::Imu& m, const btQuaternion& q, const btVector3& w, const btVector3& a)
{
  m.orientation.x = q.x();
  m.orientation.y = q.y();
  m.orientation.z = q.z();
  m.orientation.w = q.w();
  m.angular_velocity.x = w.x();
  m.angular_velocity.y = w.y();
  m.angular_velocity.z = w.z();
  m.linear_acceleration.x = a.x();
  m.linear_acceleration.y = a.y();
  m.linear_acceleration.z = a.z();
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
