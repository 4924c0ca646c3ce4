#include "mybot_ros_control/robot_hw_sim.h"

#include <algorithm>
#include <cmath>

namespace mybot_ros_control
{

using mybot_gazebo_lite::JointSpec;
using mybot_gazebo_lite::LoadError;

namespace
{
// A joint without <limit effort> may push as hard as it needs in Gazebo (the limit is
// infinite there); a physics motor needs a number, and this one is beyond any robot's.
constexpr double kUnlimitedEffort = 1e6;
// Position servo time constant, in control periods: stable with the control period's delay.
constexpr double kServoPeriods = 5.0;
}  // namespace

std::string interfaceName(Interface i)
{
  switch (i)
  {
    case Interface::POSITION:
      return "hardware_interface/PositionJointInterface";
    case Interface::VELOCITY:
      return "hardware_interface/VelocityJointInterface";
    case Interface::EFFORT:
      return "hardware_interface/EffortJointInterface";
  }
  return "";
}

bool parseInterface(const std::string& s, Interface& out)
{
  for (Interface i : {Interface::POSITION, Interface::VELOCITY, Interface::EFFORT})
  {
    const std::string full = interfaceName(i);
    if (s == full || s == full.substr(full.find('/') + 1))
    {
      out = i;
      return true;
    }
  }
  return false;
}

bool SimJoint::has(Interface i) const
{
  return std::find(interfaces.begin(), interfaces.end(), i) != interfaces.end();
}

RobotHWSim::RobotHWSim(const mybot_gazebo_lite::RobotSpec& spec, std::vector<std::string>& warnings)
{
  for (const auto& t : spec.transmissions)
  {
    const std::string where = spec.source + ": <transmission name='" + t.name + "'>";
    if (t.type != "transmission_interface/SimpleTransmission" && t.type != "pr2_mechanism_model/SimpleTransmission")
      throw LoadError(where + ": <type> '" + t.type +
                      "' is not supported (gazebo_ros_control's default robot supports "
                      "transmission_interface/SimpleTransmission)");
    const JointSpec* js = spec.joint(t.joint);
    if (js->type == JointSpec::FIXED)
      throw LoadError(where + ": joint '" + t.joint + "' is fixed");
    if (t.interfaces.empty())
      throw LoadError(where + ": joint '" + t.joint + "' declares no <hardwareInterface>");
    SimJoint* j = joint(t.joint);
    if (!j)
    {
      joints_.emplace_back();
      j = &joints_.back();
      j->name = t.joint;
      j->reduction = t.reduction;
      j->continuous = js->type == JointSpec::CONTINUOUS;
      j->has_position_limits = js->has_limits && !j->continuous;
      j->lower = js->lower;
      j->upper = js->upper;
      if (js->has_velocity && js->velocity > 0)
        j->max_velocity = js->velocity;
      if (js->has_effort && js->effort > 0)
        j->max_effort = js->effort;
    }
    for (const std::string& name : t.interfaces)
    {
      Interface i;
      if (!parseInterface(name, i))
        throw LoadError(where + ": <hardwareInterface> '" + name +
                        "' is not supported (Position, Velocity or EffortJointInterface of hardware_interface)");
      if (name.find('/') == std::string::npos)
        warnings.push_back(where + ": <hardwareInterface> '" + name +
                           "' without the 'hardware_interface/' prefix is deprecated");
      if (!j->has(i))
        j->interfaces.push_back(i);
    }
    if (!t.actuator.empty() && t.reduction != 1.0)
      warnings.push_back(where + ": <mechanicalReduction> " + std::to_string(t.reduction) +
                         " does not scale the commands (they are joint-side, as in gazebo_ros_control)");
    j->mode = j->interfaces.front();
  }
}

SimJoint* RobotHWSim::joint(const std::string& name)
{
  for (auto& j : joints_)
    if (j.name == name)
      return &j;
  return nullptr;
}

double clampPosition(const SimJoint& j, double p)
{
  return j.has_position_limits ? std::max(j.lower, std::min(j.upper, p)) : p;
}

void RobotHWSim::claim(SimJoint& j, Interface i)
{
  j.mode = i;
  j.command = i == Interface::POSITION ? j.position : 0.0;
  j.setpoint = j.position;
  j.pid.reset();
}

void RobotHWSim::read(const mybot_gazebo_lite::Robot& robot)
{
  for (auto& j : joints_)
  {
    j.position = robot.jointPosition(j.name);
    j.velocity = robot.jointVelocity(j.name);
    j.effort = robot.jointEffort(j.name);
  }
}

void RobotHWSim::reset(const mybot_gazebo_lite::Robot& robot)
{
  read(robot);
  for (auto& j : joints_)
    claim(j, j.mode);
}

void RobotHWSim::write(mybot_gazebo_lite::Robot& robot, double dt)
{
  for (auto& j : joints_)
  {
    const double effort_cap = std::isfinite(j.max_effort) ? j.max_effort : kUnlimitedEffort;
    const double cmd = std::isfinite(j.command) ? j.command : 0.0;
    switch (j.mode)
    {
      case Interface::EFFORT:
        robot.commandEffort(j.name, std::max(-effort_cap, std::min(effort_cap, cmd)));
        break;
      case Interface::VELOCITY:
      {
        const double v = std::max(-j.max_velocity, std::min(j.max_velocity, cmd));
        if (j.use_pid)
          robot.commandEffort(j.name, j.pid.compute(v, j.velocity, dt));
        else
          robot.commandVelocity(j.name, v, effort_cap);
        break;
      }
      case Interface::POSITION:
      {
        double p = clampPosition(j, cmd);
        if (std::isfinite(j.max_velocity) && dt > 0)
          p = j.setpoint + std::max(-j.max_velocity * dt, std::min(j.max_velocity * dt, p - j.setpoint));
        const double rate = dt > 0 ? (p - j.setpoint) / dt : 0.0;
        j.setpoint = p;
        if (j.use_pid)
        {
          robot.commandEffort(j.name, j.pid.compute(p, j.position, dt));
        }
        else if (dt > 0)
        {
          // A servo: the setpoint's rate plus the error closed over kServoPeriods control periods,
          // never faster than <limit velocity>, by a motor no stronger than <limit effort>.
          // (Gazebo teleports the joint instead; a servo keeps the effort limit honest.)
          const double v = rate + (p - j.position) / (kServoPeriods * dt);
          robot.commandVelocity(j.name, std::max(-j.max_velocity, std::min(j.max_velocity, v)), effort_cap);
        }
        break;
      }
    }
  }
}

}  // namespace mybot_ros_control
