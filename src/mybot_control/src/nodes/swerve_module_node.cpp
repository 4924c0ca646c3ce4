// Servo loops of N swerve modules in one process (one module per process also works:
// modules: [a]). Per module m, under swerve_<m>/: subscribes rqst_pivot_angle (rad) and
// rqst_wheel_speed (m/s at the rim); publishes pivot_angle (rad, wrapped), wheel_speed (m/s),
// pivot_angle_error, wheel_speed_error, pivot_control and wheel_control (joint velocity
// commands, rad/s).
//   interface: joints -> measurements from joint_states, commands as std_msgs/Float64 on
//              <joint>/command (the simulator's joint-command interface);
//   interface: mock   -> no hardware: a first-order actuator model per joint, integrated on a
//              timer, and the node publishes joint_states itself (for the odometry).
#include <mybot_lockstep/ros/participant.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Float64.h>

#include <cmath>

#include "mybot_control/odometry.hpp"
#include "mybot_control/ros/params.hpp"
#include "mybot_control/swerve_module.hpp"
#include "mybot_control/ros/swerve.hpp"
#include "swerve_nodes.hpp"

using namespace mybot_control;

namespace mybot_control_nodes
{
struct Module
{
  Module(const std::string& n, const SwerveModuleConfig& c, std::size_t window, double tau)
      : name(n), ctl(c), encoder(window), mock(tau)
  {
  }
  std::string name;
  SwerveModuleController ctl;
  WheelEncoder encoder;
  MockModuleActuator mock;
  double rqst_angle = 0.0, rqst_speed = 0.0;
  bool have_angle_request = false;
  ros::Time last_speed_request;
  double pivot_position = 0.0;
  double pivot_command = 0.0, wheel_command = 0.0;  // last outputs (rad/s)
  bool have_measurement = false;
  ros::Publisher angle_pub, speed_pub, angle_error_pub, speed_error_pub, pivot_control_pub, wheel_control_pub;
  ros::Publisher pivot_cmd_pub, wheel_cmd_pub;
  ros::Subscriber angle_sub, speed_sub;
};

class SwerveModuleNode
{
public:
  SwerveModuleNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) : nh_(nh), pnh_(pnh)
  {
    const ParamReader p(pnh_);
    geometry_ = loadSwerveGeometry(p, false, true);
    const std::string interface = p.string("interface", "joints");
    if (interface != "joints" && interface != "mock")
      p.fail("interface", "must be 'joints' (simulator joint commands) or 'mock' (got '" + interface + "')");
    mock_ = interface == "mock";
    timeout_ = p.nonNegative("timeout", 0.5);
    const double rate = p.positive("rate", 50.0);
    const double mock_tau = p.nonNegative("mock_tau", 0.05);
    const auto window = static_cast<std::size_t>(p.positive("velocity_window", 2));
    const PidConfig pivot_shared = loadPid(p, "pivot_pid", false);
    const PidConfig drive_shared = loadPid(p, "drive_pid", false);

    const std::size_t n = geometry_.modules.size();
    modules_.reserve(n);
    for (std::size_t i = 0; i < n; ++i)
    {
      const std::string& m = geometry_.modules[i];
      // Per-module gains (<m>/pivot_pid) override the shared block; one of them is required.
      SwerveModuleConfig c;
      const bool own_pivot = p.has(m + "/pivot_pid"), own_drive = p.has(m + "/drive_pid");
      if (!own_pivot && !p.has("pivot_pid"))
        p.fail("pivot_pid", "is required (or " + p.full(m + "/pivot_pid") + "): a PID block with p, i, d");
      if (!own_drive && !p.has("drive_pid"))
        p.fail("drive_pid", "is required (or " + p.full(m + "/drive_pid") + "): a PID block with p, i, d, f");
      c.pivot = own_pivot ? loadPid(p, m + "/pivot_pid", true) : pivot_shared;
      c.drive = own_drive ? loadPid(p, m + "/drive_pid", true) : drive_shared;
      c.wheel_radius = geometry_.wheel_radius;
      c.pivot_rate_ff = p.number("pivot_rate_ff", 1.0);
      c.pivot_rate_ff_max_step = p.nonNegative("pivot_rate_ff_max_step", 0.2);
      c.optimize = p.boolean("optimize", true);
      c.cosine_scale = p.boolean("cosine_scale", true);
      const std::string err = c.validate(p.full(m) + "/");
      if (!err.empty())
        throw ParamError("parameter " + err);

      modules_.emplace_back(m, c, window, mock_tau);
      Module& mod = modules_.back();
      const std::string ns = "swerve_" + m + "/";
      mod.angle_pub = nh_.advertise<std_msgs::Float64>(ns + "pivot_angle", 10);
      mod.speed_pub = nh_.advertise<std_msgs::Float64>(ns + "wheel_speed", 10);
      mod.angle_error_pub = nh_.advertise<std_msgs::Float64>(ns + "pivot_angle_error", 10);
      mod.speed_error_pub = nh_.advertise<std_msgs::Float64>(ns + "wheel_speed_error", 10);
      mod.pivot_control_pub = nh_.advertise<std_msgs::Float64>(ns + "pivot_control", 10);
      mod.wheel_control_pub = nh_.advertise<std_msgs::Float64>(ns + "wheel_control", 10);
      if (!mock_)
      {
        mod.pivot_cmd_pub = nh_.advertise<std_msgs::Float64>(geometry_.pivot_joints[i] + "/command", 10);
        mod.wheel_cmd_pub = nh_.advertise<std_msgs::Float64>(geometry_.wheel_joints[i] + "/command", 10);
      }
      mod.angle_sub = mybot_lockstep::Participant::instance().subscribe<std_msgs::Float64>(
          nh_, ns + "rqst_pivot_angle", 10,
          [this, i](const std_msgs::Float64::ConstPtr& msg)
          {
            if (std::isfinite(msg->data))
            {
              modules_[i].rqst_angle = msg->data;
              modules_[i].have_angle_request = true;
            }
          },
          ros::TransportHints().tcpNoDelay());
      mod.speed_sub = mybot_lockstep::Participant::instance().subscribe<std_msgs::Float64>(
          nh_, ns + "rqst_wheel_speed", 10,
          [this, i](const std_msgs::Float64::ConstPtr& msg)
          {
            if (std::isfinite(msg->data))
            {
              modules_[i].rqst_speed = msg->data;
              modules_[i].last_speed_request = ros::Time::now();
            }
          },
          ros::TransportHints().tcpNoDelay());
    }

    std::vector<std::string> joints;
    for (std::size_t i = 0; i < n; ++i)
    {
      joints.push_back(geometry_.pivot_joints[i]);
      joints.push_back(geometry_.wheel_joints[i]);
    }
    if (mock_)
    {
      joint_state_.name = joints;
      joint_state_.position.assign(joints.size(), 0.0);
      joint_state_.velocity.assign(joints.size(), 0.0);
      joint_state_pub_ = nh_.advertise<sensor_msgs::JointState>("joint_states", 10);
      timer_ = mybot_lockstep::Participant::instance().createTimer(
          nh_, 1.0 / rate, [this](const ros::TimerEvent& e) { onMockTimer(e); });
    }
    else
    {
      index_ = JointIndex(joints);
      joint_sub_ = mybot_lockstep::Participant::instance().subscribe<sensor_msgs::JointState>(
          nh_, "joint_states", 10, [this](const sensor_msgs::JointState& m) { onJointStates(m); },
          ros::TransportHints().tcpNoDelay());
    }
    ROS_INFO("swerve_module: %zu modules, interface %s, wheel_radius %.4f m", n, interface.c_str(),
             geometry_.wheel_radius);
  }

private:
  void onJointStates(const sensor_msgs::JointState& msg)
  {
    if (!index_.update(msg.name, msg.position.size()))
      return;  // joint_states of other joints
    const ros::Time stamp = msg.header.stamp.isZero() ? ros::Time::now() : msg.header.stamp;
    for (std::size_t i = 0; i < modules_.size(); ++i)
      measure(modules_[i], msg.position[index_[2 * i]], msg.position[index_[2 * i + 1]], stamp);
    control(stamp);
  }

  void onMockTimer(const ros::TimerEvent&)
  {
    const ros::Time now = ros::Time::now();
    const double dt = last_step_.isZero() ? 0.0 : (now - last_step_).toSec();
    for (std::size_t i = 0; i < modules_.size(); ++i)
    {
      Module& m = modules_[i];
      m.mock.step(m.pivot_command, m.wheel_command, dt);  // last period's commands
      joint_state_.position[2 * i] = m.mock.pivotPosition();
      joint_state_.velocity[2 * i] = m.mock.pivotVelocity();
      joint_state_.position[2 * i + 1] = m.mock.wheelPosition();
      joint_state_.velocity[2 * i + 1] = m.mock.wheelVelocity();
      measure(m, m.mock.pivotPosition(), m.mock.wheelPosition(), now);
    }
    joint_state_.header.stamp = now;
    publishShared(joint_state_pub_, joint_state_);
    control(now);
  }

  void measure(Module& m, double pivot_position, double wheel_position, const ros::Time& stamp)
  {
    if (stamp < last_step_)  // time went backwards (simulation reset)
      m.encoder.reset();
    if (std::isfinite(pivot_position))
    {
      m.pivot_position = pivot_position;
      m.have_measurement = true;
    }
    m.encoder.update(wheel_position, stamp.toSec());
  }

  void control(const ros::Time& now)
  {
    double dt = last_step_.isZero() ? 0.0 : (now - last_step_).toSec();
    if (dt < 0.0)
    {
      for (auto& m : modules_)
        m.ctl.reset();
      dt = 0.0;
    }
    last_step_ = now;
    std_msgs::Float64 v;
    for (auto& m : modules_)
    {
      if (!m.have_measurement)
        continue;
      const double angle = wrapAngle(m.pivot_position);
      const double rate = m.encoder.valid() ? m.encoder.velocity() : 0.0;
      // No angle request yet: hold the module where it is. Requests stopping: stop the wheel.
      const bool stale = m.last_speed_request.isZero() || now < m.last_speed_request ||
                         (timeout_ > 0.0 && (now - m.last_speed_request).toSec() > timeout_);
      const SwerveModuleState request{stale ? 0.0 : m.rqst_speed, m.have_angle_request ? m.rqst_angle : angle};
      const auto out = m.ctl.update(request, angle, rate, dt);
      m.pivot_command = out.pivot_command;
      m.wheel_command = out.wheel_command;
      auto pub = [&v](ros::Publisher& p, double x)
      {
        v.data = x;
        publishShared(p, v);
      };
      pub(m.angle_pub, angle);
      pub(m.speed_pub, rate * geometry_.wheel_radius);
      pub(m.angle_error_pub, out.pivot_error);
      pub(m.speed_error_pub, out.speed_error);
      pub(m.pivot_control_pub, out.pivot_command);
      pub(m.wheel_control_pub, out.wheel_command);
      if (!mock_)
      {
        pub(m.pivot_cmd_pub, out.pivot_command);
        pub(m.wheel_cmd_pub, out.wheel_command);
      }
    }
  }

  ros::NodeHandle nh_, pnh_;
  SwerveGeometry geometry_;
  std::vector<Module> modules_;
  bool mock_ = false;
  double timeout_ = 0.5;
  JointIndex index_;
  ros::Time last_step_;
  sensor_msgs::JointState joint_state_;
  ros::Publisher joint_state_pub_;
  ros::Subscriber joint_sub_;
  mybot_lockstep::Timer timer_;
};

std::shared_ptr<void> makeSwerveModule(const ros::NodeHandle& nh, const ros::NodeHandle& pnh)
{
  return std::make_shared<SwerveModuleNode>(nh, pnh);
}
}  // namespace mybot_control_nodes

#ifndef MYBOT_CONTROL_NODE_LIBRARY
int main(int argc, char** argv)
{
  return runNode(argc, argv, "swerve_module",
                 []
                 {
                   const auto node = mybot_control_nodes::makeSwerveModule(ros::NodeHandle(), ros::NodeHandle("~"));
                   ros::spin();
                 });
}
#endif
