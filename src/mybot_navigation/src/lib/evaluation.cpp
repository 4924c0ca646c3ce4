#include "mybot_navigation/evaluation.h"

#include <cmath>

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
    theta = normalizeAngle(truth[0].theta - estimate[0].theta);  // degenerate: use headings
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

}  // namespace mybot_navigation
