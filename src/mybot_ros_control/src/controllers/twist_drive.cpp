#include "twist_drive.h"

#include <mybot_control/ros/params.hpp>

#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>

#include <cmath>

namespace mybot_ros_control
{

TwistDrive::TwistDrive(const ControllerContext& c) : c_(c), hw_(c.hw)
{
  publish_period_ = 1.0 / c.positive("publish_rate", 50.0);
  open_loop_ = c.boolean("open_loop", false);
  const int window = static_cast<int>(c.number("velocity_rolling_window_size", 10));
  if (window < 1)
    c.fail("velocity_rolling_window_size", "must be >= 1");
  velocity_window_ = static_cast<std::size_t>(window);
  timeout_ = c.positive("cmd_vel_timeout", 0.5);
  base_frame_ = c.string("base_frame_id", "base_link");
  odom_frame_ = c.string("odom_frame_id", "odom");
  enable_tf_ = c.boolean("enable_odom_tf", true);
  allow_multiple_ = c.boolean("allow_multiple_cmd_vel_publishers", true);
  linear_ = readLimits("linear/x");
  angular_ = readLimits("angular/z");
  pose_cov_ = covariance("pose_covariance_diagonal");
  twist_cov_ = covariance("twist_covariance_diagonal");

  ros::NodeHandle nh = c.nh;
  sub_ = mybot_gazebo_lite::subscribeCommand<geometry_msgs::Twist>(*c.plugin, nh, "cmd_vel",
                                                                   [this](const geometry_msgs::Twist::ConstPtr& m)
                                                                   { onCmd(m->linear.x, m->linear.y, m->angular.z); });
  odom_pub_ = nh.advertise<nav_msgs::Odometry>("odom", 100);
}

void TwistDrive::restart(double t)
{
  cmd_ = Cmd{};
  cmd_.stamp = t;
  last0_ = last1_ = mybot_control::Twist2D{};
  next_publish_ = t;
}

mybot_control::Twist2D TwistDrive::command(double t, double dt)
{
  mybot_control::Twist2D cmd{cmd_.lin, holonomic_ ? cmd_.lat : 0.0, cmd_.ang};
  if (t - cmd_.stamp > timeout_)
    cmd = mybot_control::Twist2D{};
  return limited(cmd, dt);
}

mybot_control::Twist2D TwistDrive::limited(mybot_control::Twist2D cmd, double dt, bool angular)
{
  linear_.limit(cmd.vx, last0_.vx, last1_.vx, dt);
  if (angular)
    angular_.limit(cmd.wz, last0_.wz, last1_.wz, dt);
  last1_ = last0_;
  last0_ = cmd;
  return cmd;
}

void TwistDrive::onCmd(double lin, double lat, double ang)
{
  // As upstream: with several publishers on cmd_vel and allow_multiple_cmd_vel_publishers
  // false, every command is refused rather than obeying whoever spoke last.
  if (!allow_multiple_ && sub_.getNumPublishers() > 1)
  {
    ROS_ERROR_THROTTLE(1.0, "%s: cmd_vel has %u publishers and allow_multiple_cmd_vel_publishers is false; ignored",
                       c_.name.c_str(), sub_.getNumPublishers());
    return;
  }
  if (!std::isfinite(lin) || !std::isfinite(ang) || (holonomic_ && !std::isfinite(lat)))
  {
    ROS_WARN_THROTTLE(1.0, "%s: ignoring a non-finite cmd_vel", c_.name.c_str());
    return;
  }
  cmd_.lin = lin;
  cmd_.lat = lat;
  cmd_.ang = ang;
  cmd_.stamp = c_.plugin->world->time();
}

// The limit block and covariance lists, read by mybot_control's ParamReader (the real robot's
// controller reads the same names the same way).
mybot_control::SpeedLimiter TwistDrive::readLimits(const std::string& ns) const
{
  return mybot_control::SpeedLimiter(mybot_control::loadSpeedLimits(mybot_control::ParamReader(c_.nh), ns + "/"));
}

boost::array<double, 36> TwistDrive::covariance(const std::string& param) const
{
  boost::array<double, 36> cov{};
  const mybot_control::ParamReader p(c_.nh);
  if (!p.has(param))
    return cov;
  const std::vector<double> diag = p.numbers(param, 6);
  for (int k = 0; k < 6; ++k)
    cov[k * 7] = diag[k];
  return cov;
}

double TwistDrive::radiusFromUrdf(const std::string& param, const std::string& joint) const
{
  const mybot_gazebo_lite::RobotSpec& spec = c_.plugin->robot->spec();
  const std::string link = spec.joint(joint)->child;
  const auto* ls = spec.link(link);
  if (ls && !ls->collisions.empty())
  {
    const mybot_gazebo_lite::Shape& s = ls->collisions.front();
    if (s.type == mybot_gazebo_lite::Shape::CYLINDER || s.type == mybot_gazebo_lite::Shape::SPHERE)
      return s.radius;
  }
  c_.fail(param, "not set, and link '" + link + "' has no collision cylinder or sphere to take it from");
}

double TwistDrive::jointDistance(const std::string& a, const std::string& b) const
{
  const mybot_gazebo_lite::RobotSpec& spec = c_.plugin->robot->spec();
  auto inRoot = [&spec](const std::string& name)
  {
    btTransform t = btTransform::getIdentity();
    for (const mybot_gazebo_lite::JointSpec* j = spec.joint(name); j;)
    {
      t = j->origin * t;
      const std::string parent = j->parent;
      j = nullptr;
      for (const auto& up : spec.joints)
        if (up.child == parent)
          j = &up;
    }
    return t.getOrigin();
  };
  const btVector3 d = inRoot(a) - inRoot(b);
  return std::hypot(d.x(), d.y());
}

bool TwistDrive::publish(double t, const mybot_control::Pose2D& p, const mybot_control::Twist2D& twist)
{
  if (t + 1e-9 < next_publish_)
    return false;
  next_publish_ = (next_publish_ + publish_period_ < t) ? t + publish_period_ : next_publish_ + publish_period_;
  nav_msgs::Odometry o;
  o.header.stamp = ros::Time(t);
  o.header.frame_id = odom_frame_;
  o.child_frame_id = base_frame_;
  o.pose.pose.position.x = p.x;
  o.pose.pose.position.y = p.y;
  o.pose.pose.orientation.z = std::sin(p.theta / 2);
  o.pose.pose.orientation.w = std::cos(p.theta / 2);
  o.pose.covariance = pose_cov_;
  o.twist.twist.linear.x = twist.vx;
  o.twist.twist.linear.y = twist.vy;
  o.twist.twist.angular.z = twist.wz;
  o.twist.covariance = twist_cov_;
  odom_pub_.publish(o);
  if (!enable_tf_)
    return true;
  geometry_msgs::TransformStamped tf;
  tf.header = o.header;
  tf.child_frame_id = base_frame_;
  tf.transform.translation.x = p.x;
  tf.transform.translation.y = p.y;
  tf.transform.rotation = o.pose.pose.orientation;
  c_.plugin->tf->sendTransform(tf);
  return true;
}

}  // namespace mybot_ros_control
