// gazebo_ros_control's DefaultRobotHWSim for gazebo_lite: the joints a URDF's <transmission>
// blocks expose, with the hardware interfaces they declare, their state read from the
// simulated robot and their commands written back through the physics (motors limited by the
// URDF's <limit effort> and <limit velocity>; position commands clamped to <limit lower/upper>).
// No ROS: the ROS side (controller manager, controllers) sits on top.
#pragma once

#include <mybot_control/pid.hpp>
#include <mybot_gazebo_lite/model.h>
#include <mybot_gazebo_lite/physics.h>

#include <limits>
#include <map>
#include <string>
#include <vector>

namespace mybot_ros_control
{

enum class Interface
{
  POSITION,
  VELOCITY,
  EFFORT
};

// "hardware_interface/PositionJointInterface" and friends.
std::string interfaceName(Interface i);
// Accepts the full name and the short one ("EffortJointInterface", pre-Indigo URDFs).
bool parseInterface(const std::string& s, Interface& out);

struct SimJoint
{
  std::string name;
  std::vector<Interface> interfaces;  // declared in its <transmission>
  double reduction = 1.0;             // read for the record: commands are joint-side, as in DefaultRobotHWSim
  // URDF limits; infinite when absent.
  bool has_position_limits = false;
  double lower = 0, upper = 0;
  double max_velocity = std::numeric_limits<double>::infinity();
  double max_effort = std::numeric_limits<double>::infinity();
  bool continuous = false;
  // State, read before the controllers run.
  double position = 0, velocity = 0, effort = 0;
  // The command of the interface that drives the joint now.
  Interface mode = Interface::EFFORT;
  double command = 0;
  // A position command moves the servo's setpoint no faster than <limit velocity>, as
  // joint_limits_interface's saturation does upstream.
  double setpoint = 0;
  // gazebo_ros_control/pid_gains/<joint>: position and velocity commands become efforts.
  bool use_pid = false;
  mybot_control::Pid pid;

  bool has(Interface i) const;
};

class RobotHWSim
{
public:
  // Throws mybot_gazebo_lite::LoadError naming the transmission for an unsupported type or
  // interface; pushes a warning for what it reads but does not use.
  RobotHWSim(const mybot_gazebo_lite::RobotSpec& spec, std::vector<std::string>& warnings);

  std::vector<SimJoint>& joints() { return joints_; }
  const std::vector<SimJoint>& joints() const { return joints_; }
  SimJoint* joint(const std::string& name);

  // Gives a joint to an interface: the command starts where the joint is (position) or at rest.
  void claim(SimJoint& j, Interface i);
  void read(const mybot_gazebo_lite::Robot& robot);
  // Applies every joint's command for the next dt seconds.
  void write(mybot_gazebo_lite::Robot& robot, double dt);
  // Every joint back to its initial mode at rest (reset_world, reset_simulation).
  void reset(const mybot_gazebo_lite::Robot& robot);

private:
  std::vector<SimJoint> joints_;
};

// Clamps a position command to the joint's limits (continuous joints are not clamped).
double clampPosition(const SimJoint& j, double position);

}  // namespace mybot_ros_control
