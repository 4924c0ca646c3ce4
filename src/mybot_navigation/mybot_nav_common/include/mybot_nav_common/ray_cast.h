// Grid traversal (Bresenham between cells; exact for segments) and range casting against a static map.
#pragma once

#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

#include "mybot_nav_common/grid_map.h"

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

// Visits every cell a segment given in cell units (x / resolution) passes through, however little
// of it, in order from the first end (Amanatides & Woo); traceLine's Bresenham line between the
// end cells strays up to a cell off the true segment. The visitor gets the cell and where the
// segment enters it, as a fraction of its length (0 for the first cell), and returns false to
// stop early. A segment with a non-finite end visits nothing; one that reaches beyond 2^28 cells
// (cellIndex) is walked to its end cell there, so the visitor must stop where its grid ends.
template <class Visit>
void traceSegmentEntries(double x0, double y0, double x1, double y1, Visit&& visit)
{
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (!(std::isfinite(x0) && std::isfinite(y0) && std::isfinite(x1) && std::isfinite(y1)))
    return;  // no segment: nothing is crossed
  int x = cellIndex(x0), y = cellIndex(y0);
  const int x_end = cellIndex(x1), y_end = cellIndex(y1);
  const double dx = x1 - x0, dy = y1 - y0;
  const int sx = dx > 0 ? 1 : -1, sy = dy > 0 ? 1 : -1;
  // Parameter t (0..1 along the segment) per cell crossed, and at the next x / y cell boundary.
  const double t_dx = dx != 0 ? std::abs(1.0 / dx) : kInf, t_dy = dy != 0 ? std::abs(1.0 / dy) : kInf;
  double t_x = dx > 0 ? (x + 1 - x0) * t_dx : dx < 0 ? (x0 - x) * t_dx : kInf;
  double t_y = dy > 0 ? (y + 1 - y0) * t_dy : dy < 0 ? (y0 - y) * t_dy : kInf;
  if (!visit(x, y, 0.0))
    return;
  for (int steps = std::abs(x_end - x) + std::abs(y_end - y); steps > 0; --steps)
  {
    double t;
    if (t_x < t_y)
    {
      t = t_x;
      t_x += t_dx, x += sx;
    }
    else
    {
      t = t_y;
      t_y += t_dy, y += sy;
    }
    if (!visit(x, y, t))
      return;
  }
}

// traceSegmentEntries for a visitor of cells only.
template <class Visit>
void traceSegment(double x0, double y0, double x1, double y1, Visit&& visit)
{
  traceSegmentEntries(x0, y0, x1, y1, [&visit](int x, int y, double) { return visit(x, y); });
}

// Range along a ray from a map-frame point until the first cell with value >= occupied_threshold
// (or unknown if unknown_is_obstacle). Returns max_range if nothing is hit or the map ends.
double castRay(const GridMap& map, double x, double y, double angle, double max_range, int occupied_threshold = 50,
               bool unknown_is_obstacle = false);

// A simulated laser scan (ranges in the sensor frame) from a pose in the map.
std::vector<float> simulateScan(const GridMap& map, const Pose2D& sensor_pose, double angle_min, double angle_increment,
                                int beams, double max_range);

// castRay for many rays into one map that does not change: the same traversal, but where the
// map says no blocked cell is near, it jumps along the ray instead of stepping cell by cell
// (sphere tracing on a distance field). A 30 m beam through the 50 m factory crosses up to 600
// cells, and synthetic scans cost the SLAM tests most of their time. Ranges equal castRay's up
// to rounding (the traversal restarts after a jump; test_ray_cast compares them). The map must
// outlive the caster.
class RayCaster
{
public:
  explicit RayCaster(const GridMap& map, int occupied_threshold = 50, bool unknown_is_obstacle = false);
  double cast(double x, double y, double angle, double max_range) const;
  std::vector<float> scan(const Pose2D& sensor_pose, double angle_min, double angle_increment, int beams,
                          double max_range) const;

private:
  const GridMap& map_;
  int occupied_threshold_;
  bool unknown_is_obstacle_;
  // Per cell, in cells: a lower bound of the distance from its centre to the nearest blocked
  // cell's centre (huge if there is none).
  std::vector<float> clearance_;
};

}  // namespace mybot_navigation
