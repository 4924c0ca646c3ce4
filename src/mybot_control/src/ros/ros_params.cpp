#include "mybot_control/ros/params.hpp"

#include <urdf/model.h>

#include <cmath>

namespace mybot_control
{

SpeedLimits loadSpeedLimits(const ParamReader& p, const std::string& prefix)
{
  SpeedLimits l;
  l.has_velocity_limits = p.boolean(prefix + "has_velocity_limits", false);
  l.max_velocity = p.number(prefix + "max_velocity", 0.0);
  l.min_velocity = p.number(prefix + "min_velocity", -l.max_velocity);
  l.has_acceleration_limits = p.boolean(prefix + "has_acceleration_limits", false);
  l.max_acceleration = p.number(prefix + "max_acceleration", 0.0);
  l.min_acceleration = p.number(prefix + "min_acceleration", -l.max_acceleration);
  l.has_deceleration_limits = p.boolean(prefix + "has_deceleration_limits", false);
  l.max_deceleration = p.number(prefix + "max_deceleration", 0.0);
  l.has_jerk_limits = p.boolean(prefix + "has_jerk_limits", false);
  l.max_jerk = p.number(prefix + "max_jerk", 0.0);
  l.min_jerk = p.number(prefix + "min_jerk", -l.max_jerk);
  const std::string err = l.validate(p.full(prefix.empty() ? "" : prefix.substr(0, prefix.size() - 1)) + "/");
  if (!err.empty())
    throw ParamError("parameter " + err);
  return l;
}

PidConfig loadPid(const ParamReader& p, const std::string& name, bool required, const PidConfig& defaults)
{
  if (!p.has(name))
  {
    if (required)
      p.fail(name, "is required: a PID block with at least p, i, d");
    return defaults;
  }
  XmlRpc::XmlRpcValue block;
  p.nh().getParam(name, block);
  if (block.getType() != XmlRpc::XmlRpcValue::TypeStruct)
    p.fail(name, "must be a mapping with p, i, d (PID gains YAML)");
  const std::string b = name + "/";
  PidConfig c = defaults;
  c.p = p.number(b + "p", defaults.p);
  c.i = p.number(b + "i", defaults.i);
  c.d = p.number(b + "d", defaults.d);
  c.f = p.number(b + "f", defaults.f);
  c.i_clamp_min = p.number(b + "i_clamp_min", defaults.i_clamp_min);
  c.i_clamp_max = p.number(b + "i_clamp_max", defaults.i_clamp_max);
  c.output_min = p.number(b + "output_min", defaults.output_min);
  c.output_max = p.number(b + "output_max", defaults.output_max);
  c.d_filter_tau = p.number(b + "d_filter_tau", defaults.d_filter_tau);
  c.angle_wrap = p.boolean(b + "angle_wrap", defaults.angle_wrap);
  c.no_reverse_below = p.number(b + "no_reverse_below", defaults.no_reverse_below);
  const double delay = p.number(b + "setpoint_delay", defaults.setpoint_delay);
  if (delay != std::floor(delay))
    p.fail(b + "setpoint_delay", "must be an integer number of control steps");
  c.setpoint_delay = static_cast<int>(delay);
  if (p.has(b + "schedule"))
  {
    XmlRpc::XmlRpcValue list;
    p.nh().getParam(b + "schedule", list);
    if (list.getType() != XmlRpc::XmlRpcValue::TypeArray)
      p.fail(b + "schedule", "must be a list of {error, p, i, d}");
    c.schedule.clear();
    for (int k = 0; k < list.size(); ++k)
    {
      const std::string where = b + "schedule[" + std::to_string(k) + "]";
      if (list[k].getType() != XmlRpc::XmlRpcValue::TypeStruct || !list[k].hasMember("error"))
        p.fail(where, "must be a mapping with error, p, i, d");
      auto get = [&](const char* key, double dflt)
      {
        if (!list[k].hasMember(key))
          return dflt;
        XmlRpc::XmlRpcValue& v = list[k][key];
        if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble)
          return static_cast<double>(v);
        if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
          return static_cast<double>(static_cast<int>(v));
        p.fail(where + "." + key, "must be a number");
      };
      c.schedule.push_back({get("error", 0.0), get("p", 0.0), get("i", 0.0), get("d", 0.0)});
    }
  }
  const std::string err = c.validate(p.full(name) + "/");
  if (!err.empty())
    throw ParamError("parameter " + err);
  return c;
}

namespace
{
// Position of a joint's origin in the root link frame (all joints at zero).
urdf::Vector3 jointPositionInRoot(const urdf::Model& model, const urdf::JointConstSharedPtr& joint)
{
  urdf::Pose pose = joint->parent_to_joint_origin_transform;
  urdf::LinkConstSharedPtr link = model.getLink(joint->parent_link_name);
  while (link && link->parent_joint)
  {
    const urdf::Pose& up = link->parent_joint->parent_to_joint_origin_transform;
    const urdf::Vector3 r = up.rotation * pose.position;
    pose.position = urdf::Vector3(r.x + up.position.x, r.y + up.position.y, r.z + up.position.z);
    pose.rotation = up.rotation * pose.rotation;
    link = model.getLink(link->parent_joint->parent_link_name);
  }
  return pose.position;
}

double wheelRadius(const urdf::Model& model, const urdf::JointConstSharedPtr& joint)
{
  const urdf::LinkConstSharedPtr link = model.getLink(joint->child_link_name);
  if (!link || !link->collision || !link->collision->geometry)
    throw ParamError("robot_description: wheel link '" + joint->child_link_name + "' of joint '" + joint->name +
                     "' has no collision geometry to take wheel_radius from; set wheel_radius");
  const auto& g = link->collision->geometry;
  if (g->type == urdf::Geometry::CYLINDER)
    return static_cast<const urdf::Cylinder&>(*g).radius;
  if (g->type == urdf::Geometry::SPHERE)
    return static_cast<const urdf::Sphere&>(*g).radius;
  throw ParamError("robot_description: wheel link '" + link->name +
                   "' collision is neither a cylinder nor a sphere; set wheel_radius");
}
}  // namespace

WheelGeometry wheelGeometryFromUrdf(const std::string& xml, const std::string& left_joint,
                                    const std::string& right_joint)
{
  urdf::Model model;
  if (!model.initString(xml))
    throw ParamError("robot_description: cannot parse the URDF");
  const auto left = model.getJoint(left_joint);
  const auto right = model.getJoint(right_joint);
  if (!left)
    throw ParamError("robot_description has no joint '" + left_joint + "' (parameter left_wheel)");
  if (!right)
    throw ParamError("robot_description has no joint '" + right_joint + "' (parameter right_wheel)");
  const urdf::Vector3 a = jointPositionInRoot(model, left), b = jointPositionInRoot(model, right);
  WheelGeometry g;
  g.separation = std::hypot(a.x - b.x, a.y - b.y, a.z - b.z);
  g.left_radius = wheelRadius(model, left);
  g.right_radius = wheelRadius(model, right);
  return g;
}

WheelGeometry loadWheelGeometry(const ParamReader& p, const std::string& left_joint, const std::string& right_joint,
                                bool need_separation, bool need_radius)
{
  WheelGeometry g;
  const bool have_sep = p.has("wheel_separation"), have_rad = p.has("wheel_radius");
  if ((need_separation && !have_sep) || (need_radius && !have_rad))
  {
    std::string key, xml;
    if (!p.nh().searchParam("robot_description", key) || !p.nh().getParam(key, xml))
      throw ParamError("parameter " + p.full(need_separation && !have_sep ? "wheel_separation" : "wheel_radius") +
                       " not set and no robot_description to read it from");
    g = wheelGeometryFromUrdf(xml, left_joint, right_joint);
  }
  if (have_sep)
    g.separation = p.positive("wheel_separation", 0.0);
  if (have_rad)
    g.left_radius = g.right_radius = p.positive("wheel_radius", 0.0);
  if (need_separation && !(g.separation > 0.0))
    p.fail("wheel_separation", "must be > 0 (the URDF wheel joints coincide)");
  if (need_radius && !(g.left_radius > 0.0 && g.right_radius > 0.0))
    p.fail("wheel_radius", "must be > 0");
  g.separation *= p.positive("wheel_separation_multiplier", 1.0);
  const double radius_multiplier = p.positive("wheel_radius_multiplier", 1.0);
  g.left_radius *= radius_multiplier * p.positive("left_wheel_radius_multiplier", 1.0);
  g.right_radius *= radius_multiplier * p.positive("right_wheel_radius_multiplier", 1.0);
  return g;
}

}  // namespace mybot_control
