// What ros_controllers' diff_drive_controller, ackermann_steering_controller and
// four_wheel_steering_controller share, with the same parameter names: cmd_vel in (its timeout, the linear/x and
// angular/z limits, the check for several publishers), odom and its tf out at publish_rate with the covariance
// diagonals, and the wheel radius from the URDF. Each drive adds its kinematics and odometry.
#pragma once

#include "controllers.h"

#include <mybot_control/kinematics.hpp>
#include <mybot_control/speed_limiter.hpp>

#include <boost/array.hpp>

namespace mybot_ros_control
{

class TwistDrive : public Controller
{
protected:
  // Reads the shared parameters and subscribes to cmd_vel.
  explicit TwistDrive(const ControllerContext& c);

  // The command for the step from t: the last cmd_vel (zero once older than cmd_vel_timeout)
  // through the speed limits. It is also the open-loop odometry's twist.
  mybot_control::Twist2D command(double t, double dt);
  // A command through the speed limits (linear/x, and angular/z unless `angular` is false); what
  // command() does after the timeout, for a drive with a second command topic.
  mybot_control::Twist2D limited(mybot_control::Twist2D cmd, double dt, bool angular = true);
  // When the last cmd_vel arrived (sim time, s), and cmd_vel_timeout.
  double commandStamp() const { return cmd_.stamp; }
  double commandTimeout() const { return timeout_; }
  // The odometry at t, on odom (and tf) when publish_rate says so (then true).
  bool publish(double t, const mybot_control::Pose2D& pose, const mybot_control::Twist2D& twist);
  // At starting: the last command forgotten, the next publication due now.
  void restart(double t);
  // The last command: what the open-loop odometry (open_loop) integrates.
  const mybot_control::Twist2D& lastCommand() const { return last0_; }
  // As upstream: the radius of `joint`'s child link's collision cylinder or sphere, when the
  // parameter `param` is not set; fails naming the parameter otherwise.
  double radiusFromUrdf(const std::string& param, const std::string& joint) const;
  // As upstream's urdf_geometry_parser: how far apart two joints' origins are in the plane of the
  // robot's root link, their joints at zero.
  double jointDistance(const std::string& a, const std::string& b) const;
  // The rolling window of the odometry's twist (velocity_rolling_window_size).
  std::size_t velocity_window_ = 10;
  bool open_loop_ = false;
  // cmd_vel's linear.y is taken (four_wheel_steering_controller); the others ignore it, as upstream.
  bool holonomic_ = false;
  ControllerContext c_;
  RobotHWSim* hw_;

private:
  struct Cmd
  {
    double lin = 0, lat = 0, ang = 0, stamp = 0;
  };
  void onCmd(double lin, double lat, double ang);
  mybot_control::SpeedLimiter readLimits(const std::string& ns) const;
  boost::array<double, 36> covariance(const std::string& param) const;

  double publish_period_ = 0.02, next_publish_ = 0, timeout_ = 0.5;
  bool enable_tf_ = true, allow_multiple_ = true;
  std::string base_frame_, odom_frame_;
  mybot_control::SpeedLimiter linear_, angular_;
  boost::array<double, 36> pose_cov_{}, twist_cov_{};
  mybot_control::Twist2D last0_, last1_;
  Cmd cmd_;
  ros::Subscriber sub_;
  ros::Publisher odom_pub_;
};

}  // namespace mybot_ros_control
