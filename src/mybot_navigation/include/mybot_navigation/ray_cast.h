// Grid ray traversal (Bresenham) and range casting against a static map.
#pragma once

#include <cmath>
#include <cstdlib>
#include <vector>

#include "mybot_navigation/grid_map.h"

namespace mybot_navigation
{

// Visits every cell on the line from (x0,y0) to (x1,y1), both included, in order.
// The visitor returns false to stop early.
template <typename Visitor>
void traceLine(int x0, int y0, int x1, int y1, Visitor&& visit)
{
  const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
  const int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
  int err = dx + dy;
  while (true)
  {
    if (!visit(x0, y0))
      return;
    if (x0 == x1 && y0 == y1)
      return;
    const int e2 = 2 * err;
    if (e2 >= dy)
    {
      err += dy;
      x0 += sx;
    }
    if (e2 <= dx)
    {
      err += dx;
      y0 += sy;
    }
  }
}

// Range along a ray from a map-frame point until the first cell with value >= occupied_threshold
// (or unknown if unknown_is_obstacle). Returns max_range if nothing is hit or the map ends.
double castRay(const GridMap& map, double x, double y, double angle, double max_range,
               int occupied_threshold = 50, bool unknown_is_obstacle = false);

// A simulated laser scan (ranges in the sensor frame) from a pose in the map.
std::vector<float> simulateScan(const GridMap& map, const Pose2D& sensor_pose, double angle_min,
                                double angle_increment, int beams, double max_range);

}  // namespace mybot_navigation
