// Robot side of the diff-drive chain: lwheel/rwheel_tangent_vel_target (m/s) ->
// *_angular_vel_target (rad/s) -> PID against the encoder speed (pid_on) -> *_angular_vel_control
// -> *_angular_vel_motor, and in the simulator the Float64 joint velocity commands.
// Publishes *_angular_vel_enc and *_tangent_vel_enc from stamped joint_states positions.
#include <mybot_lockstep/ros/participant.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Float32.h>
#include <std_msgs/Float64.h>

#include <array>
#include <deque>

#include "mybot_control/odometry.hpp"
#include "mybot_control/pid.hpp"
#include "diffdrive_nodes.hpp"
#include "mybot_control/ros/params.hpp"
#include "mybot_control/step_scheduler.hpp"

using namespace mybot_control;

namespace
{
struct Wheel
{
  std::string joint;
  std::string prefix;  // "lwheel" / "rwheel"
  double radius = 0.1;
  double target_tangent = 0.0;
  ros::Time target_stamp;
  bool have_target = false;
  WheelEncoder encoder;
  ros::Time encoder_stamp;
  int joint_index = -1;  // cached index into joint_states.name
  Pid pid;
  StepScheduler scheduler{0.02};
  std::deque<std::pair<double, double>> target_history;  // (ROS time, rad/s) commanded
  double encoder_time = 0.0;                             // stamp of the last encoder reading
  ros::Publisher target_pub, control_pub, motor_pub, enc_pub, tangent_enc_pub, joint_cmd_pub;
  ros::Subscriber target_sub;
};

void publish(ros::Publisher& pub, double value)
{
  std_msgs::Float32 m;
  m.data = static_cast<float>(value);
  pub.publish(m);
}

class WheelControllerNode
{
public:
  WheelControllerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) : nh_(nh), pnh_(pnh)
  {
    const ParamReader p(pnh_);
    wheels_[0].joint = p.string("left_wheel", "left_wheel_hinge");
    wheels_[1].joint = p.string("right_wheel", "right_wheel_hinge");
    wheels_[0].prefix = "lwheel";
    wheels_[1].prefix = "rwheel";
    const WheelGeometry g = loadWheelGeometry(p, wheels_[0].joint, wheels_[1].joint, false, true);
    wheels_[0].radius = g.left_radius;
    wheels_[1].radius = g.right_radius;
    const double rate = p.positive("rate", 50.0);
    period_ = 1.0 / rate;
    timeout_ = p.positive("timeout", 0.5);
    encoder_timeout_ = p.positive("encoder_timeout", 0.5);
    pid_on_ = p.boolean("pid_on", true);
    response_time_ = p.nonNegative("response_time", 0.0);
    const std::string interface = p.string("command_interface", "motor");
    if (interface != "motor" && interface != "joints")
      p.fail("command_interface",
             "must be 'motor' (GoPiGo driver) or 'joints' (simulator joint commands), got '" + interface + "'");
    joint_commands_ = interface == "joints";
    const auto window = static_cast<std::size_t>(p.positive("velocity_window", 2));
    const double encoder_period = p.nonNegative("encoder_period", 0.0);
    PidConfig defaults;
    defaults.p = 0.5;
    defaults.i = 5.0;
    defaults.f = 1.0;  // velocity-commanded motors: feed the target forward, PID trims
    const PidConfig pid = loadPid(p, "pid", false, defaults);

    for (std::size_t k = 0; k < 2; ++k)
    {
      Wheel& w = wheels_[k];
      w.encoder = WheelEncoder(window, encoder_period);
      w.pid = Pid(pid);
      w.scheduler = StepScheduler(period_);
      w.target_pub = nh_.advertise<std_msgs::Float32>(w.prefix + "_angular_vel_target", 10);
      w.control_pub = nh_.advertise<std_msgs::Float32>(w.prefix + "_angular_vel_control", 10);
      w.motor_pub = nh_.advertise<std_msgs::Float32>(w.prefix + "_angular_vel_motor", 10);
      w.enc_pub = nh_.advertise<std_msgs::Float32>(w.prefix + "_angular_vel_enc", 10);
      w.tangent_enc_pub = nh_.advertise<std_msgs::Float32>(w.prefix + "_tangent_vel_enc", 10);
      if (joint_commands_)
        w.joint_cmd_pub = nh_.advertise<std_msgs::Float64>(
            p.string(k == 0 ? "left_command_topic" : "right_command_topic", w.joint + "/command"), 10);
      w.target_sub = mybot_lockstep::Participant::instance().subscribe<std_msgs::Float32>(
          nh_, w.prefix + "_tangent_vel_target", 10,
          [this, k](const std_msgs::Float32::ConstPtr& m) { onTarget(k, m->data); },
          ros::TransportHints().tcpNoDelay());
    }
    joint_sub_ = mybot_lockstep::Participant::instance().subscribe<sensor_msgs::JointState>(
        nh_, "joint_states", 20, [this](const sensor_msgs::JointState& m) { onJointStates(m); },
        ros::TransportHints().tcpNoDelay());
    timer_ = mybot_lockstep::Participant::instance().createTimer(nh_, period_,
                                                                 [this](const ros::TimerEvent& e) { onTimer(e); });
    ROS_INFO("wheel_controller: radius %.4f/%.4f m, %.0f Hz, pid_on %s, output %s", wheels_[0].radius,
             wheels_[1].radius, rate, pid_on_ ? "true" : "false", interface.c_str());
  }

private:
  void onTarget(std::size_t k, float value)
  {
    if (!std::isfinite(value))
    {
      ROS_WARN_THROTTLE(1.0, "wheel_controller: ignoring a NaN/inf %s_tangent_vel_target", wheels_[k].prefix.c_str());
      return;
    }
    Wheel& w = wheels_[k];
    w.target_tangent = value;
    w.target_stamp = ros::Time::now();
    w.have_target = true;
    double dt;
    if (w.scheduler.onEvent(w.target_stamp.toSec(), dt))  // step now: no added latency
      step(w, w.target_stamp, dt);
  }

  void onJointStates(const sensor_msgs::JointState& msg)
  {
    const ros::Time stamp = msg.header.stamp.isZero() ? ros::Time::now() : msg.header.stamp;
    for (Wheel& w : wheels_)
    {
      if (w.joint_index < 0 || static_cast<std::size_t>(w.joint_index) >= msg.name.size() ||
          msg.name[w.joint_index] != w.joint)
      {
        w.joint_index = -1;
        for (std::size_t i = 0; i < msg.name.size(); ++i)
          if (msg.name[i] == w.joint)
            w.joint_index = static_cast<int>(i);
      }
      if (w.joint_index < 0 || static_cast<std::size_t>(w.joint_index) >= msg.position.size())
        continue;
      if (stamp.toSec() < w.encoder.lastStamp())  // time went backwards: simulation reset
        w.encoder.reset();
      if (!w.encoder.update(msg.position[w.joint_index], stamp.toSec()) || !w.encoder.valid())
        continue;
      w.encoder_stamp = ros::Time::now();
      w.encoder_time = stamp.toSec();
      publish(w.enc_pub, w.encoder.velocity());
      publish(w.tangent_enc_pub, w.encoder.velocity() * w.radius);
    }
  }

  void onTimer(const ros::TimerEvent&)
  {
    const ros::Time now = ros::Time::now();
    double dt;
    for (Wheel& w : wheels_)
      if (w.scheduler.onTick(now.toSec(), dt))
        step(w, now, dt);
  }

  void step(Wheel& w, const ros::Time& now, double dt)
  {
    {
      double motor = 0.0;
      // A target from before a jump back in time (simulation reset) is stale, not fresh.
      const bool fresh = w.have_target && now >= w.target_stamp && (now - w.target_stamp).toSec() <= timeout_;
      const double target = fresh ? w.target_tangent / w.radius : 0.0;
      publish(w.target_pub, target);
      if (!fresh)
      {
        w.pid.reset();  // stopped: no integral carried into the next start
      }
      else if (!pid_on_)
      {
        motor = target;
      }
      else if (target == 0.0)
      {
        // A zero target is a stop, as in the tutorial: command zero rather than let the
        // PID hunt around zero against a motor's dead band.
        w.pid.reset();
        publish(w.control_pub, 0.0);
      }
      else if (!w.encoder.valid() || (now - w.encoder_stamp).toSec() > encoder_timeout_)
      {
        // Closed loop without a measurement is blind: stop rather than guess.
        if (target != 0.0)
          ROS_WARN_THROTTLE(2.0, "wheel_controller: pid_on but no recent joint_states for joint '%s'; motor stopped",
                            w.joint.c_str());
        w.pid.reset();
      }
      else
      {
        motor = w.pid.compute(target, referenceFor(w, now.toSec(), target), w.encoder.velocity(), dt);
        publish(w.control_pub, motor);
      }
      w.target_history.emplace_back(now.toSec(), target);
      while (w.target_history.size() > 2 && w.target_history[1].first < now.toSec() - 2.0)
        w.target_history.pop_front();
      publish(w.motor_pub, motor);
      if (joint_commands_)
      {
        std_msgs::Float64 c;
        c.data = motor;
        w.joint_cmd_pub.publish(c);
      }
    }
  }

  // The target the encoder reading can reflect: the one commanded response_time before the
  // reading was taken (its stamp, not its arrival: late joint_states on a busy machine then
  // do not look like a slow wheel and wind the integral up).
  double referenceFor(const Wheel& w, double now, double target) const
  {
    if (response_time_ <= 0.0 || w.target_history.empty())
      return target;
    const double t = std::min(now, w.encoder_time) - response_time_;
    double reference = w.target_history.front().second;
    for (const auto& [stamp, value] : w.target_history)
    {
      if (stamp > t)
        break;
      reference = value;
    }
    return reference;
  }

  ros::NodeHandle nh_, pnh_;
  std::array<Wheel, 2> wheels_;
  double period_ = 0.02, timeout_ = 0.5, encoder_timeout_ = 0.5;
  double response_time_ = 0.0;
  bool pid_on_ = true, joint_commands_ = false;
  ros::Subscriber joint_sub_;
  mybot_lockstep::Timer timer_;
};

}  // namespace

namespace mybot_control_nodes
{
std::shared_ptr<void> makeWheelController(const ros::NodeHandle& nh, const ros::NodeHandle& pnh)
{
  return std::make_shared<WheelControllerNode>(nh, pnh);
}
}  // namespace mybot_control_nodes

#ifndef MYBOT_CONTROL_NODE_LIBRARY
int main(int argc, char** argv)
{
  return runNode(argc, argv, "wheel_controller",
                 []
                 {
                   const auto node = mybot_control_nodes::makeWheelController(ros::NodeHandle(), ros::NodeHandle("~"));
                   ros::spin();
                 });
}
#endif
