// diff_drive_controller/DiffDriveController with ros_controllers' parameters and topics:
// cmd_vel in, odom and tf out, wheels through VelocityJointInterface. The odometry and the
// speed limits are this workspace's diff-drive library (mybot_control), the same as the
// real robot's controller.
#include "controllers.h"

#include <mybot_control/odometry.hpp>
#include <mybot_control/ros/params.hpp>
#include <mybot_control/speed_limiter.hpp>

#include <geometry_msgs/Twist.h>
#include <geometry_msgs/TwistStamped.h>
#include <nav_msgs/Odometry.h>

#include <cmath>

namespace mybot_ros_control
{

namespace
{
using mybot_gazebo_lite::JointSpec;
using mybot_gazebo_lite::RobotSpec;
using mybot_gazebo_lite::Shape;

class DiffDriveController : public Controller
{
public:
  explicit DiffDriveController(const ControllerContext& c) : c_(c), hw_(c.hw)
  {
    const std::vector<std::string> left = c.stringList("left_wheel", true), right = c.stringList("right_wheel", true);
    for (const auto& n : left)
      left_.push_back(&c.joint("left_wheel", n, Interface::VELOCITY));
    for (const auto& n : right)
      right_.push_back(&c.joint("right_wheel", n, Interface::VELOCITY));
    auto& claim = claimed_[interfaceName(Interface::VELOCITY)];
    claim.insert(claim.end(), left.begin(), left.end());
    claim.insert(claim.end(), right.begin(), right.end());

    publish_period_ = 1.0 / c.positive("publish_rate", 50.0);
    open_loop_ = c.boolean("open_loop", false);
    const double sep_mult = c.positive("wheel_separation_multiplier", 1.0);
    const double radius_mult = c.positive("wheel_radius_multiplier", 1.0);
    const double left_mult = c.positive("left_wheel_radius_multiplier", radius_mult);
    const double right_mult = c.positive("right_wheel_radius_multiplier", radius_mult);
    const int window = static_cast<int>(c.number("velocity_rolling_window_size", 10));
    if (window < 1)
      c.fail("velocity_rolling_window_size", "must be >= 1");
    timeout_ = c.positive("cmd_vel_timeout", 0.5);
    base_frame_ = c.string("base_frame_id", "base_link");
    odom_frame_ = c.string("odom_frame_id", "odom");
    enable_tf_ = c.boolean("enable_odom_tf", true);
    publish_cmd_ = c.boolean("publish_cmd", false);
    allow_multiple_ = c.boolean("allow_multiple_cmd_vel_publishers", true);

    const RobotSpec& spec = c.plugin->robot->spec();
    double separation = c.number("wheel_separation", 0.0);
    if (!c.nh.hasParam("wheel_separation"))
      separation = separationFromUrdf(spec, left.front(), right.front());
    double radius = c.number("wheel_radius", 0.0);
    if (!c.nh.hasParam("wheel_radius"))
      radius = radiusFromUrdf(spec, left.front());
    if (!(separation > 0))
      c.fail("wheel_separation", "must be positive");
    if (!(radius > 0))
      c.fail("wheel_radius", "must be positive");
    mybot_control::DiffDriveOdometry::Params op;
    op.wheel_separation = sep_mult * separation;
    op.left_radius = left_mult * radius;
    op.right_radius = right_mult * radius;
    op.velocity_window = static_cast<std::size_t>(window);
    odometry_ = mybot_control::DiffDriveOdometry(op);
    kin_ = mybot_control::DiffDriveKinematics(op.wheel_separation, op.left_radius, op.right_radius);

    linear_ = readLimits("linear/x");
    angular_ = readLimits("angular/z");
    pose_cov_ = covariance("pose_covariance_diagonal");
    twist_cov_ = covariance("twist_covariance_diagonal");

    ros::NodeHandle nh = c.nh;
    sub_ = mybot_gazebo_lite::subscribeCommand<geometry_msgs::Twist>(
        *c.plugin, nh, "cmd_vel", [this](const geometry_msgs::Twist::ConstPtr& m) { onCmd(*m); });
    odom_pub_ = nh.advertise<nav_msgs::Odometry>("odom", 100);
    if (publish_cmd_)
      cmd_out_pub_ = nh.advertise<geometry_msgs::TwistStamped>("cmd_vel_out", 100);
    ROS_INFO("%s: wheel separation %.4f m, radius left %.4f m right %.4f m", c.name.c_str(), op.wheel_separation,
             op.left_radius, op.right_radius);
  }

  void starting(double t) override
  {
    for (SimJoint* j : left_)
      hw_->claim(*j, Interface::VELOCITY);
    for (SimJoint* j : right_)
      hw_->claim(*j, Interface::VELOCITY);
    odometry_.reset();
    cmd_ = Cmd{};
    cmd_.stamp = t;
    last0_ = last1_ = mybot_control::Twist2D{};
    next_publish_ = t;
  }
  void stopping(double) override { brake(); }

  void update(double t, double dt) override
  {
    // Odometry from the mean wheel angle of each side (the encoders), or the commands (open_loop).
    if (open_loop_)
    {
      const mybot_control::Pose2D p = mybot_control::poseExp(odometry_.pose(), last0_ * dt);
      odometry_.setPose(p);
      odom_twist_ = last0_;
    }
    else
    {
      odometry_.update(mean(left_), mean(right_), t);
      odom_twist_ = odometry_.twist();
    }
    if (t + 1e-9 >= next_publish_)
    {
      next_publish_ = (next_publish_ + publish_period_ < t) ? t + publish_period_ : next_publish_ + publish_period_;
      publishOdometry(t);
    }
    // The command, braked after cmd_vel_timeout, then limited.
    mybot_control::Twist2D cmd{cmd_.lin, 0.0, cmd_.ang};
    if (t - cmd_.stamp > timeout_)
      cmd = mybot_control::Twist2D{};
    linear_.limit(cmd.vx, last0_.vx, last1_.vx, dt);
    angular_.limit(cmd.wz, last0_.wz, last1_.wz, dt);
    last1_ = last0_;
    last0_ = cmd;
    if (publish_cmd_)
    {
      geometry_msgs::TwistStamped m;
      m.header.stamp = ros::Time(t);
      m.twist.linear.x = cmd.vx;
      m.twist.angular.z = cmd.wz;
      cmd_out_pub_.publish(m);
    }
    const mybot_control::WheelVelocities w = kin_.toWheelAngular(cmd);
    for (SimJoint* j : left_)
      j->command = w.left;
    for (SimJoint* j : right_)
      j->command = w.right;
  }

private:
  struct Cmd
  {
    double lin = 0, ang = 0, stamp = 0;
  };
  static double mean(const std::vector<SimJoint*>& js)
  {
    double s = 0;
    for (const SimJoint* j : js)
      s += j->position;
    return s / js.size();
  }
  void brake()
  {
    for (SimJoint* j : left_)
      j->command = 0;
    for (SimJoint* j : right_)
      j->command = 0;
  }
  void onCmd(const geometry_msgs::Twist& m)
  {
    // As upstream: with several publishers on cmd_vel and allow_multiple_cmd_vel_publishers
    // false, every command is refused rather than obeying whoever spoke last.
    if (!allow_multiple_ && sub_.getNumPublishers() > 1)
    {
      ROS_ERROR_THROTTLE(1.0, "%s: cmd_vel has %u publishers and allow_multiple_cmd_vel_publishers is false; ignored",
                         c_.name.c_str(), sub_.getNumPublishers());
      return;
    }
    if (!std::isfinite(m.linear.x) || !std::isfinite(m.angular.z))
    {
      ROS_WARN_THROTTLE(1.0, "%s: ignoring a non-finite cmd_vel", c_.name.c_str());
      return;
    }
    cmd_.lin = m.linear.x;
    cmd_.ang = m.angular.z;
    cmd_.stamp = c_.plugin->world->time();
  }
  // diff_drive_controller's limit block and covariance lists, read by mybot_control's ParamReader
  // (the real robot's controller reads the same names the same way).
  mybot_control::SpeedLimiter readLimits(const std::string& ns) const
  {
    return mybot_control::SpeedLimiter(mybot_control::loadSpeedLimits(mybot_control::ParamReader(c_.nh), ns + "/"));
  }
  boost::array<double, 36> covariance(const std::string& param) const
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
  // As upstream: the distance between the two wheel joints' origins in their parent frames.
  double separationFromUrdf(const RobotSpec& spec, const std::string& l, const std::string& r) const
  {
    const JointSpec *jl = spec.joint(l), *jr = spec.joint(r);
    return (jl->origin.getOrigin() - jr->origin.getOrigin()).length();
  }
  // As upstream: the radius of the wheel link's collision cylinder or sphere.
  double radiusFromUrdf(const RobotSpec& spec, const std::string& joint) const
  {
    const std::string link = spec.joint(joint)->child;
    const auto* ls = spec.link(link);
    if (ls && !ls->collisions.empty())
    {
      const Shape& s = ls->collisions.front();
      if (s.type == Shape::CYLINDER || s.type == Shape::SPHERE)
        return s.radius;
    }
    c_.fail("wheel_radius", "not set, and link '" + link + "' has no collision cylinder or sphere to take it from");
  }
  void publishOdometry(double t)
  {
    const mybot_control::Pose2D& p = odometry_.pose();
    nav_msgs::Odometry o;
    o.header.stamp = ros::Time(t);
    o.header.frame_id = odom_frame_;
    o.child_frame_id = base_frame_;
    o.pose.pose.position.x = p.x;
    o.pose.pose.position.y = p.y;
    o.pose.pose.orientation.z = std::sin(p.theta / 2);
    o.pose.pose.orientation.w = std::cos(p.theta / 2);
    o.pose.covariance = pose_cov_;
    o.twist.twist.linear.x = odom_twist_.vx;
    o.twist.twist.angular.z = odom_twist_.wz;
    o.twist.covariance = twist_cov_;
    odom_pub_.publish(o);
    if (!enable_tf_)
      return;
    geometry_msgs::TransformStamped tf;
    tf.header = o.header;
    tf.child_frame_id = base_frame_;
    tf.transform.translation.x = p.x;
    tf.transform.translation.y = p.y;
    tf.transform.rotation = o.pose.pose.orientation;
    c_.plugin->tf->sendTransform(tf);
  }

  ControllerContext c_;
  RobotHWSim* hw_;
  std::vector<SimJoint*> left_, right_;
  double publish_period_ = 0.02, next_publish_ = 0, timeout_ = 0.5;
  bool open_loop_ = false, enable_tf_ = true, publish_cmd_ = false, allow_multiple_ = true;
  std::string base_frame_, odom_frame_;
  mybot_control::DiffDriveOdometry odometry_;
  mybot_control::DiffDriveKinematics kin_;
  mybot_control::SpeedLimiter linear_, angular_;
  boost::array<double, 36> pose_cov_{}, twist_cov_{};
  mybot_control::Twist2D last0_, last1_, odom_twist_;
  Cmd cmd_;
  ros::Subscriber sub_;
  ros::Publisher odom_pub_, cmd_out_pub_;
};
}  // namespace

std::unique_ptr<Controller> makeDiffDriveController(const ControllerContext& c)
{
  return std::make_unique<DiffDriveController>(c);
}

}  // namespace mybot_ros_control
