#include "mybot_nav_common/ray_cast.h"

#include <algorithm>
#include <limits>

namespace mybot_navigation
{

double castRay(const GridMap& map, double x, double y, double angle, double max_range, int occupied_threshold,
               bool unknown_is_obstacle)
{
  // Amanatides-Woo traversal in the map's own frame: exact distance to the first blocked cell's
  // boundary, so simulated ranges are not quantised to cell centres.
  const Point2D s = transformPoint(inverse(map.info.origin), {x, y});
  const double a = angle - map.info.origin.theta;
  const double res = map.info.resolution;
  const double dx = std::cos(a), dy = std::sin(a);
  const double px = s.x / res, py = s.y / res;  // position in cell units
  int cx = static_cast<int>(std::floor(px)), cy = static_cast<int>(std::floor(py));
  const int step_x = dx > 0 ? 1 : -1, step_y = dy > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  const double t_delta_x = dx != 0 ? std::abs(1.0 / dx) : inf;
  const double t_delta_y = dy != 0 ? std::abs(1.0 / dy) : inf;
  double t_max_x = dx != 0 ? ((dx > 0 ? (cx + 1 - px) : (px - cx)) * t_delta_x) : inf;
  double t_max_y = dy != 0 ? ((dy > 0 ? (cy + 1 - py) : (py - cy)) * t_delta_y) : inf;
  const double t_end = max_range / res;
  double t = 0.0;
  const bool started_inside = map.inside(cx, cy);
  while (t <= t_end)
  {
    if (map.inside(cx, cy))
    {
      const int8_t v = map.at(cx, cy);
      if (v >= occupied_threshold || (unknown_is_obstacle && v < 0))
        return std::min(t * res, max_range);
    }
    else if (started_inside)
    {
      break;  // left the map: nothing more to hit
    }
    if (t_max_x < t_max_y)
    {
      t = t_max_x;
      t_max_x += t_delta_x;
      cx += step_x;
    }
    else
    {
      t = t_max_y;
      t_max_y += t_delta_y;
      cy += step_y;
    }
  }
  return max_range;
}

std::vector<float> simulateScan(const GridMap& map, const Pose2D& sensor_pose, double angle_min, double angle_increment,
                                int beams, double max_range)
{
  std::vector<float> ranges(static_cast<size_t>(beams));
  for (int i = 0; i < beams; ++i)
  {
    const double r =
        castRay(map, sensor_pose.x, sensor_pose.y, sensor_pose.theta + angle_min + angle_increment * i, max_range);
    ranges[static_cast<size_t>(i)] = r >= max_range ? std::numeric_limits<float>::infinity() : static_cast<float>(r);
  }
  return ranges;
}

}  // namespace mybot_navigation
