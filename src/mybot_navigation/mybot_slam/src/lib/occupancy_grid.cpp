#include "mybot_slam/occupancy_grid.h"

#include <algorithm>
#include <cmath>

#include "mybot_nav_common/ray_cast.h"

namespace mybot_navigation
{
namespace
{
float logit(double p)
{
  return static_cast<float>(std::log(p / (1.0 - p)));
}
}  // namespace

OccupancyGrid::OccupancyGrid(const OccupancyGridParams& params)
    : params_(params),
      l_hit_(logit(params.prob_hit)),
      l_miss_(logit(params.prob_miss)),
      l_min_(logit(params.prob_min)),
      l_max_(logit(params.prob_max))
{
}

void OccupancyGrid::clear()
{
  min_x_ = min_y_ = width_ = height_ = 0;
  cells_.clear();
  stamp_.clear();
  scan_count_ = 0;
}

double OccupancyGrid::probability(int gx, int gy) const
{
  const double l = logOdds(gx, gy);
  return 1.0 - 1.0 / (1.0 + std::exp(l));
}

void OccupancyGrid::growToContain(int gx0, int gy0, int gx1, int gy1)
{
  if (width_ > 0 && contains(gx0, gy0) && contains(gx1, gy1))
    return;
  const int margin = static_cast<int>(std::ceil(params_.grow_margin / params_.resolution));
  int nx0 = gx0, ny0 = gy0, nx1 = gx1, ny1 = gy1;  // inclusive
  if (width_ > 0)
  {
    // Grow only the sides that need it, with a margin so growth is amortised.
    nx0 = gx0 < min_x_ ? gx0 - margin : min_x_;
    ny0 = gy0 < min_y_ ? gy0 - margin : min_y_;
    nx1 = gx1 >= min_x_ + width_ ? gx1 + margin : min_x_ + width_ - 1;
    ny1 = gy1 >= min_y_ + height_ ? gy1 + margin : min_y_ + height_ - 1;
  }
  else
  {
    nx0 -= margin;
    ny0 -= margin;
    nx1 += margin;
    ny1 += margin;
  }
  const int nw = nx1 - nx0 + 1, nh = ny1 - ny0 + 1;
  std::vector<float> cells(static_cast<size_t>(nw) * nh, 0.0f);
  std::vector<uint32_t> stamp(cells.size(), 0u);
  for (int y = 0; y < height_; ++y)
  {
    const size_t src = static_cast<size_t>(y) * width_;
    const size_t dst = static_cast<size_t>(y + min_y_ - ny0) * nw + (min_x_ - nx0);
    std::copy_n(cells_.begin() + src, width_, cells.begin() + dst);
    std::copy_n(stamp_.begin() + src, width_, stamp.begin() + dst);
  }
  cells_.swap(cells);
  stamp_.swap(stamp);
  min_x_ = nx0;
  min_y_ = ny0;
  width_ = nw;
  height_ = nh;
}

void OccupancyGrid::reserve(const Point2D& lo, const Point2D& hi)
{
  growToContain(worldToLattice(lo.x), worldToLattice(lo.y), worldToLattice(hi.x), worldToLattice(hi.y));
}

void OccupancyGrid::update(int gx, int gy, float delta)
{
  const size_t i = idx(gx, gy);
  if (stamp_[i] == scan_count_)
    return;
  stamp_[i] = scan_count_;
  cells_[i] = std::clamp(cells_[i] + delta, l_min_, l_max_);
}

namespace
{
// How many cells before a hit its beam may not clear: 1 / sin of the angle between the beam and
// the surface through its neighbours a and b (capped at kMaxKeepCells), or 1 (the hit's own cell)
// where the neighbours are too far apart to lie on the hit's surface.
double grazingKeepCells(const Point2D& origin, const Point2D& a, const Point2D& h, const Point2D& b)
{
  constexpr double kMaxKeepCells = 20.0;
  const double sx = b.x - a.x, sy = b.y - a.y, sl = std::hypot(sx, sy);
  const double rx = h.x - origin.x, ry = h.y - origin.y, rl = std::hypot(rx, ry);
  // Beams 0.25 deg apart meet a surface at 5 degrees 0.05 * r apart: a gap of more than 0.1 m
  // plus 0.15 * r is an edge or another object.
  if (sl < 1e-6 || rl < 1e-6 || sl > 0.1 + 0.15 * rl)
    return 1.0;
  const double sin_angle = std::abs(sx * ry - sy * rx) / (sl * rl);
  return std::min(kMaxKeepCells, 1.0 / std::max(sin_angle, 1.0 / kMaxKeepCells));
}
}  // namespace

void OccupancyGrid::insertScan(const Pose2D& pose, const RangeScan& scan)
{
  const Point2D o = transformPoint(pose, scan.origin);
  const int ox = worldToLattice(o.x), oy = worldToLattice(o.y);
  std::vector<std::pair<int, int>> hits, misses;
  hits.reserve(scan.hits.size());
  misses.reserve(scan.misses.size());
  int x0 = ox, y0 = oy, x1 = ox, y1 = oy;
  auto add = [&](const std::vector<Point2D>& pts, std::vector<std::pair<int, int>>& out)
  {
    for (const Point2D& p : pts)
    {
      const Point2D w = transformPoint(pose, p);
      const int gx = worldToLattice(w.x), gy = worldToLattice(w.y);
      out.emplace_back(gx, gy);
      x0 = std::min(x0, gx);
      y0 = std::min(y0, gy);
      x1 = std::max(x1, gx);
      y1 = std::max(y1, gy);
    }
  };
  add(scan.hits, hits);
  add(scan.misses, misses);
  growToContain(x0, y0, x1, y1);
  ++scan_count_;
  for (const auto& h : hits)
    update(h.first, h.second, l_hit_);
  auto free_ray = [&](const std::pair<int, int>& end, bool include_end)
  {
    traceLine(ox, oy, end.first, end.second,
              [&](int x, int y)
              {
                if (!include_end && x == end.first && y == end.second)
                  return false;
                update(x, y, l_miss_);
                return true;
              });
  };
  // A beam that meets a surface at a grazing angle runs within a cell of it for the last
  // 1 / sin(angle) cells of its length, through the surface's own cells: that is no evidence
  // that they are free, and counting it erased walls seen only from far along them (in the demo,
  // a rack's face; AMCL then put the robot on the rack's far face, 0.8 m off, and the scan
  // matcher's local maps lost the walls that hold the heading). With keep_grazing_surfaces those
  // cells are left alone; the surface's direction at a hit comes from its two neighbours in the
  // scan.
  for (size_t i = 0; i < hits.size(); ++i)
  {
    const double keep = params_.keep_grazing_surfaces && i > 0 && i + 1 < hits.size()
                            ? grazingKeepCells(scan.origin, scan.hits[i - 1], scan.hits[i], scan.hits[i + 1])
                            : 1.0;
    const auto& end = hits[i];
    traceLine(ox, oy, end.first, end.second,
              [&](int x, int y)
              {
                const double dx = x - end.first, dy = y - end.second;
                if (dx * dx + dy * dy < keep * keep)
                  return false;
                update(x, y, l_miss_);
                return true;
              });
  }
  for (const auto& m : misses)
    free_ray(m, true);
}

GridMap OccupancyGrid::toGridMap(double occ_thresh) const
{
  MapInfo info;
  info.resolution = params_.resolution;
  info.width = width_;
  info.height = height_;
  info.origin = {min_x_ * params_.resolution, min_y_ * params_.resolution, 0.0};
  GridMap map(info, GridMap::kUnknown);
  const float l_occ = logit(std::clamp(occ_thresh, 1e-6, 1.0 - 1e-6));
  for (size_t i = 0; i < cells_.size(); ++i)
  {
    if (stamp_[i] == 0)
      continue;
    map.data[i] = cells_[i] > l_occ ? GridMap::kOccupied : GridMap::kFree;
  }
  return map;
}

}  // namespace mybot_navigation
