// libgazebo_ros_laser.so / gpu_laser
#include "builtin.h"

#include "mybot_gazebo_lite/kinematics.h"

#include <sensor_msgs/LaserScan.h>

#include <cmath>

namespace mybot_gazebo_lite
{

namespace
{
class Laser : public SimPlugin
{
public:
  explicit Laser(const PluginContext& c) : c_(c), noise_(0, 1)
  {
    PluginParams p(c, c.spec->xml);
    if (!c.spec->has_sensor)
      p.fail("sensor", "the laser plugin must sit inside a <sensor type=\"ray\">");
    PluginParams s(c, c.spec->sensor);
    link_ = c.spec->reference;
    sensor_pose_ = s.pose("pose");
    rate_ = Rate(s.num("update_rate", 0.0));
    const RayScan scan = RayScan::read(s, 640);  // a 2D laser: its vertical samples are not cast
    samples_ = scan.horizontal;
    amin_ = scan.hmin;
    amax_ = scan.hmax;
    rmin_ = scan.range_min;
    rmax_ = scan.range_max;
    mean_ = s.num("ray/noise/mean", 0.0);
    stddev_ = s.num("ray/noise/stddev", 0.0);
    if (stddev_ < 0)
      s.fail("ray/noise/stddev", "must be >= 0");
    // gazebo_ros_laser's defaults for both.
    frame_ = resolveFrame(c, p.str("frameName", "/world"));
    ros::NodeHandle nh(c.ns);
    pub_ = p.advertise<sensor_msgs::LaserScan>(nh, "topicName", p.str("topicName", "/world"), 1);
    inc_ = samples_ > 1 ? (amax_ - amin_) / (samples_ - 1) : 0.0;
    for (int i = 0; i < samples_; ++i)
    {
      cos_.push_back(std::cos(amin_ + i * inc_));
      sin_.push_back(std::sin(amin_ + i * inc_));
    }
  }
  void update(double t) override
  {
    if (!rate_.due(t))
      return;
    btTransform tf = c_.robot->linkState(link_).tf * sensor_pose_;
    const btVector3 o = tf.getOrigin();
    btScalar yaw, pitch, roll;
    tf.getBasis().getEulerZYX(yaw, pitch, roll);
    const double cy = std::cos(yaw), sy = std::sin(yaw);
    const RayCaster2D& caster = c_.slices->at(o.z());
    ranges_.resize(samples_);
    for (int i = 0; i < samples_; ++i)
    {
      double dx = cy * cos_[i] - sy * sin_[i], dy = sy * cos_[i] + cy * sin_[i];
      ranges_[i] = caster.cast(o.x(), o.y(), dx, dy, rmax_);
    }
    // Robots and dynamic bodies: Bullet ray tests only for beams that can reach them.
    for (const auto& ob : c_.world->dynamicObstacles(c_.robot))
    {
      if (o.z() < ob.zmin || o.z() > ob.zmax)
        continue;
      double ddx = ob.center.x() - o.x(), ddy = ob.center.y() - o.y();
      double dist = std::hypot(ddx, ddy);
      if (dist - ob.radius > rmax_)
        continue;
      double half = dist <= ob.radius ? M_PI : std::asin(ob.radius / dist);
      double bearing = std::atan2(ddy, ddx) - yaw;
      for (int i = 0; i < samples_; ++i)
      {
        double a = std::remainder(amin_ + i * inc_ - bearing, 2 * M_PI);
        if (std::abs(a) > half)
          continue;
        double dx = cy * cos_[i] - sy * sin_[i], dy = sy * cos_[i] + cy * sin_[i];
        double reach = std::min(ranges_[i], rmax_);
        double d = c_.world->rayTestObject(ob.object, o, o + btVector3(dx, dy, 0) * reach);
        if (d >= 0 && d < ranges_[i])
          ranges_[i] = d;
      }
    }
    sensor_msgs::LaserScan m;
    m.header.stamp = ros::Time(t);
    m.header.frame_id = frame_;
    m.angle_min = amin_;
    m.angle_max = amax_;
    m.angle_increment = inc_;
    m.range_min = rmin_;
    m.range_max = rmax_;
    m.ranges.resize(samples_);
    m.intensities.assign(samples_, 0.0f);
    for (int i = 0; i < samples_; ++i)
    {
      double n = stddev_ > 0 ? mean_ + stddev_ * noise_(*c_.rng) : mean_;
      m.ranges[i] = static_cast<float>(laserRange(ranges_[i], rmin_, rmax_, n));
    }
    pub_.publish(m);
  }

  SensorUpdates sensorUpdates() const override { return {&rate_.fired, nullptr}; }

private:
  PluginContext c_;
  std::string link_, frame_;
  btTransform sensor_pose_;
  Rate rate_;
  int samples_;
  double amin_, amax_, inc_, rmin_, rmax_, mean_, stddev_;
  std::vector<double> cos_, sin_, ranges_;
  std::normal_distribution<double> noise_;
  ros::Publisher pub_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeLaser(const PluginContext& c)
{
  return std::make_unique<Laser>(c);
}

}  // namespace mybot_gazebo_lite
