// Message <-> library conversions shared by the navigation nodes (header-only, ROS side).
#pragma once

#include <cmath>

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Transform.h>
#include <nav_msgs/OccupancyGrid.h>

#include "mybot_nav_common/grid_map.h"

namespace mybot_navigation
{

inline double yawOf(double x, double y, double z, double w)
{
  return std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
}

inline Pose2D toPose2D(const geometry_msgs::Transform& t)
{
  return {t.translation.x, t.translation.y, yawOf(t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w)};
}

inline Pose2D toPose2D(const geometry_msgs::Pose& p)
{
  return {p.position.x, p.position.y, yawOf(p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w)};
}

inline geometry_msgs::Transform toTransform(const Pose2D& p)
{
  geometry_msgs::Transform t;
  t.translation.x = p.x;
  t.translation.y = p.y;
  t.rotation.z = std::sin(p.theta / 2.0);
  t.rotation.w = std::cos(p.theta / 2.0);
  return t;
}

inline geometry_msgs::Pose toPoseMsg(const Pose2D& p)
{
  geometry_msgs::Pose m;
  m.position.x = p.x;
  m.position.y = p.y;
  m.orientation.z = std::sin(p.theta / 2.0);
  m.orientation.w = std::cos(p.theta / 2.0);
  return m;
}

inline nav_msgs::MapMetaData toMapMetaData(const MapInfo& info)
{
  nav_msgs::MapMetaData m;
  m.resolution = static_cast<float>(info.resolution);
  m.width = static_cast<uint32_t>(info.width);
  m.height = static_cast<uint32_t>(info.height);
  m.origin = toPoseMsg(info.origin);
  return m;
}

inline void toOccupancyGrid(const GridMap& map, nav_msgs::OccupancyGrid& msg)
{
  msg.info = toMapMetaData(map.info);
  msg.data.assign(map.data.begin(), map.data.end());
}

inline GridMap fromOccupancyGrid(const nav_msgs::OccupancyGrid& msg)
{
  GridMap map;
  map.info.resolution = msg.info.resolution;
  map.info.width = static_cast<int>(msg.info.width);
  map.info.height = static_cast<int>(msg.info.height);
  map.info.origin = toPose2D(msg.info.origin);
  map.data.assign(msg.data.begin(), msg.data.end());
  return map;
}

}  // namespace mybot_navigation
