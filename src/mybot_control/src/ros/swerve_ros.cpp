#include "mybot_control/ros/swerve.hpp"

#include <urdf/model.h>

#include <algorithm>
#include <cmath>

namespace mybot_control
{

std::vector<Vec2> moduleOffsetsFromUrdf(const std::string& xml, const std::vector<std::string>& pivot_joints)
{
  urdf::Model model;
  if (!model.initString(xml))
    throw ParamError("robot_description: cannot parse the URDF");
  std::vector<Vec2> offsets;
  for (const auto& name : pivot_joints)
  {
    urdf::JointConstSharedPtr joint = model.getJoint(name);
    if (!joint)
      throw ParamError("robot_description has no joint '" + name + "' (swerve module pivot joint)");
    // Compose the joint origins from the pivot joint up to the root link (joints at zero).
    urdf::Pose p = joint->parent_to_joint_origin_transform;
    for (auto link = model.getLink(joint->parent_link_name); link && link->parent_joint;
         link = model.getLink(link->parent_joint->parent_link_name))
    {
      const urdf::Pose& up = link->parent_joint->parent_to_joint_origin_transform;
      const urdf::Vector3 r = up.rotation * p.position;
      p.position = urdf::Vector3(r.x + up.position.x, r.y + up.position.y, r.z + up.position.z);
      p.rotation = up.rotation * p.rotation;
    }
    offsets.push_back({p.position.x, p.position.y});
  }
  return offsets;
}

namespace
{
std::string robotDescription(const ParamReader& p, const std::string& why)
{
  std::string key, xml;
  if (!p.nh().searchParam("robot_description", key) || !p.nh().getParam(key, xml))
    throw ParamError(why + " not set and no robot_description to read it from");
  return xml;
}
}  // namespace

SwerveGeometry loadSwerveGeometry(const ParamReader& p, bool need_offsets, bool need_radius)
{
  SwerveGeometry g;
  XmlRpc::XmlRpcValue list;
  if (p.nh().getParam("modules", list))
  {
    if (list.getType() != XmlRpc::XmlRpcValue::TypeArray || list.size() < 2)
      p.fail("modules", "must be a list of at least 2 module names");
    for (int k = 0; k < list.size(); ++k)
    {
      if (list[k].getType() != XmlRpc::XmlRpcValue::TypeString || static_cast<std::string>(list[k]).empty())
        p.fail("modules", "element " + std::to_string(k) + " must be a non-empty string");
      g.modules.push_back(static_cast<std::string>(list[k]));
    }
  }
  else
  {
    g.modules = {"a", "b", "c", "d"};
  }
  for (std::size_t i = 0; i < g.modules.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (g.modules[i] == g.modules[j])
        p.fail("modules", "lists module '" + g.modules[i] + "' twice");

  bool all_offsets = true;
  for (const auto& m : g.modules)
  {
    g.pivot_joints.push_back(p.string(m + "/pivot_joint", "swerve_" + m + "_pivot_joint"));
    g.wheel_joints.push_back(p.string(m + "/wheel_joint", "swerve_" + m + "_wheel_joint"));
    all_offsets = all_offsets && p.has(m + "/offset");
  }

  if (need_offsets)
  {
    std::vector<Vec2> from_urdf;
    if (!all_offsets)
      from_urdf = moduleOffsetsFromUrdf(
          robotDescription(p, "module offsets (" + p.full(g.modules[0] + "/offset") + ")"), g.pivot_joints);
    for (std::size_t i = 0; i < g.modules.size(); ++i)
    {
      const std::string name = g.modules[i] + "/offset";
      if (p.has(name))
      {
        const auto xy = p.numbers(name, 2);
        g.offsets.push_back({xy[0], xy[1]});
      }
      else
      {
        g.offsets.push_back(from_urdf[i]);
      }
    }
    const std::string err = SwerveKinematics::validate(g.offsets);
    if (!err.empty())
      throw ParamError("swerve module offsets (" + p.full("modules") + ", " + p.full(g.modules[0] + "/offset") +
                       " ... or robot_description): " + err);
  }

  if (need_radius)
  {
    if (p.has("wheel_radius"))
    {
      g.wheel_radius = p.positive("wheel_radius", 0.0);
    }
    else
    {
      const std::string xml = robotDescription(p, "parameter " + p.full("wheel_radius"));
      for (const auto& joint : g.wheel_joints)
      {
        // Same joint twice: only its wheel radius is wanted.
        const double r = wheelGeometryFromUrdf(xml, joint, joint).left_radius;
        if (g.wheel_radius > 0.0 && std::abs(r - g.wheel_radius) > 1e-9)
          p.fail("wheel_radius", "is not set and the URDF wheels differ in radius; set it");
        g.wheel_radius = r;
      }
      if (!(g.wheel_radius > 0.0))
        p.fail("wheel_radius",
               "must be > 0 (robot_description's wheel radius is " + std::to_string(g.wheel_radius) + ")");
    }
  }
  return g;
}

double yawOf(const geometry_msgs::Quaternion& q)
{
  return std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
}

bool JointIndex::update(const std::vector<std::string>& names, std::size_t positions_size)
{
  for (std::size_t k = 0; k < names_.size(); ++k)
  {
    int& idx = index_[k];
    if (idx >= 0 && static_cast<std::size_t>(idx) < std::min(names.size(), positions_size) && names[idx] == names_[k])
      continue;
    idx = -1;
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == names_[k])
        idx = static_cast<int>(i);
    if (idx < 0 || static_cast<std::size_t>(idx) >= positions_size)
      return false;
  }
  return true;
}

}  // namespace mybot_control
