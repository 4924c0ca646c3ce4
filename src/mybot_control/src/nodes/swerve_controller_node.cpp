// cmd_vel (vx, vy, wz) -> per-module requested pivot angle and wheel speed
// (swerve_<m>/rqst_pivot_angle, swerve_<m>/rqst_wheel_speed), through the twist limiter,
// inverse kinematics, desaturation and module-state optimisation
// against the measured pivot angles (swerve_<m>/pivot_angle). The wheels wait (speed 0)
// while any module is more than angle_error_threshold from its requested angle.
#include <geometry_msgs/Twist.h>
#include <geometry_msgs/TwistStamped.h>
#include <mybot_lockstep/ros/participant.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <std_msgs/Float64.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "mybot_control/ros/params.hpp"
#include "mybot_control/swerve_limiter.hpp"
#include "mybot_control/step_scheduler.hpp"
#include "mybot_control/swerve_kinematics.hpp"
#include "mybot_control/ros/swerve.hpp"
#include "swerve_nodes.hpp"

using namespace mybot_control;

namespace mybot_control_nodes
{
class SwerveControllerNode
{
public:
  SwerveControllerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) : nh_(nh), pnh_(pnh)
  {
    const ParamReader p(pnh_);
    geometry_ = loadSwerveGeometry(p, true, false);
    kin_ = std::make_unique<SwerveKinematics>(geometry_.offsets);
    const double rate = p.positive("publish_rate", 50.0);
    cmd_vel_timeout_ = p.nonNegative("cmd_vel_timeout", 0.5);
    max_wheel_speed_ = p.nonNegative("max_wheel_speed", 0.0);
    angle_error_threshold_ = p.positive("angle_error_threshold", 0.1);
    discretize_ = p.boolean("discretize", true);
    field_relative_ = p.boolean("field_relative", false);
    publish_cmd_ = p.boolean("publish_cmd", false);
    if (p.has("center_of_rotation"))
    {
      const auto c = p.numbers("center_of_rotation", 2);
      center_ = {c[0], c[1]};
    }
    limiter_ = SwerveTwistLimiter(loadSpeedLimits(p, "linear/x/"), loadSpeedLimits(p, "linear/y/"),
                                  loadSpeedLimits(p, "angular/z/"));
    period_ = 1.0 / rate;
    scheduler_ = StepScheduler(period_);

    const std::size_t n = geometry_.modules.size();
    measured_.assign(n, 0.0);
    have_measured_.assign(n, false);
    angle_pubs_.resize(n);
    speed_pubs_.resize(n);
    for (std::size_t i = 0; i < n; ++i)
    {
      const std::string ns = "swerve_" + geometry_.modules[i] + "/";
      angle_pubs_[i] = nh_.advertise<std_msgs::Float64>(ns + "rqst_pivot_angle", 10);
      speed_pubs_[i] = nh_.advertise<std_msgs::Float64>(ns + "rqst_wheel_speed", 10);
      angle_subs_.push_back(mybot_lockstep::Participant::instance().subscribe<std_msgs::Float64>(
          nh_, ns + "pivot_angle", 10,
          [this, i](const std_msgs::Float64::ConstPtr& m)
          {
            if (!std::isfinite(m->data))
              return;
            measured_[i] = m->data;
            have_measured_[i] = true;
            if (!headings_initialised_ &&
                std::all_of(have_measured_.begin(), have_measured_.end(), [](bool b) { return b; }))
            {
              // A zero command holds the modules where they are, not at 0 rad.
              kin_->resetHeadings(measured_);
              headings_initialised_ = true;
            }
          },
          ros::TransportHints().tcpNoDelay()));
    }
    if (field_relative_)
      imu_sub_ = mybot_lockstep::Participant::instance().subscribe<sensor_msgs::Imu>(
          nh_, "imu", 10, [this](const sensor_msgs::Imu& m) { onImu(m); });
    if (publish_cmd_)
      cmd_out_pub_ = pnh_.advertise<geometry_msgs::TwistStamped>("cmd_vel_out", 10);
    cmd_sub_ = mybot_lockstep::Participant::instance().subscribe<geometry_msgs::Twist>(
        nh_, "cmd_vel", 10, [this](const geometry_msgs::Twist& m) { onCmd(m); }, ros::TransportHints().tcpNoDelay());
    timer_ = mybot_lockstep::Participant::instance().createTimer(nh_, period_,
                                                                 [this](const ros::TimerEvent& e) { onTimer(e); });
    ROS_INFO("swerve_controller: %zu modules, %.0f Hz, cmd_vel_timeout %.2f s, angle_error_threshold %.3f rad%s", n,
             rate, cmd_vel_timeout_, angle_error_threshold_, field_relative_ ? ", field-relative" : "");
  }

private:
  void onImu(const sensor_msgs::Imu& msg)
  {
    const double yaw = yawOf(msg.orientation);
    if (std::isfinite(yaw))
    {
      yaw_ = yaw;
      have_yaw_ = true;
    }
  }

  void onCmd(const geometry_msgs::Twist& msg)
  {
    const Twist2D t{msg.linear.x, msg.linear.y, msg.angular.z};
    if (!t.finite())
    {
      ROS_WARN_THROTTLE(1.0, "swerve_controller: ignoring a cmd_vel with NaN/inf components");
      return;
    }
    command_ = t;
    last_cmd_ = ros::Time::now();
    have_cmd_ = true;
    double dt;
    if (scheduler_.onEvent(last_cmd_.toSec(), dt))
      step(last_cmd_, dt);
  }

  void onTimer(const ros::TimerEvent&)
  {
    const ros::Time now = ros::Time::now();
    double dt;
    if (scheduler_.onTick(now.toSec(), dt))
      step(now, dt);
  }

  void step(const ros::Time& now, double dt)
  {
    if (now < last_step_)  // simulation reset: start over from rest
      limiter_.reset();
    last_step_ = now;
    // A command from before a jump back in time (simulation reset) is not fresh: it times out
    // (otherwise now - last_cmd_ < 0 would keep it forever and the robot would drive itself).
    const bool timed_out =
        !have_cmd_ || now < last_cmd_ || (cmd_vel_timeout_ > 0.0 && (now - last_cmd_).toSec() > cmd_vel_timeout_);
    Twist2D twist = limiter_.limit(timed_out ? Twist2D{} : command_, dt);
    if (field_relative_ && !have_yaw_)
    {
      ROS_WARN_THROTTLE(2.0, "swerve_controller: field_relative but no imu yet; holding still");
      twist = Twist2D{};
      limiter_.reset();
    }
    // A body-frame cmd_vel is already the constant twist held over the period (an exact arc);
    // a field-relative one is not (the robot turns during the period), hence discretize.
    Twist2D body = twist;
    if (field_relative_)
    {
      body = fromFieldRelative(twist, yaw_);
      if (discretize_)
        body = discretize(body, period_);
    }
    auto states = kin_->toModuleStates(body, center_);
    const double k = desaturateModuleSpeeds(states, max_wheel_speed_);
    if (k < 1.0)
      limiter_.overrideLast(twist * k);

    bool wait = false;
    for (std::size_t i = 0; i < states.size(); ++i)
    {
      if (!have_measured_[i])
      {
        wait = true;
        continue;
      }
      states[i] = optimizeModuleState(states[i], measured_[i]);
      wait = wait || std::abs(wrapAngle(states[i].angle - measured_[i])) > angle_error_threshold_;
    }
    if (wait)
    {
      for (auto& s : states)
        s.speed = 0.0;
      // Restart from rest once the modules point the right way, through the acceleration limits.
      limiter_.overrideLast(Twist2D{});
      if (!timed_out &&
          std::count(have_measured_.begin(), have_measured_.end(), true) < static_cast<long>(states.size()))
        ROS_WARN_THROTTLE(2.0, "swerve_controller: waiting for swerve_<m>/pivot_angle of every module");
    }

    std_msgs::Float64 angle, speed;
    for (std::size_t i = 0; i < states.size(); ++i)
    {
      angle.data = states[i].angle;
      speed.data = states[i].speed;
      publishShared(angle_pubs_[i], angle);
      publishShared(speed_pubs_[i], speed);
    }
    if (publish_cmd_)
    {
      geometry_msgs::TwistStamped out;
      out.header.stamp = now;
      const Twist2D sent = wait ? Twist2D{} : twist * k;
      out.twist.linear.x = sent.vx;
      out.twist.linear.y = sent.vy;
      out.twist.angular.z = sent.wz;
      cmd_out_pub_.publish(out);
    }
  }

  ros::NodeHandle nh_, pnh_;
  SwerveGeometry geometry_;
  std::unique_ptr<SwerveKinematics> kin_;
  SwerveTwistLimiter limiter_;
  StepScheduler scheduler_{0.02};
  double period_ = 0.02, cmd_vel_timeout_ = 0.5, max_wheel_speed_ = 0.0, angle_error_threshold_ = 0.1;
  bool discretize_ = true, field_relative_ = false, publish_cmd_ = false, have_cmd_ = false, have_yaw_ = false,
       headings_initialised_ = false;
  double yaw_ = 0.0;
  Vec2 center_;
  Twist2D command_;
  std::vector<double> measured_;
  std::vector<bool> have_measured_;
  ros::Time last_cmd_, last_step_;
  std::vector<ros::Publisher> angle_pubs_, speed_pubs_;
  std::vector<ros::Subscriber> angle_subs_;
  ros::Publisher cmd_out_pub_;
  ros::Subscriber cmd_sub_, imu_sub_;
  mybot_lockstep::Timer timer_;
};

std::shared_ptr<void> makeSwerveController(const ros::NodeHandle& nh, const ros::NodeHandle& pnh)
{
  return std::make_shared<SwerveControllerNode>(nh, pnh);
}
}  // namespace mybot_control_nodes

#ifndef MYBOT_CONTROL_NODE_LIBRARY
int main(int argc, char** argv)
{
  return runNode(argc, argv, "swerve_controller",
                 []
                 {
                   const auto node = mybot_control_nodes::makeSwerveController(ros::NodeHandle(), ros::NodeHandle("~"));
                   ros::spin();
                 });
}
#endif
