// cmd_vel -> lwheel/rwheel_tangent_vel_target (m/s), through the speed limiter and the
// curvature-preserving wheel desaturation. Host side of the diff-drive chain.
#include <geometry_msgs/Twist.h>
#include <geometry_msgs/TwistStamped.h>
#include <mybot_lockstep/ros/participant.h>
#include <ros/ros.h>
#include <std_msgs/Float32.h>

#include "mybot_control/kinematics.hpp"
#include "diffdrive_nodes.hpp"
#include "mybot_control/ros/params.hpp"
#include "mybot_control/speed_limiter.hpp"
#include "mybot_control/step_scheduler.hpp"

using namespace mybot_control;

namespace
{
class DiffDriveControllerNode
{
public:
  DiffDriveControllerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) : nh_(nh), pnh_(pnh)
  {
    const ParamReader p(pnh_);
    const std::string left = p.string("left_wheel", "left_wheel_hinge");
    const std::string right = p.string("right_wheel", "right_wheel_hinge");
    const WheelGeometry g = loadWheelGeometry(p, left, right, true, false);
    kin_ = DiffDriveKinematics(g.separation, 1.0, 1.0);
    const double rate = p.positive("publish_rate", 50.0);
    cmd_vel_timeout_ = p.nonNegative("cmd_vel_timeout", 0.5);
    max_wheel_velocity_ = p.nonNegative("max_wheel_velocity", 0.0);
    publish_cmd_ = p.boolean("publish_cmd", false);
    limiter_ = TwistLimiter(loadSpeedLimits(p, "linear/x/"), SpeedLimits{}, loadSpeedLimits(p, "angular/z/"));
    scheduler_ = StepScheduler(1.0 / rate);

    left_pub_ = nh_.advertise<std_msgs::Float32>("lwheel_tangent_vel_target", 10);
    right_pub_ = nh_.advertise<std_msgs::Float32>("rwheel_tangent_vel_target", 10);
    if (publish_cmd_)
      cmd_out_pub_ = pnh_.advertise<geometry_msgs::TwistStamped>("cmd_vel_out", 10);
    cmd_sub_ = mybot_lockstep::Participant::instance().subscribe<geometry_msgs::Twist>(
        nh_, "cmd_vel", 10, [this](const geometry_msgs::Twist& m) { onCmd(m); }, ros::TransportHints().tcpNoDelay());
    timer_ = mybot_lockstep::Participant::instance().createTimer(nh_, 1.0 / rate,
                                                                 [this](const ros::TimerEvent& e) { onTimer(e); });
    ROS_INFO("diffdrive_controller: wheel_separation %.4f m, %.0f Hz, cmd_vel_timeout %.2f s", g.separation, rate,
             cmd_vel_timeout_);
  }

private:
  void onCmd(const geometry_msgs::Twist& msg)
  {
    const Twist2D t{msg.linear.x, 0.0, msg.angular.z};
    if (!t.finite())
    {
      ROS_WARN_THROTTLE(1.0, "diffdrive_controller: ignoring a cmd_vel with NaN/inf components");
      return;
    }
    command_ = t;
    last_cmd_ = ros::Time::now();
    have_cmd_ = true;
    double dt;
    if (scheduler_.onEvent(last_cmd_.toSec(), dt))  // step now: no added latency
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
    if (now < last_step_)  // time went backwards (simulation reset): start over from rest
      limiter_.reset();
    last_step_ = now;
    // A command from before a jump back in time (simulation reset) is not fresh: it times out
    // (otherwise now - last_cmd_ < 0 would keep it forever and the robot would drive itself).
    const bool timed_out =
        !have_cmd_ || now < last_cmd_ || (cmd_vel_timeout_ > 0.0 && (now - last_cmd_).toSec() > cmd_vel_timeout_);
    // On timeout the target is zero, still through the limiter: the robot ramps down.
    Twist2D twist = limiter_.limit(timed_out ? Twist2D{} : command_, dt);
    WheelVelocities wheels = kin_.toWheelTangent(twist);
    const double k = desaturate(wheels, max_wheel_velocity_);
    if (k < 1.0)
    {
      twist = twist * k;
      limiter_.overrideLast(twist);
    }
    std_msgs::Float32 l, r;
    l.data = static_cast<float>(wheels.left);
    r.data = static_cast<float>(wheels.right);
    left_pub_.publish(l);
    right_pub_.publish(r);
    if (publish_cmd_)
    {
      geometry_msgs::TwistStamped out;
      out.header.stamp = now;
      out.twist.linear.x = twist.vx;
      out.twist.angular.z = twist.wz;
      cmd_out_pub_.publish(out);
    }
  }

  ros::NodeHandle nh_, pnh_;
  DiffDriveKinematics kin_;
  TwistLimiter limiter_;
  StepScheduler scheduler_{0.02};
  double cmd_vel_timeout_ = 0.5, max_wheel_velocity_ = 0.0;
  bool publish_cmd_ = false, have_cmd_ = false;
  Twist2D command_;
  ros::Time last_cmd_, last_step_;
  ros::Publisher left_pub_, right_pub_, cmd_out_pub_;
  ros::Subscriber cmd_sub_;
  mybot_lockstep::Timer timer_;
};

}  // namespace

namespace mybot_control_nodes
{
std::shared_ptr<void> makeDiffDriveController(const ros::NodeHandle& nh, const ros::NodeHandle& pnh)
{
  return std::make_shared<DiffDriveControllerNode>(nh, pnh);
}
}  // namespace mybot_control_nodes

#ifndef MYBOT_CONTROL_NODE_LIBRARY
int main(int argc, char** argv)
{
  return runNode(argc, argv, "diffdrive_controller",
                 []
                 {
                   const auto node =
                       mybot_control_nodes::makeDiffDriveController(ros::NodeHandle(), ros::NodeHandle("~"));
                   ros::spin();
                 });
}
#endif
