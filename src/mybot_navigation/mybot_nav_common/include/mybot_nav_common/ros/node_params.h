// ROS-side helpers shared by the navigation nodes: strict parameter reading and laser
// scan conversion (header-only; the algorithms stay in the ROS-free libraries).
#pragma once

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2/LinearMath/Matrix3x3.h>
#include <tf2/LinearMath/Quaternion.h>
#include <geometry_msgs/TransformStamped.h>
#include <XmlRpcValue.h>

#include "mybot_common/checks.h"
#include "mybot_common/ros/params.h"
#include "mybot_nav_common/pose2d.h"

namespace mybot_navigation
{

using mybot_common::fatalParam;
using mybot_common::readParam;

// False for a scan that contradicts its own geometry (ranges not matching its angles, or range limits
// that are no range), with a throttled warning naming the topic and the numbers: drawn in, it would
// put walls at the wrong bearings or at NaN in the map, the particle weights and the costmap.
inline bool scanGeometryOk(const std::string& node, const std::string& topic, const sensor_msgs::LaserScan& scan)
{
  const std::string error = mybot_common::scanError(scan.angle_min, scan.angle_max, scan.angle_increment,
                                                    scan.ranges.size(), scan.range_min, scan.range_max);
  if (error.empty())
    return true;
  ROS_WARN_THROTTLE(5.0, "%s: dropping scans on %s: one %s", node.c_str(), topic.c_str(), error.c_str());
  return false;
}

// costmap_2d's footprint parameter: a list [[x, y], ...] or the same as a string.
inline bool parseFootprint(const XmlRpc::XmlRpcValue& value, std::vector<Point2D>& out, std::string& error)
{
  out.clear();
  auto number = [](const XmlRpc::XmlRpcValue& v, double& d)
  {
    if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble)
      d = static_cast<double>(const_cast<XmlRpc::XmlRpcValue&>(v));
    else if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
      d = static_cast<int>(const_cast<XmlRpc::XmlRpcValue&>(v));
    else
      return false;
    return true;
  };
  if (value.getType() == XmlRpc::XmlRpcValue::TypeString)
  {
    // "[[x, y], [x, y], ...]": pull out the numbers pairwise.
    std::string s = static_cast<std::string>(const_cast<XmlRpc::XmlRpcValue&>(value));
    std::vector<double> nums;
    const char* p = s.c_str();
    while (*p)
    {
      char* end = nullptr;
      const double d = std::strtod(p, &end);
      if (end != p)
      {
        nums.push_back(d);
        p = end;
      }
      else
      {
        ++p;
      }
    }
    if (nums.size() % 2 != 0 || nums.size() < 6)
    {
      error = "expected at least 3 [x, y] points, got \"" + s + "\"";
      return false;
    }
    for (size_t i = 0; i < nums.size(); i += 2)
      out.push_back({nums[i], nums[i + 1]});
    return true;
  }
  if (value.getType() != XmlRpc::XmlRpcValue::TypeArray || value.size() < 3)
  {
    error = "expected a list of at least 3 [x, y] points";
    return false;
  }
  for (int i = 0; i < value.size(); ++i)
  {
    const XmlRpc::XmlRpcValue& pt = const_cast<XmlRpc::XmlRpcValue&>(value)[i];
    Point2D q;
    if (pt.getType() != XmlRpc::XmlRpcValue::TypeArray || pt.size() != 2 ||
        !number(const_cast<XmlRpc::XmlRpcValue&>(pt)[0], q.x) || !number(const_cast<XmlRpc::XmlRpcValue&>(pt)[1], q.y))
    {
      error = "point " + std::to_string(i) + " is not a pair of numbers";
      return false;
    }
    out.push_back(q);
  }
  return true;
}

inline Pose2D toPose2D(const geometry_msgs::TransformStamped& t, bool* upside_down = nullptr)
{
  const tf2::Quaternion q(t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z,
                          t.transform.rotation.w);
  double roll, pitch, yaw;
  tf2::Matrix3x3(q).getRPY(roll, pitch, yaw);
  if (upside_down)
    *upside_down = tf2::Matrix3x3(q).getColumn(2).z() < 0.0;  // sensor z axis points down
  return {t.transform.translation.x, t.transform.translation.y, yaw};
}

// End points of a scan's beams in a target frame, split into obstacle hits and free-space
// rays (no return or beyond `max_range`), given the sensor's pose in that frame.
// `inf_is_valid`: +inf means "nothing within range" (REP 117) and clears up to clear_range.
inline void scanEndPoints(const sensor_msgs::LaserScan& scan, const Pose2D& sensor, bool upside_down,
                          double clear_range, std::vector<Point2D>& hits, std::vector<Point2D>& free_ends,
                          bool inf_is_valid = true)
{
  hits.clear();
  free_ends.clear();
  const double sign = upside_down ? -1.0 : 1.0;
  for (size_t i = 0; i < scan.ranges.size(); ++i)
  {
    const double r = scan.ranges[i];
    const double a = sensor.theta + sign * (scan.angle_min + scan.angle_increment * static_cast<double>(i));
    const double c = std::cos(a), s = std::sin(a);
    if (std::isnan(r) || r < scan.range_min)
      continue;
    if (!std::isfinite(r) || r >= scan.range_max)
    {
      if (inf_is_valid || std::isfinite(r))
        free_ends.push_back({sensor.x + clear_range * c, sensor.y + clear_range * s});
      continue;
    }
    hits.push_back({sensor.x + r * c, sensor.y + r * s});
  }
}

}  // namespace mybot_navigation
