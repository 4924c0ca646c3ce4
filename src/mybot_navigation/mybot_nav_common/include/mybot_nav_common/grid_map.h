// A static occupancy map in nav_msgs/OccupancyGrid semantics (row-major, cell (0,0) at the
// lower-left corner `origin`, values 0..100 or -1 unknown), without ROS types.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "mybot_nav_common/pose2d.h"

namespace mybot_navigation
{

// floor(v) as a cell index, v in cells. Beyond +-2^28 cells (13000 km at 5 cm, far off any grid)
// it is held there, and NaN is taken as -2^28: a point that an absurd but finite range puts 1e30 m
// away is a cell off the grid, not an out-of-range conversion to int (undefined behaviour; x86
// gives INT_MIN, and the differences a traversal takes of two such overflow). Held at 2^28, the
// sum of four differences still fits an int.
inline int cellIndex(double v)
{
  constexpr double kFar = 1 << 28;
  if (v >= -kFar && v <= kFar)
    return static_cast<int>(std::floor(v));
  return v > 0 ? static_cast<int>(kFar) : -static_cast<int>(kFar);
}

// One 64-bit key for a cell, for hashing sparse cells: x in the high half, y in the low. Built
// unsigned: shifting a negative signed value is undefined before C++20 (UBSan saw it on the
// Intel log's scans, whose points lie on both sides of zero).
inline std::uint64_t cellKey(int cx, int cy)
{
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(cx)) << 32) | static_cast<std::uint32_t>(cy);
}

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
