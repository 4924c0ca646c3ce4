// ROS-side helpers shared by the swerve nodes: module names, joint names, module offsets and
// wheel radius from parameters or the URDF, all validated (one ParamError naming the
// parameter). Kept out of the pure library on purpose.
#pragma once

#include <boost/make_shared.hpp>
#include <geometry_msgs/Quaternion.h>
#include <ros/publisher.h>

#include <string>
#include <vector>

#include "mybot_control/ros/params.hpp"
#include "mybot_control/swerve_kinematics.hpp"

namespace mybot_control
{

// Publishes a copy as a shared pointer. In one process (swerve_chain, the nodelets) roscpp then
// hands it to the subscriber as is; a message published by value is serialised and wakes
// roscpp's network thread, once per message, even when every subscriber is in the process.
template <class M>
void publishShared(const ros::Publisher& pub, const M& msg)
{
  if (pub.getNumSubscribers() > 0)
    pub.publish(boost::make_shared<M>(msg));
}

struct SwerveGeometry
{
  std::vector<std::string> modules;       // e.g. a, b, c, d
  std::vector<std::string> pivot_joints;  // swerve_<m>_pivot_joint
  std::vector<std::string> wheel_joints;  // swerve_<m>_wheel_joint
  std::vector<Vec2> offsets;              // pivot axis positions in the base frame (m)
  double wheel_radius = 0.0;              // m
};

// Reads `modules` (default [a, b, c, d]), per module `<m>/pivot_joint`, `<m>/wheel_joint`
// (defaults swerve_<m>_pivot_joint / swerve_<m>_wheel_joint) and `<m>/offset` ([x, y]; default:
// the pivot joint's position in robot_description), and `wheel_radius` (default: the first
// wheel link's collision radius in robot_description). need_offsets / need_radius: which of
// them the node uses (robot_description is only read when one of those is missing).
SwerveGeometry loadSwerveGeometry(const ParamReader& params, bool need_offsets, bool need_radius);

// Module offsets (x, y) of the given pivot joints in the URDF's root frame. Throws ParamError
// naming a missing joint.
std::vector<Vec2> moduleOffsetsFromUrdf(const std::string& urdf_xml, const std::vector<std::string>& pivot_joints);

// Yaw (rad) of an orientation (e.g. sensor_msgs/Imu's); NaN in, NaN out.
double yawOf(const geometry_msgs::Quaternion& q);

// Index of each name in a JointState-like name list (cached; -1 when absent).
class JointIndex
{
public:
  explicit JointIndex(std::vector<std::string> names = {}) : names_(std::move(names)), index_(names_.size(), -1) {}
  // True when every joint is in `names` and has a position (positions_size entries).
  bool update(const std::vector<std::string>& names, std::size_t positions_size);
  int operator[](std::size_t k) const { return index_[k]; }
  std::size_t size() const { return names_.size(); }

private:
  std::vector<std::string> names_;
  std::vector<int> index_;
};

}  // namespace mybot_control
