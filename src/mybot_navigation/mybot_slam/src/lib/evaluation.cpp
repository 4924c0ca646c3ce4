#include "mybot_slam/evaluation.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace mybot_navigation
{
namespace
{
bool occupiedNear(const GridMap& map, int cx, int cy, int tol, int thr)
{
  for (int dy = -tol; dy <= tol; ++dy)
    for (int dx = -tol; dx <= tol; ++dx)
      if (map.inside(cx + dx, cy + dy) && map.at(cx + dx, cy + dy) >= thr)
        return true;
  return false;
}

bool knownNear(const GridMap& map, int cx, int cy, int tol)
{
  for (int dy = -tol; dy <= tol; ++dy)
    for (int dx = -tol; dx <= tol; ++dx)
      if (map.inside(cx + dx, cy + dy) && map.at(cx + dx, cy + dy) >= 0)
        return true;
  return false;
}
}  // namespace

MapScore scoreMap(const GridMap& estimate, const GridMap& truth, const Pose2D& truth_from_estimate, int tol, int thr)
{
  MapScore s;
  // The tolerance is in estimate cells; convert it for a truth map of another resolution.
  const int tol_truth = static_cast<int>(std::lround(tol * estimate.info.resolution / truth.info.resolution));
  int tp_est = 0;
  for (int y = 0; y < estimate.info.height; ++y)
    for (int x = 0; x < estimate.info.width; ++x)
    {
      if (estimate.at(x, y) < thr)
        continue;
      ++s.estimate_occupied;
      const Point2D p = transformPoint(truth_from_estimate, estimate.cellCenter(x, y));
      int tx, ty;
      truth.worldToCell(p.x, p.y, tx, ty);
      if (occupiedNear(truth, tx, ty, tol_truth, thr))
        ++tp_est;
    }
  const Pose2D estimate_from_truth = inverse(truth_from_estimate);
  int tp_truth = 0;
  for (int y = 0; y < truth.info.height; ++y)
    for (int x = 0; x < truth.info.width; ++x)
    {
      if (truth.at(x, y) < thr)
        continue;
      const Point2D p = transformPoint(estimate_from_truth, truth.cellCenter(x, y));
      int ex, ey;
      estimate.worldToCell(p.x, p.y, ex, ey);
      if (!knownNear(estimate, ex, ey, tol))
        continue;
      ++s.truth_occupied;
      if (occupiedNear(estimate, ex, ey, tol, thr))
        ++tp_truth;
    }
  s.precision = s.estimate_occupied ? static_cast<double>(tp_est) / s.estimate_occupied : 0.0;
  s.recall = s.truth_occupied ? static_cast<double>(tp_truth) / s.truth_occupied : 0.0;
  return s;
}

Pose2D alignTrajectories(const std::vector<Pose2D>& estimate, const std::vector<Pose2D>& truth)
{
  const size_t n = std::min(estimate.size(), truth.size());
  if (n == 0)
    return {};
  double ex = 0, ey = 0, tx = 0, ty = 0;
  for (size_t i = 0; i < n; ++i)
  {
    ex += estimate[i].x;
    ey += estimate[i].y;
    tx += truth[i].x;
    ty += truth[i].y;
  }
  ex /= n;
  ey /= n;
  tx /= n;
  ty /= n;
  double sxx = 0, sxy = 0;  // 2D Kabsch: angle maximising the correlation
  for (size_t i = 0; i < n; ++i)
  {
    const double ax = estimate[i].x - ex, ay = estimate[i].y - ey;
    const double bx = truth[i].x - tx, by = truth[i].y - ty;
    sxx += ax * bx + ay * by;
    sxy += ax * by - ay * bx;
  }
  double theta = std::atan2(sxy, sxx);
  if (n < 3 || (std::abs(sxx) + std::abs(sxy)) < 1e-9)
    theta = wrapAngle(truth[0].theta - estimate[0].theta);  // degenerate: use headings
  const double c = std::cos(theta), s = std::sin(theta);
  return {tx - (c * ex - s * ey), ty - (s * ex + c * ey), theta};
}

double absoluteTrajectoryRmse(const std::vector<Pose2D>& estimate, const std::vector<Pose2D>& truth,
                              const Pose2D& truth_from_estimate)
{
  const size_t n = std::min(estimate.size(), truth.size());
  if (n == 0)
    return 0.0;
  double sum = 0.0;
  for (size_t i = 0; i < n; ++i)
  {
    const Pose2D e = compose(truth_from_estimate, estimate[i]);
    sum += std::pow(e.x - truth[i].x, 2) + std::pow(e.y - truth[i].y, 2);
  }
  return std::sqrt(sum / n);
}

RelativePoseError relativePoseError(const std::vector<Pose2D>& estimate, const std::vector<Pose2D>& truth, int step)
{
  RelativePoseError r;
  const size_t n = std::min(estimate.size(), truth.size());
  double st = 0, sr = 0;
  for (size_t i = 0; i + static_cast<size_t>(step) < n; ++i)
  {
    const Pose2D de = between(estimate[i], estimate[i + step]);
    const Pose2D dt = between(truth[i], truth[i + step]);
    const Pose2D err = between(dt, de);
    st += err.x * err.x + err.y * err.y;
    sr += err.theta * err.theta;
    ++r.pairs;
  }
  if (r.pairs)
  {
    r.translation_rms = std::sqrt(st / r.pairs);
    r.rotation_rms = std::sqrt(sr / r.pairs);
  }
  return r;
}

namespace
{
struct Accumulator
{
  std::vector<double> values;
  void add(double v) { values.push_back(v); }
  ErrorStats stats() const
  {
    ErrorStats e;
    e.count = static_cast<int>(values.size());
    if (values.empty())
      return e;
    double sum = 0.0, sum2 = 0.0, sq = 0.0, sq2 = 0.0;
    for (double v : values)
    {
      sum += v;
      sum2 += v * v;
      sq += v * v;
      sq2 += v * v * v * v;
      e.max = std::max(e.max, v);
    }
    const double n = static_cast<double>(values.size());
    e.mean = sum / n;
    e.std = std::sqrt(std::max(0.0, sum2 / n - e.mean * e.mean));
    e.squared_mean = sq / n;
    e.squared_std = std::sqrt(std::max(0.0, sq2 / n - e.squared_mean * e.squared_mean));
    return e;
  }
};
}  // namespace

RelationScore scoreRelations(const std::vector<StampedPose>& trajectory, const std::vector<Relation>& relations,
                             double local_max_dt, double stamp_tolerance)
{
  std::vector<StampedPose> sorted = trajectory;
  std::sort(sorted.begin(), sorted.end(), [](const StampedPose& a, const StampedPose& b) { return a.stamp < b.stamp; });
  // The pose whose stamp is nearest to t, within the tolerance. Not the first within it: Intel's
  // log holds bursts of scans stamped under 1 ms apart (1479 of its 13631 gaps), and the first
  // of a burst is another scan, taken up to 0.2 s before the one the relation names.
  auto find = [&](double t, Pose2D& out)
  {
    auto it = std::lower_bound(sorted.begin(), sorted.end(), t - stamp_tolerance,
                               [](const StampedPose& p, double v) { return p.stamp < v; });
    auto best = sorted.end();
    for (; it != sorted.end() && it->stamp <= t + stamp_tolerance; ++it)
      if (best == sorted.end() || std::abs(it->stamp - t) < std::abs(best->stamp - t))
        best = it;
    if (best == sorted.end())
      return false;
    out = best->pose;
    return true;
  };
  Accumulator t_all, r_all, t_local, r_local, t_loop, r_loop;
  RelationScore score;
  for (const Relation& rel : relations)
  {
    Pose2D a, b;
    if (!find(rel.t1, a) || !find(rel.t2, b))
    {
      ++score.missing;
      continue;
    }
    const Pose2D est = between(a, b);
    const double dt = std::hypot(est.x - rel.motion.x, est.y - rel.motion.y);
    const double dr = std::abs(wrapAngle(est.theta - rel.motion.theta)) * 180.0 / M_PI;
    t_all.add(dt);
    r_all.add(dr);
    const bool local = std::abs(rel.t2 - rel.t1) <= local_max_dt;
    (local ? t_local : t_loop).add(dt);
    (local ? r_local : r_loop).add(dr);
  }
  score.translation = t_all.stats();
  score.rotation_deg = r_all.stats();
  score.local_translation = t_local.stats();
  score.local_rotation_deg = r_local.stats();
  score.loop_translation = t_loop.stats();
  score.loop_rotation_deg = r_loop.stats();
  return score;
}

std::vector<Relation> readRelations(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error(path + ": cannot open the relations file");
  std::vector<Relation> out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n)
  {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#')
      continue;
    std::istringstream fields(line);
    Relation r;
    double z, roll, pitch;
    if (!(fields >> r.t1 >> r.t2 >> r.motion.x >> r.motion.y >> z >> roll >> pitch >> r.motion.theta) ||
        !std::isfinite(r.t1) || !std::isfinite(r.t2) || !std::isfinite(r.motion.x) || !std::isfinite(r.motion.y) ||
        !std::isfinite(r.motion.theta))
      throw std::runtime_error(path + ":" + std::to_string(n) + ": expected \"t1 t2 x y z roll pitch yaw\", got \"" +
                               line + "\"");
    out.push_back(r);
  }
  return out;
}

}  // namespace mybot_navigation
