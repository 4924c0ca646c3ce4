#include "mybot_move_base/costmap.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "mybot_nav_common/costmap_distance.h"
#include "mybot_nav_common/ray_cast.h"

namespace mybot_navigation
{

std::string validate(const CostmapParams& p)
{
  std::ostringstream e;
  if (!(p.resolution > 0.0))
    e << "resolution must be > 0 (got " << p.resolution << ")";
  else if (p.rolling_window && !(p.width > p.resolution && p.height > p.resolution))
    e << "width and height must be larger than the resolution for a rolling window";
  else if (p.footprint.empty() && !(p.robot_radius > 0.0))
    e << "robot_radius must be > 0 when no footprint is given (got " << p.robot_radius << ")";
  else if (!p.footprint.empty() && p.footprint.size() < 3)
    e << "footprint needs at least 3 points (got " << p.footprint.size() << ")";
  else if (p.inflation_radius < 0.0)
    e << "inflation_radius must be >= 0 (got " << p.inflation_radius << ")";
  else if (p.cost_scaling_factor < 0.0)
    e << "cost_scaling_factor must be >= 0 (got " << p.cost_scaling_factor << ")";
  else if (p.obstacle_range < 0.0 || p.raytrace_range < 0.0)
    e << "obstacle_range and raytrace_range must be >= 0";
  else if (p.lethal_cost_threshold < 1 || p.lethal_cost_threshold > 100)
    e << "lethal_cost_threshold must be in [1, 100] (got " << p.lethal_cost_threshold << ")";
  return e.str();
}

std::vector<Point2D> paddedFootprint(const CostmapParams& p)
{
  std::vector<Point2D> out;
  if (p.footprint.size() >= 3)
  {
    // costmap_2d's padFootprint: push every vertex outwards by the padding along each axis.
    for (const Point2D& q : p.footprint)
      out.push_back({q.x + (q.x > 0   ? p.footprint_padding
                            : q.x < 0 ? -p.footprint_padding
                                      : 0.0),
                     q.y + (q.y > 0   ? p.footprint_padding
                            : q.y < 0 ? -p.footprint_padding
                                      : 0.0)});
    return out;
  }
  const double r = p.robot_radius + p.footprint_padding;
  for (int i = 0; i < 16; ++i)
  {
    const double a = 2.0 * M_PI * i / 16;
    out.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return out;
}

namespace
{
double pointSegmentDistance(const Point2D& p, const Point2D& a, const Point2D& b)
{
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double l2 = dx * dx + dy * dy;
  double t = l2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / l2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

}  // namespace

double inscribedRadius(const std::vector<Point2D>& polygon)
{
  double r = 1e9;
  for (size_t i = 0; i < polygon.size(); ++i)
    r = std::min(r, pointSegmentDistance({0, 0}, polygon[i], polygon[(i + 1) % polygon.size()]));
  return polygon.empty() ? 0.0 : r;
}

double circumscribedRadius(const std::vector<Point2D>& polygon)
{
  double r = 0.0;
  for (const Point2D& q : polygon)
    r = std::max(r, std::hypot(q.x, q.y));
  return r;
}

Costmap::Costmap(const CostmapParams& params) : params_(params)
{
  footprint_ = paddedFootprint(params_);
  inscribed_ = mybot_navigation::inscribedRadius(footprint_);
  circumscribed_ = mybot_navigation::circumscribedRadius(footprint_);
  if (params_.rolling_window)
  {
    MapInfo info;
    info.resolution = params_.resolution;
    info.width = std::max(1, static_cast<int>(std::round(params_.width / params_.resolution)));
    info.height = std::max(1, static_cast<int>(std::round(params_.height / params_.resolution)));
    origin_ix_ = -info.width / 2;
    origin_iy_ = -info.height / 2;
    info.origin = {origin_ix_ * info.resolution, origin_iy_ * info.resolution, 0.0};
    resize(info);
  }
}

void Costmap::resize(const MapInfo& info)
{
  info_ = info;
  const size_t n = static_cast<size_t>(info_.width) * info_.height;
  const uint8_t unknown = params_.track_unknown_space ? costs::kNoInformation : costs::kFree;
  static_.assign(n, unknown);
  obstacles_.assign(n, 0);
  master_.assign(n, unknown);
  markDirty(0, 0, info_.width - 1, info_.height - 1);
}

uint8_t Costmap::staticCostFromMap(int8_t value) const
{
  if (value < 0)
    return params_.track_unknown_space ? costs::kNoInformation : costs::kFree;
  if (value >= params_.lethal_cost_threshold)
    return costs::kLethal;
  return costs::kFree;  // costmap_2d's trinary_costmap default
}

void Costmap::setStaticMap(const GridMap& map)
{
  static_map_ = map;
  has_static_ = true;
  if (!params_.rolling_window)
  {
    MapInfo info = map.info;
    resize(info);
  }
  refreshStaticLayer();
  updateCosts();  // the master grid is never stale for a planner that runs right away
}

void Costmap::refreshStaticLayer()
{
  if (!params_.use_static_map || !has_static_)
    return;
  if (!params_.rolling_window)
  {
    for (size_t i = 0; i < static_.size(); ++i)
      static_[i] = staticCostFromMap(static_map_.data[i]);
  }
  else
  {
    const uint8_t outside = params_.track_unknown_space ? costs::kNoInformation : costs::kFree;
    for (int y = 0; y < info_.height; ++y)
      for (int x = 0; x < info_.width; ++x)
      {
        const Point2D w = mapToWorld(x, y);
        int mx, my;
        static_[idx(x, y)] =
            static_map_.worldToCell(w.x, w.y, mx, my) ? staticCostFromMap(static_map_.at(mx, my)) : outside;
      }
  }
  markDirty(0, 0, info_.width - 1, info_.height - 1);
}

void Costmap::updateOrigin(double robot_x, double robot_y)
{
  if (!params_.rolling_window)
    return;
  const double res = info_.resolution;
  // Snap the origin to the cell lattice so cells keep their world positions when shifted.
  const int ix = cellIndex(robot_x / res) - info_.width / 2;
  const int iy = cellIndex(robot_y / res) - info_.height / 2;
  const int shift_x = ix - origin_ix_, shift_y = iy - origin_iy_;
  if (shift_x == 0 && shift_y == 0 && info_.origin.x == ix * res && info_.origin.y == iy * res)
    return;
  std::vector<uint8_t> moved(obstacles_.size(), 0);
  for (int y = 0; y < info_.height; ++y)
    for (int x = 0; x < info_.width; ++x)
    {
      const int sx = x + shift_x, sy = y + shift_y;
      if (inside(sx, sy))
        moved[idx(x, y)] = obstacles_[idx(sx, sy)];
    }
  obstacles_.swap(moved);
  origin_ix_ = ix;
  origin_iy_ = iy;
  info_.origin = {ix * res, iy * res, 0.0};
  refreshStaticLayer();
}

bool Costmap::worldToMap(double wx, double wy, int& cx, int& cy) const
{
  cx = cellIndex((wx - info_.origin.x) / info_.resolution);
  cy = cellIndex((wy - info_.origin.y) / info_.resolution);
  if (info_.origin.theta != 0.0)
  {
    const Point2D l = transformPoint(inverse(info_.origin), {wx, wy});
    cx = cellIndex(l.x / info_.resolution);
    cy = cellIndex(l.y / info_.resolution);
  }
  return inside(cx, cy);
}

Point2D Costmap::mapToWorld(int cx, int cy) const
{
  return transformPoint(info_.origin, {(cx + 0.5) * info_.resolution, (cy + 0.5) * info_.resolution});
}

uint8_t Costmap::costAt(double wx, double wy) const
{
  int cx, cy;
  return worldToMap(wx, wy, cx, cy) ? cost(cx, cy) : costs::kNoInformation;
}

void Costmap::markDirty(int x0, int y0, int x1, int y1)
{
  if (!dirty_ || dirty_x1_ < dirty_x0_)
  {
    dirty_x0_ = x0;
    dirty_y0_ = y0;
    dirty_x1_ = x1;
    dirty_y1_ = y1;
  }
  else
  {
    dirty_x0_ = std::min(dirty_x0_, x0);
    dirty_y0_ = std::min(dirty_y0_, y0);
    dirty_x1_ = std::max(dirty_x1_, x1);
    dirty_y1_ = std::max(dirty_y1_, y1);
  }
  dirty_ = true;
}

void Costmap::updateWithScan(const Point2D& sensor, const std::vector<Point2D>& hits,
                             const std::vector<Point2D>& free_ends)
{
  if (!params_.use_obstacles || info_.width == 0)
    return;
  int sx, sy;
  if (!worldToMap(sensor.x, sensor.y, sx, sy))
    return;  // costmap_2d also refuses to raytrace from outside the grid
  int bx0 = sx, by0 = sy, bx1 = sx, by1 = sy;
  const double res = info_.resolution;
  auto clearRay = [&](const Point2D& end, bool keep_end)
  {
    double dx = end.x - sensor.x, dy = end.y - sensor.y;
    const double len = std::hypot(dx, dy);
    if (len > params_.raytrace_range && len > 0)
    {
      dx *= params_.raytrace_range / len;
      dy *= params_.raytrace_range / len;
      keep_end = false;
    }
    // Cells in the local lattice (handles a rotated origin through worldToMap's maths).
    const Point2D l0 = transformPoint(inverse(info_.origin), sensor);
    const Point2D l1 = transformPoint(inverse(info_.origin), {sensor.x + dx, sensor.y + dy});
    const int ex = cellIndex(l1.x / res), ey = cellIndex(l1.y / res);
    traceLine(cellIndex(l0.x / res), cellIndex(l0.y / res), ex, ey,
              [&](int x, int y)
              {
                if (!inside(x, y))
                  return false;
                if (keep_end && x == ex && y == ey)
                  return false;
                obstacles_[idx(x, y)] = 0;
                bx0 = std::min(bx0, x);
                by0 = std::min(by0, y);
                bx1 = std::max(bx1, x);
                by1 = std::max(by1, y);
                return true;
              });
  };
  for (const Point2D& e : free_ends)
    clearRay(e, false);
  for (const Point2D& h : hits)
    clearRay(h, true);
  for (const Point2D& h : hits)
  {
    if (std::hypot(h.x - sensor.x, h.y - sensor.y) > params_.obstacle_range)
      continue;
    int cx, cy;
    if (!worldToMap(h.x, h.y, cx, cy))
      continue;
    obstacles_[idx(cx, cy)] = 1;
    bx0 = std::min(bx0, cx);
    by0 = std::min(by0, cy);
    bx1 = std::max(bx1, cx);
    by1 = std::max(by1, cy);
  }
  markDirty(bx0, by0, bx1, by1);
}

void Costmap::clearObstaclesOutside(double x, double y, double distance)
{
  for (int cy = 0; cy < info_.height; ++cy)
    for (int cx = 0; cx < info_.width; ++cx)
    {
      if (!obstacles_[idx(cx, cy)])
        continue;
      const Point2D w = mapToWorld(cx, cy);
      if (distance < 0 || std::hypot(w.x - x, w.y - y) > distance)
        obstacles_[idx(cx, cy)] = 0;
    }
  markDirty(0, 0, info_.width - 1, info_.height - 1);
}

void Costmap::clearFootprint(const Pose2D& pose)
{
  if (!params_.use_obstacles || !params_.footprint_clearing_enabled || info_.width == 0)
    return;
  // Every cell the outline passes through (as polygonCost sees it) and every cell whose centre is
  // inside the polygon.
  const double res = info_.resolution;
  const Pose2D inv = inverse(info_.origin);
  std::vector<Point2D> poly;
  for (const Point2D& q : footprint_)
    poly.push_back(transformPoint(inv, transformPoint(pose, q)));
  double x0 = 1e18, y0 = 1e18, x1 = -1e18, y1 = -1e18;
  for (const Point2D& q : poly)
    x0 = std::min(x0, q.x), y0 = std::min(y0, q.y), x1 = std::max(x1, q.x), y1 = std::max(y1, q.y);
  const int cx0 = std::max(0, cellIndex(x0 / res)), cy0 = std::max(0, cellIndex(y0 / res));
  const int cx1 = std::min(info_.width - 1, cellIndex(x1 / res));
  const int cy1 = std::min(info_.height - 1, cellIndex(y1 / res));
  if (cx0 > cx1 || cy0 > cy1)
    return;
  bool changed = false;
  auto clear = [&](int x, int y)
  {
    if (inside(x, y) && obstacles_[idx(x, y)])
    {
      obstacles_[idx(x, y)] = 0;
      changed = true;
    }
    return true;
  };
  for (size_t i = 0; i < poly.size(); ++i)
  {
    const Point2D& a = poly[i];
    const Point2D& b = poly[(i + 1) % poly.size()];
    traceSegment(a.x / res, a.y / res, b.x / res, b.y / res, clear);
  }
  for (int y = cy0; y <= cy1; ++y)
    for (int x = cx0; x <= cx1; ++x)
    {
      const double px = (x + 0.5) * res, py = (y + 0.5) * res;
      bool in = false;
      for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
        if ((poly[i].y > py) != (poly[j].y > py) &&
            px < (poly[j].x - poly[i].x) * (py - poly[i].y) / (poly[j].y - poly[i].y) + poly[i].x)
          in = !in;
      if (in)
        clear(x, y);
    }
  if (changed)
    markDirty(cx0, cy0, cx1, cy1);
}

void Costmap::reset()
{
  std::fill(obstacles_.begin(), obstacles_.end(), 0);
  refreshStaticLayer();
  markDirty(0, 0, info_.width - 1, info_.height - 1);
}

uint8_t Costmap::inflationCost(double distance) const
{
  if (distance <= 0.0)
    return costs::kLethal;
  if (distance <= inscribed_)
    return costs::kInscribed;
  if (distance > params_.inflation_radius)
    return costs::kFree;
  const double factor = std::exp(-params_.cost_scaling_factor * (distance - inscribed_));
  return static_cast<uint8_t>((costs::kInscribed - 1) * factor);
}

void Costmap::updateCosts()
{
  if (!dirty_ || info_.width == 0)
    return;
  const double res = info_.resolution;
  const int r_cells = static_cast<int>(std::ceil(params_.inflation_radius / res)) + 1;
  // Cells whose cost can change, and the larger window whose lethal cells can influence them.
  const int x0 = std::max(0, dirty_x0_ - r_cells), y0 = std::max(0, dirty_y0_ - r_cells);
  const int x1 = std::min(info_.width - 1, dirty_x1_ + r_cells), y1 = std::min(info_.height - 1, dirty_y1_ + r_cells);
  const int wx0 = std::max(0, x0 - r_cells), wy0 = std::max(0, y0 - r_cells);
  const int wx1 = std::min(info_.width - 1, x1 + r_cells), wy1 = std::min(info_.height - 1, y1 + r_cells);
  const int ww = wx1 - wx0 + 1, wh = wy1 - wy0 + 1;
  std::vector<uint8_t> seed(static_cast<size_t>(ww) * wh);
  for (int y = wy0; y <= wy1; ++y)
    for (int x = wx0; x <= wx1; ++x)
      seed[static_cast<size_t>(y - wy0) * ww + (x - wx0)] =
          (static_[idx(x, y)] == costs::kLethal || obstacles_[idx(x, y)]) ? 1 : 0;
  const std::vector<float> dist = distanceTransform(seed, ww, wh);
  // Cost lookup by squared cell distance keeps exp() out of the loop.
  const int max_d2 = r_cells * r_cells;
  std::vector<uint8_t> lut(static_cast<size_t>(max_d2) + 1);
  for (int d2 = 0; d2 <= max_d2; ++d2)
    lut[static_cast<size_t>(d2)] = inflationCost(std::sqrt(static_cast<double>(d2)) * res);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
    {
      const float d = dist[static_cast<size_t>(y - wy0) * ww + (x - wx0)];
      uint8_t c = costs::kFree;
      if (d <= r_cells)  // also false for the huge "no obstacle" distance
        c = lut[static_cast<size_t>(std::lround(static_cast<double>(d) * d))];
      const uint8_t s = static_[idx(x, y)];
      if (s == costs::kNoInformation && c == costs::kFree && !obstacles_[idx(x, y)])
        c = costs::kNoInformation;
      master_[idx(x, y)] = c;
    }
  dirty_ = false;
  dirty_x1_ = dirty_x0_ - 1;
}

double Costmap::footprintCost(const Pose2D& pose) const
{
  if (params_.footprint.size() >= 3)
    return polygonCost(pose, footprint_);
  // A circular robot: the inflated cost at its centre says it all.
  int cx, cy;
  if (!worldToMap(pose.x, pose.y, cx, cy))
    return -3.0;
  const uint8_t centre = cost(cx, cy);
  if (centre == costs::kLethal || centre == costs::kInscribed)
    return -1.0;
  if (centre == costs::kNoInformation)
    return params_.track_unknown_space ? -2.0 : 0.0;
  return centre;
}

double Costmap::polygonCost(const Pose2D& pose, const std::vector<Point2D>& polygon) const
{
  int cx, cy;
  if (!worldToMap(pose.x, pose.y, cx, cy))
    return -3.0;
  const uint8_t centre = cost(cx, cy);
  if (centre == costs::kLethal)
    return -1.0;
  if (centre == costs::kNoInformation && params_.track_unknown_space)
    return -2.0;
  double worst = centre == costs::kNoInformation ? 0.0 : centre;
  const double res = info_.resolution;
  const Pose2D inv = inverse(info_.origin);
  for (size_t i = 0; i < polygon.size(); ++i)
  {
    const Point2D a = transformPoint(inv, transformPoint(pose, polygon[i]));
    const Point2D b = transformPoint(inv, transformPoint(pose, polygon[(i + 1) % polygon.size()]));
    bool hit = false, unknown = false;
    // Every cell the edge itself passes through. A line between the end points' cells
    // (costmap_2d's) strays up to a cell off the edge, so along a shelf face a pose and the next
    // few flip between touching and not, and a robot standing there had every move rejected
    // although its own pose passed (the factory demo's stalls at shelf ends).
    traceSegment(a.x / res, a.y / res, b.x / res, b.y / res,
                 [&](int x, int y)
                 {
                   if (!inside(x, y))
                     return !(hit = true);
                   const uint8_t c = cost(x, y);
                   if (c == costs::kLethal)
                     return !(hit = true);
                   if (c == costs::kNoInformation)
                     unknown = unknown || params_.track_unknown_space;
                   else
                     worst = std::max(worst, static_cast<double>(c));
                   return true;
                 });
    if (hit)
      return -1.0;
    if (unknown)
      return -2.0;
  }
  return worst;
}

std::vector<Point2D> Costmap::footprintClearing(const Pose2D& pose, double max_shrink) const
{
  for (int step = 1; step <= 3; ++step)
  {
    std::vector<Point2D> candidate;
    for (const Point2D& v : footprint_)
    {
      const double r = std::hypot(v.x, v.y);
      const double k = r > 0.0 ? std::max(0.0, r - step * max_shrink / 3.0 * std::sqrt(2.0)) / r : 0.0;
      candidate.push_back({v.x * k, v.y * k});
    }
    if (polygonCost(pose, candidate) >= 0)
      return candidate;
  }
  return {};
}

std::vector<int8_t> Costmap::toOccupancyValues() const
{
  std::vector<int8_t> out(master_.size());
  for (size_t i = 0; i < master_.size(); ++i)
  {
    const uint8_t c = master_[i];
    if (c == costs::kNoInformation)
      out[i] = -1;
    else if (c == costs::kLethal)
      out[i] = 100;
    else if (c == costs::kInscribed)
      out[i] = 99;
    else if (c == 0)
      out[i] = 0;
    else
      out[i] = static_cast<int8_t>(1 + (97 * (c - 1)) / 251);
  }
  return out;
}

}  // namespace mybot_navigation
