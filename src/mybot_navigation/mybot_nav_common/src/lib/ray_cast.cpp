#include "mybot_nav_common/ray_cast.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

namespace mybot_navigation
{

namespace
{
bool blocked(int8_t v, int occupied_threshold, bool unknown_is_obstacle)
{
  return v >= occupied_threshold || (unknown_is_obstacle && v < 0);
}

// Amanatides-Woo traversal in the map's own frame: the exact distance to the first blocked cell's
// boundary, so simulated ranges are not quantised to cell centres. jump(cell index) says how many
// cells the ray may skip from a free cell without passing through a blocked one; from a jump of
// two cells or more, the traversal lands there and restarts from the cell it lands in.
template <class Blocked, class Jump>
double traverse(const GridMap& map, double x, double y, double angle, double max_range, Blocked&& is_blocked,
                Jump&& jump)
{
  const Point2D s = transformPoint(inverse(map.info.origin), {x, y});
  const double a = angle - map.info.origin.theta;
  const double res = map.info.resolution;
  const double dx = std::cos(a), dy = std::sin(a);
  const double px = s.x / res, py = s.y / res;  // position in cell units
  int cx = cellIndex(px), cy = cellIndex(py);
  const int step_x = dx > 0 ? 1 : -1, step_y = dy > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  const double t_delta_x = dx != 0 ? std::abs(1.0 / dx) : inf;
  const double t_delta_y = dy != 0 ? std::abs(1.0 / dy) : inf;
  // Ray parameter (cells travelled) at the next x / y cell boundary, from the point at t.
  auto boundaries = [&](double t, double qx, double qy)
  {
    cx = cellIndex(qx);
    cy = cellIndex(qy);
    return std::make_pair(dx != 0 ? t + ((dx > 0 ? (cx + 1 - qx) : (qx - cx)) * t_delta_x) : inf,
                          dy != 0 ? t + ((dy > 0 ? (cy + 1 - qy) : (qy - cy)) * t_delta_y) : inf);
  };
  auto [t_max_x, t_max_y] = boundaries(0.0, px, py);
  const double t_end = max_range / res;
  double t = 0.0;
  const bool started_inside = map.inside(cx, cy);
  constexpr double kMinJump = 2.0;  // cells: shorter jumps cost more than the steps they save
  while (t <= t_end)
  {
    if (map.inside(cx, cy))
    {
      const size_t i = map.index(cx, cy);
      if (is_blocked(map.data[i]))
        return std::min(t * res, max_range);
      const double skip = jump(i);
      if (skip >= kMinJump)
      {
        t += skip;
        std::tie(t_max_x, t_max_y) = boundaries(t, px + dx * t, py + dy * t);
        continue;
      }
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

// Ranges of `beams` rays from a sensor pose, infinity where nothing is hit within max_range.
template <class Cast>
std::vector<float> scanWith(Cast&& cast, const Pose2D& sensor_pose, double angle_min, double angle_increment, int beams,
                            double max_range)
{
  std::vector<float> ranges(static_cast<size_t>(beams));
  for (int i = 0; i < beams; ++i)
  {
    const double r = cast(sensor_pose.x, sensor_pose.y, sensor_pose.theta + angle_min + angle_increment * i, max_range);
    ranges[static_cast<size_t>(i)] = r >= max_range ? std::numeric_limits<float>::infinity() : static_cast<float>(r);
  }
  return ranges;
}
}  // namespace

double castRay(const GridMap& map, double x, double y, double angle, double max_range, int occupied_threshold,
               bool unknown_is_obstacle)
{
  return traverse(
      map, x, y, angle, max_range, [&](int8_t v) { return blocked(v, occupied_threshold, unknown_is_obstacle); },
      [](size_t) { return 0.0; });
}

RayCaster::RayCaster(const GridMap& map, int occupied_threshold, bool unknown_is_obstacle)
    : map_(map), occupied_threshold_(occupied_threshold), unknown_is_obstacle_(unknown_is_obstacle)
{
  // Two-pass chamfer transform with steps 1 and sqrt(2): the octile distance to the nearest
  // blocked cell. An octile distance exceeds the Euclidean one by at most 8.24% (at 22.5
  // degrees), so dividing by 1.0825 leaves a lower bound, which is all a jump needs.
  const int w = map.info.width, h = map.info.height;
  constexpr float kFar = 1e9f;
  const float diag = static_cast<float>(std::sqrt(2.0));
  clearance_.assign(map.data.size(), kFar);
  for (size_t i = 0; i < map.data.size(); ++i)
    if (blocked(map.data[i], occupied_threshold, unknown_is_obstacle))
      clearance_[i] = 0.0f;
  auto at = [&](int x, int y) -> float& { return clearance_[static_cast<size_t>(y) * w + x]; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
    {
      float& d = at(x, y);
      if (x > 0)
        d = std::min(d, at(x - 1, y) + 1.0f);
      if (y > 0)
      {
        d = std::min(d, at(x, y - 1) + 1.0f);
        if (x > 0)
          d = std::min(d, at(x - 1, y - 1) + diag);
        if (x + 1 < w)
          d = std::min(d, at(x + 1, y - 1) + diag);
      }
    }
  for (int y = h - 1; y >= 0; --y)
    for (int x = w - 1; x >= 0; --x)
    {
      float& d = at(x, y);
      if (x + 1 < w)
        d = std::min(d, at(x + 1, y) + 1.0f);
      if (y + 1 < h)
      {
        d = std::min(d, at(x, y + 1) + 1.0f);
        if (x + 1 < w)
          d = std::min(d, at(x + 1, y + 1) + diag);
        if (x > 0)
          d = std::min(d, at(x - 1, y + 1) + diag);
      }
    }
  for (float& d : clearance_)
    d /= 1.0825f;
}

double RayCaster::cast(double x, double y, double angle, double max_range) const
{
  // In a cell whose centre is at least c cells from every blocked cell's centre, every point of
  // the ray within c - sqrt(2) cells lies outside every blocked cell (each point of a cell is
  // within sqrt(2)/2 of its centre).
  const double reach = std::sqrt(2.0) + 1e-6;
  return traverse(
      map_, x, y, angle, max_range, [this](int8_t v) { return blocked(v, occupied_threshold_, unknown_is_obstacle_); },
      [&](size_t i) { return clearance_[i] - reach; });
}

std::vector<float> RayCaster::scan(const Pose2D& sensor_pose, double angle_min, double angle_increment, int beams,
                                   double max_range) const
{
  return scanWith([this](double x, double y, double a, double r) { return cast(x, y, a, r); }, sensor_pose, angle_min,
                  angle_increment, beams, max_range);
}

std::vector<float> simulateScan(const GridMap& map, const Pose2D& sensor_pose, double angle_min, double angle_increment,
                                int beams, double max_range)
{
  return scanWith([&map](double x, double y, double a, double r) { return castRay(map, x, y, a, r); }, sensor_pose,
                  angle_min, angle_increment, beams, max_range);
}

}  // namespace mybot_navigation
