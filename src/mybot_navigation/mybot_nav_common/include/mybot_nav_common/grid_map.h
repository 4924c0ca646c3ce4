// A static occupancy map in nav_msgs/OccupancyGrid semantics (row-major, cell (0,0) at the
// lower-left corner `origin`, values 0..100 or -1 unknown), without ROS types.
#pragma once

#include <cstdint>
#include <vector>

#include "mybot_nav_common/pose2d.h"

namespace mybot_navigation
{

struct MapInfo
{
  double resolution = 0.05;  // m/cell
  int width = 0;             // cells along x
  int height = 0;            // cells along y
  Pose2D origin;             // pose of the lower-left corner of cell (0,0) in the map frame
};

struct GridMap
{
  static constexpr int8_t kUnknown = -1;
  static constexpr int8_t kFree = 0;
  static constexpr int8_t kOccupied = 100;

  MapInfo info;
  std::vector<int8_t> data;

  GridMap() = default;
  GridMap(const MapInfo& i, int8_t fill) : info(i), data(static_cast<size_t>(i.width) * i.height, fill) {}

  bool inside(int cx, int cy) const { return cx >= 0 && cy >= 0 && cx < info.width && cy < info.height; }
  size_t index(int cx, int cy) const { return static_cast<size_t>(cy) * info.width + cx; }
  int8_t at(int cx, int cy) const { return data[index(cx, cy)]; }
  int8_t& at(int cx, int cy) { return data[index(cx, cy)]; }

  // Cell containing a map-frame point (honours origin yaw); false if outside.
  bool worldToCell(double wx, double wy, int& cx, int& cy) const;
  // Map-frame coordinates of a cell centre.
  Point2D cellCenter(int cx, int cy) const;
};

}  // namespace mybot_navigation
