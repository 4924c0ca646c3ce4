#include "mybot_slam/scan_matcher.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <unordered_set>

#include <Eigen/Dense>

namespace mybot_navigation
{

MatchField::MatchField(const OccupancyGrid& grid, double sigma, int levels)
    : MatchField(grid, sigma, levels, grid.minCellX(), grid.minCellY(), grid.minCellX() + grid.width() - 1,
                 grid.minCellY() + grid.height() - 1)
{
}

MatchField::MatchField(const OccupancyGrid& grid, double sigma, int levels, int x0, int y0, int x1, int y1,
                       double unobserved_weight)
{
  resolution_ = grid.resolution();
  x0 = std::max(x0, grid.minCellX());
  y0 = std::max(y0, grid.minCellY());
  x1 = std::min(x1, grid.minCellX() + grid.width() - 1);
  y1 = std::min(y1, grid.minCellY() + grid.height() - 1);
  std::vector<std::pair<int, int>> occupied;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      if (grid.logOdds(x, y) > 0.0f)
        occupied.emplace_back(x, y);
  splat(occupied, x0, y0, x1, y1, sigma, levels);
  if (unobserved_weight < 1.0 && !levels_.empty())
  {
    std::vector<uint8_t>& base = levels_[0];
    for (int y = 0; y < height_; ++y)
      for (int x = 0; x < width_; ++x)
      {
        uint8_t& v = base[static_cast<size_t>(y) * width_ + x];
        if (v > 0 && grid.logOdds(x + min_x_, y + min_y_) == 0.0f)
          v = static_cast<uint8_t>(v * unobserved_weight);
      }
  }
  pool(levels);
}

MatchField::MatchField(const GridMap& map, double sigma, int levels, int occupied_threshold)
{
  resolution_ = map.info.resolution;
  const int ox = static_cast<int>(std::lround(map.info.origin.x / resolution_));
  const int oy = static_cast<int>(std::lround(map.info.origin.y / resolution_));
  std::vector<std::pair<int, int>> occupied;
  for (int y = 0; y < map.info.height; ++y)
    for (int x = 0; x < map.info.width; ++x)
      if (map.at(x, y) >= occupied_threshold)
        occupied.emplace_back(x + ox, y + oy);
  splat(occupied, ox, oy, ox + map.info.width - 1, oy + map.info.height - 1, sigma, levels);
  pool(levels);
}

void MatchField::splat(const std::vector<std::pair<int, int>>& occupied, int bx0, int by0, int bx1, int by1,
                       double sigma, int levels)
{
  levels = std::max(1, levels);
  if (bx1 < bx0 || by1 < by0)
    return;
  const double s = std::max(sigma / resolution_, 0.3);  // in cells
  const int radius = static_cast<int>(std::ceil(3.0 * s));
  // Low-side padding so max-pooled levels cover offsets that start before the data.
  const int pad = radius + (1 << (levels - 1));
  min_x_ = bx0 - pad;
  min_y_ = by0 - pad;
  width_ = bx1 - bx0 + 1 + pad + radius;
  height_ = by1 - by0 + 1 + pad + radius;
  const size_t n = static_cast<size_t>(width_) * height_;
  std::vector<uint8_t> base(n, 0);
  std::vector<uint8_t> kernel;
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx)
      kernel.push_back(static_cast<uint8_t>(std::lround(255.0 * std::exp(-(dx * dx + dy * dy) / (2.0 * s * s)))));
  const int kw = 2 * radius + 1;
  for (const auto& c : occupied)
  {
    const int cx = c.first - min_x_, cy = c.second - min_y_;
    for (int dy = -radius; dy <= radius; ++dy)
    {
      uint8_t* row = &base[static_cast<size_t>(cy + dy) * width_];
      const uint8_t* krow = &kernel[static_cast<size_t>(dy + radius) * kw];
      for (int dx = -radius; dx <= radius; ++dx)
        row[cx + dx] = std::max(row[cx + dx], krow[dx + radius]);
    }
  }
  levels_.clear();
  levels_.push_back(std::move(base));
}

void MatchField::pool(int levels)
{
  if (levels_.empty())
    return;
  const size_t n = levels_[0].size();
  // Level h at a cell is the max of level h-1 at the cell and `half` cells right, up, and both:
  // taken as a max along the rows, then of that along the columns (the same values; plain
  // loops the compiler vectorises). Beyond the lattice a level reads nothing, as value() does.
  std::vector<uint8_t> rows(n);
  for (int h = 1; h < levels; ++h)
  {
    const int half = 1 << (h - 1);
    const uint8_t* prev = levels_.back().data();
    for (int y = 0; y < height_; ++y)
    {
      const uint8_t* in = prev + static_cast<size_t>(y) * width_;
      uint8_t* out = rows.data() + static_cast<size_t>(y) * width_;
      const int inner = std::max(0, width_ - half);
      for (int x = 0; x < inner; ++x)
        out[x] = std::max(in[x], in[x + half]);
      for (int x = inner; x < width_; ++x)
        out[x] = in[x];
    }
    std::vector<uint8_t> next(n);
    const int inner_rows = std::max(0, height_ - half);
    const size_t shift = static_cast<size_t>(half) * width_;
    for (size_t i = 0; i < static_cast<size_t>(inner_rows) * width_; ++i)
      next[i] = std::max(rows[i], rows[i + shift]);
    std::copy(rows.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(inner_rows) * width_), rows.end(),
              next.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(inner_rows) * width_));
    levels_.push_back(std::move(next));
  }
}

double MatchField::interpolate(double wx, double wy, double* dfdx, double* dfdy) const
{
  // Cell centres sit at (i + 0.5) * res.
  const double u = wx / resolution_ - 0.5, v = wy / resolution_ - 0.5;
  const int i = cellIndex(u), j = cellIndex(v);
  const double fx = u - i, fy = v - j;
  const double v00 = value(0, i, j), v10 = value(0, i + 1, j), v01 = value(0, i, j + 1), v11 = value(0, i + 1, j + 1);
  if (dfdx)
    *dfdx = ((v10 - v00) * (1 - fy) + (v11 - v01) * fy) / resolution_;
  if (dfdy)
    *dfdy = ((v01 - v00) * (1 - fx) + (v11 - v10) * fx) / resolution_;
  return (v00 * (1 - fx) + v10 * fx) * (1 - fy) + (v01 * (1 - fx) + v11 * fx) * fy;
}

MatchField matchFieldAround(const OccupancyGrid& grid, double sigma, double window, const Pose2D& around, double reach,
                            double unobserved_weight)
{
  const double res = grid.resolution();
  const int levels = matchFieldLevels(window, res);
  // Read: the points' cells shifted by up to the window (matchScan rounds it up to whole cells),
  // the cell beyond for interpolation and refinement (one cell), and the top level's block from
  // there. Contributing: any wall within the fall-off's radius (splat's) of a read cell.
  const int fall_off = static_cast<int>(std::ceil(3.0 * std::max(sigma / res, 0.3)));
  const double margin = reach + window + ((1 << (levels - 1)) + 3 + fall_off) * res;
  return MatchField(grid, sigma, levels, grid.worldToLattice(around.x - margin), grid.worldToLattice(around.y - margin),
                    grid.worldToLattice(around.x + margin), grid.worldToLattice(around.y + margin), unobserved_weight);
}

std::vector<Point2D> voxelFilter(const std::vector<Point2D>& points, double cell)
{
  std::vector<Point2D> out;
  std::unordered_set<std::uint64_t> seen;
  out.reserve(points.size());
  for (const Point2D& p : points)
  {
    if (seen.insert(cellKey(cellIndex(p.x / cell), cellIndex(p.y / cell))).second)
      out.push_back(p);
  }
  return out;
}

std::vector<Point2D> adaptiveVoxelFilter(const std::vector<Point2D>& points, double cell, size_t min_points)
{
  std::vector<Point2D> out = voxelFilter(points, cell);
  for (int halvings = 0; halvings < 2 && out.size() < min_points && out.size() < points.size(); ++halvings)
  {
    cell *= 0.5;
    out = voxelFilter(points, cell);
  }
  return out;
}

double scorePose(const MatchField& field, const std::vector<Point2D>& points, const Pose2D& pose)
{
  if (points.empty() || field.empty())
    return 0.0;
  const double res = field.resolution();
  double sum = 0.0;
  for (const Point2D& p : points)
  {
    const Point2D w = transformPoint(pose, p);
    sum += field.value(0, cellIndex(w.x / res), cellIndex(w.y / res));
  }
  return sum / static_cast<double>(points.size());
}

namespace
{
struct Candidate
{
  int angle;
  int dx, dy;
  double score;
};
}  // namespace

MatchResult matchScan(const MatchField& field, const std::vector<Point2D>& points, const MatchRequest& request)
{
  MatchResult result;
  if (points.empty() || field.empty())
    return result;
  const double res = field.resolution();
  double max_range = 0.0;
  for (const Point2D& p : points)
    max_range = std::max(max_range, std::hypot(p.x, p.y));
  // Angular step that moves the farthest point by about one cell (capped so far points do not
  // make the step needlessly fine: refinement recovers the rest).
  const double d = std::clamp(max_range, 3 * res, 15.0);
  const double angle_step = std::acos(1.0 - res * res / (2.0 * d * d));
  const int n_angles = static_cast<int>(std::ceil(request.angular_window / angle_step));
  const int window = static_cast<int>(std::ceil(request.linear_window / res));
  const int top = field.levels() - 1;
  const int top_step = 1 << top;

  // Discretised scan for each rotation, in lattice cells, at zero translation offset: the cells,
  // their bounding box, and their indices into the field's levels (for offsets that keep the box
  // inside the field, which then need no check a cell).
  struct RotatedScan
  {
    std::vector<std::pair<int, int>> cells;
    std::vector<std::ptrdiff_t> index;
    int x0 = std::numeric_limits<int>::max(), y0 = std::numeric_limits<int>::max();
    int x1 = std::numeric_limits<int>::min(), y1 = std::numeric_limits<int>::min();
  };
  const int n_rot = 2 * n_angles + 1;
  const int fx0 = field.minCellX(), fy0 = field.minCellY(), fw = field.width(), fh = field.height();
  std::vector<RotatedScan> scans(static_cast<size_t>(n_rot));
  for (int k = 0; k < n_rot; ++k)
  {
    Pose2D p = request.initial;
    p.theta = request.initial.theta + (k - n_angles) * angle_step;
    RotatedScan& r = scans[static_cast<size_t>(k)];
    r.cells.reserve(points.size());
    r.index.reserve(points.size());
    for (const Point2D& q : points)
    {
      const Point2D w = transformPoint(p, q);
      const int cx = cellIndex(w.x / res), cy = cellIndex(w.y / res);
      r.cells.emplace_back(cx, cy);
      r.index.push_back(static_cast<std::ptrdiff_t>(cy - fy0) * fw + (cx - fx0));
      r.x0 = std::min(r.x0, cx);
      r.y0 = std::min(r.y0, cy);
      r.x1 = std::max(r.x1, cx);
      r.y1 = std::max(r.y1, cy);
    }
  }
  // value()'s figures as doubles, by raw value. Each is a float (a multiple of 2^-31 in [0, 1]),
  // so their sum over fewer than 2^22 points is exact in a double, in any order: both paths
  // below give the same score to the last bit.
  double lookup[256];
  for (int v = 0; v < 256; ++v)
    lookup[v] = static_cast<double>(static_cast<float>(v) * (1.0f / 255.0f));
  const double inv_n = 1.0 / static_cast<double>(points.size());
  const double cap2 = request.translation_prior_cap > 0.0
                          ? request.translation_prior_cap * request.translation_prior_cap
                          : std::numeric_limits<double>::infinity();
  // Smallest |offset| over [d, d + size - 1] cells, in metres: keeps the penalised score of a
  // block an upper bound of its children's.
  auto nearest = [res](int d, int size)
  {
    if (d <= 0 && d + size - 1 >= 0)
      return 0.0;
    return res * std::min(std::abs(d), std::abs(d + size - 1));
  };
  auto score = [&](int level, int k, int dx, int dy)
  {
    const RotatedScan& r = scans[static_cast<size_t>(k)];
    double s = 0.0;
    if (r.x0 + dx >= fx0 && r.y0 + dy >= fy0 && r.x1 + dx < fx0 + fw && r.y1 + dy < fy0 + fh)
    {
      const uint8_t* data = field.data(level);
      const std::ptrdiff_t offset = static_cast<std::ptrdiff_t>(dy) * fw + dx;
      for (const std::ptrdiff_t i : r.index)
        s += lookup[data[i + offset]];
    }
    else
      for (const auto& c : r.cells)
        s += field.value(level, c.first + dx, c.second + dy);
    const int size = 1 << level;
    const double ex = nearest(dx, size), ey = nearest(dy, size), et = (k - n_angles) * angle_step;
    return s * inv_n - request.translation_weight * std::min(ex * ex + ey * ey, cap2) -
           request.rotation_weight * et * et;
  };

  // Whether a block of size x size cells at (dx, dy) lies wholly within the excluded disc (its
  // farthest corner inside), or, for a single cell, whether that cell does.
  const double ex0 = (request.exclude_center.x - request.initial.x) / res,
               ey0 = (request.exclude_center.y - request.initial.y) / res;
  const double exclude_cells = request.exclude_radius / res;
  auto excluded = [&](int dx, int dy, int size)
  {
    if (exclude_cells <= 0.0)
      return false;
    const double fx = std::max(std::abs(dx - ex0), std::abs(dx + size - 1 - ex0)),
                 fy = std::max(std::abs(dy - ey0), std::abs(dy + size - 1 - ey0));
    return fx * fx + fy * fy < exclude_cells * exclude_cells;
  };

  std::vector<Candidate> tops;
  for (int k = 0; k < n_rot; ++k)
    for (int dy = -window; dy <= window; dy += top_step)
      for (int dx = -window; dx <= window; dx += top_step)
        tops.push_back({k, dx, dy, score(top, k, dx, dy)});
  std::sort(tops.begin(), tops.end(), [](const Candidate& a, const Candidate& b) { return a.score > b.score; });

  Candidate best{n_angles, 0, 0, request.min_score};
  bool found = false;
  std::function<void(const Candidate&, int)> descend = [&](const Candidate& c, int level)
  {
    if (c.score <= best.score || excluded(c.dx, c.dy, 1 << level))
      return;
    if (level == 0)
    {
      best = c;
      found = true;
      return;
    }
    const int half = 1 << (level - 1);
    Candidate children[4];
    int n = 0;
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a)
      {
        const int dx = c.dx + a * half, dy = c.dy + b * half;
        if (dx > window || dy > window)
          continue;
        children[n++] = {c.angle, dx, dy, score(level - 1, c.angle, dx, dy)};
      }
    for (int i = 1; i < n; ++i)  // insertion sort, best first (n <= 4)
      for (int j = i; j > 0 && children[j].score > children[j - 1].score; --j)
        std::swap(children[j], children[j - 1]);
    for (int i = 0; i < n; ++i)
      descend(children[i], level - 1);
  };
  for (const Candidate& c : tops)
  {
    if (c.score <= best.score)
      break;
    descend(c, top);
  }
  if (!found)
    return result;
  Pose2D pose{request.initial.x + best.dx * res, request.initial.y + best.dy * res,
              wrapAngle(request.initial.theta + (best.angle - n_angles) * angle_step)};
  if (request.refine)
  {
    const Pose2D refined = refinePose(field, points, pose, 10, res, &request.initial, request.translation_weight,
                                      request.rotation_weight, request.translation_prior_cap);
    if (scorePose(field, points, refined) >= scorePose(field, points, pose) * 0.98)
      pose = refined;
  }
  result.ok = true;
  result.pose = pose;
  result.score = scorePose(field, points, pose);
  return result;
}

double translationConstraintRatio(const MatchField& field, const std::vector<Point2D>& points, const Pose2D& pose)
{
  Eigen::Matrix2d H = Eigen::Matrix2d::Zero();
  for (const Point2D& p : points)
  {
    const Point2D w = transformPoint(pose, p);
    double fx = 0, fy = 0;
    field.interpolate(w.x, w.y, &fx, &fy);
    const Eigen::Vector2d g(fx, fy);
    H += g * g.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(H);
  const double hi = eig.eigenvalues()(1);
  return hi > 0 ? eig.eigenvalues()(0) / hi : 0.0;
}

Pose2D refinePose(const MatchField& field, const std::vector<Point2D>& points, const Pose2D& start, int iterations,
                  double max_step, const Pose2D* prior, double translation_weight, double rotation_weight,
                  double translation_prior_cap)
{
  const double w = prior ? translation_weight * static_cast<double>(points.size()) : 0.0;
  const double wr = prior ? rotation_weight * static_cast<double>(points.size()) : 0.0;
  Pose2D pose = start;
  for (int it = 0; it < iterations; ++it)
  {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    const double c = std::cos(pose.theta), s = std::sin(pose.theta);
    for (const Point2D& p : points)
    {
      const Point2D w = transformPoint(pose, p);
      double fx = 0, fy = 0;
      const double f = field.interpolate(w.x, w.y, &fx, &fy);
      const double r = 1.0 - f;
      // d(1-f)/d(x,y,theta)
      Eigen::Vector3d J(-fx, -fy, -(fx * (-s * p.x - c * p.y) + fy * (c * p.x - s * p.y)));
      H += J * J.transpose();
      g += J * r;
    }
    const bool capped = prior && translation_prior_cap > 0.0 &&
                        std::hypot(pose.x - prior->x, pose.y - prior->y) > translation_prior_cap;
    if (w > 0.0 && !capped)
    {
      H(0, 0) += w;
      H(1, 1) += w;
      g.x() += w * (pose.x - prior->x);
      g.y() += w * (pose.y - prior->y);
    }
    if (wr > 0.0)
    {
      H(2, 2) += wr;
      g.z() += wr * wrapAngle(pose.theta - prior->theta);
    }
    H.diagonal() += Eigen::Vector3d(1e-3, 1e-3, 1e-3) * (H.trace() / 3.0 + 1e-9);  // LM damping
    const Eigen::Vector3d delta = -H.ldlt().solve(g);
    if (!delta.allFinite())
      break;
    pose.x += delta.x();
    pose.y += delta.y();
    pose.theta = wrapAngle(pose.theta + delta.z());
    if (std::hypot(pose.x - start.x, pose.y - start.y) > max_step)
      return start;
    if (delta.head<2>().norm() < 1e-4 && std::abs(delta.z()) < 1e-5)
      break;
  }
  return pose;
}

}  // namespace mybot_navigation
