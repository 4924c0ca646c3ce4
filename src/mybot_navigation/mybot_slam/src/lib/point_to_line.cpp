#include "mybot_slam/point_to_line.h"

#include <cmath>

#include <Eigen/Dense>

#include "mybot_nav_common/grid_map.h"

namespace mybot_navigation
{

// Calls f(index) for every point hashed into the (2 ring + 1)^2 cells around (cx, cy): with
// cells as wide as r, every point within ring * r.
template <typename F>
void LineReference::forEachNear(const Buckets& buckets, int cx, int cy, int ring, F&& f) const
{
  for (int dy = -ring; dy <= ring; ++dy)
    for (int dx = -ring; dx <= ring; ++dx)
    {
      const auto it = buckets.find(key(cx + dx, cy + dy));
      if (it != buckets.end())
        for (int j : it->second)
          f(j);
    }
}

int LineReference::cellOf(double v) const
{
  return cellIndex(v / cell_);
}

bool LineReference::fitLine(const std::vector<Point2D>& points, const Buckets& all, const Point2D& p, double radius,
                            double max_flatness, Point2D& mean_out, Point2D& normal_out) const
{
  // The neighbourhood's mean and covariance: a line's points spread along it only.
  const double r2 = radius * radius;
  int n = 0;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  Eigen::Matrix2d sq = Eigen::Matrix2d::Zero();
  forEachNear(all, cellOf(p.x), cellOf(p.y), static_cast<int>(std::ceil(radius / cell_ - 1e-9)),
              [&](int j)
              {
                const Point2D& q = points[static_cast<size_t>(j)];
                if ((q.x - p.x) * (q.x - p.x) + (q.y - p.y) * (q.y - p.y) > r2)
                  return;
                const Eigen::Vector2d v(q.x, q.y);
                sum += v;
                sq += v * v.transpose();
                ++n;
              });
  if (n < 3)
    return false;
  const Eigen::Vector2d mean = sum / n;
  const Eigen::Matrix2d cov = sq / n - mean * mean.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  const double lo = eig.eigenvalues()(0), hi = eig.eigenvalues()(1);
  if (hi <= 0.0 || lo > max_flatness * hi)
    return false;
  // The line passes through the neighbourhood's mean: the point itself carries its beam's noise,
  // the mean less of it.
  mean_out = {mean.x(), mean.y()};
  normal_out = {eig.eigenvectors()(0, 0), eig.eigenvectors()(1, 0)};
  return true;
}

LineReference::LineReference(const std::vector<Point2D>& points, double neighbour_radius, double max_flatness,
                             double sparse_radius)
    : cell_(neighbour_radius)
{
  Buckets all;
  for (size_t i = 0; i < points.size(); ++i)
    all[key(cellOf(points[i].x), cellOf(points[i].y))].push_back(static_cast<int>(i));
  for (const Point2D& p : points)
  {
    Point2D mean, normal;
    if (!fitLine(points, all, p, neighbour_radius, max_flatness, mean, normal) &&
        !(sparse_radius > neighbour_radius && fitLine(points, all, p, sparse_radius, max_flatness, mean, normal)))
      continue;
    const int index = static_cast<int>(points_.size());
    points_.push_back(mean);
    normals_.push_back(normal);
    buckets_[key(cellOf(mean.x), cellOf(mean.y))].push_back(index);
  }
}

bool LineReference::nearest(const Point2D& w, double max_distance, Point2D& point, Point2D& normal) const
{
  const int cx = cellOf(w.x), cy = cellOf(w.y);
  double best = max_distance * max_distance;
  int found = -1;
  forEachNear(buckets_, cx, cy, 1,
              [&](int j)
              {
                const Point2D& q = points_[static_cast<size_t>(j)];
                const double d2 = (q.x - w.x) * (q.x - w.x) + (q.y - w.y) * (q.y - w.y);
                if (d2 <= best)
                {
                  best = d2;
                  found = j;
                }
              });
  if (found < 0)
    return false;
  point = points_[static_cast<size_t>(found)];
  normal = normals_[static_cast<size_t>(found)];
  return true;
}

PointToLineResult refinePointToLine(const LineReference& reference, const std::vector<Point2D>& points,
                                    const Pose2D& initial, const PointToLineParams& params)
{
  PointToLineResult result;
  if (points.empty() || reference.size() == 0)
    return result;
  Pose2D pose = initial;
  Eigen::Matrix2d info = Eigen::Matrix2d::Zero();
  for (int it = 0; it < params.iterations; ++it)
  {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    info.setZero();
    const double c = std::cos(pose.theta), s = std::sin(pose.theta);
    int inliers = 0;
    double sq = 0.0;
    for (const Point2D& p : points)
    {
      const Point2D w = transformPoint(pose, p);
      Point2D q, n;
      if (!reference.nearest(w, params.max_distance, q, n))
        continue;
      const double r = n.x * (w.x - q.x) + n.y * (w.y - q.y);
      // d(T p)/d theta = (-s p.x - c p.y, c p.x - s p.y)
      const Eigen::Vector3d J(n.x, n.y, n.x * (-s * p.x - c * p.y) + n.y * (c * p.x - s * p.y));
      const double weight = std::abs(r) <= params.huber ? 1.0 : params.huber / std::abs(r);
      H += weight * J * J.transpose();
      g += weight * J * r;
      info += J.head<2>() * J.head<2>().transpose();
      sq += r * r;
      ++inliers;
    }
    result.inliers = inliers;
    result.rms = inliers > 0 ? std::sqrt(sq / inliers) : 0.0;
    if (inliers < params.min_inlier_ratio * static_cast<double>(points.size()))
      return PointToLineResult{false, initial, inliers, result.rms, 0.0};
    // The prior: prior_weight points' worth of pull towards where the pose started (its rotation
    // weighed as a point 1 m out).
    const double wp = params.prior_weight;
    H(0, 0) += wp;
    H(1, 1) += wp;
    H(2, 2) += wp;
    g.x() += wp * (pose.x - initial.x);
    g.y() += wp * (pose.y - initial.y);
    g.z() += wp * wrapAngle(pose.theta - initial.theta);
    const Eigen::Vector3d delta = -H.ldlt().solve(g);
    if (!delta.allFinite())
      return PointToLineResult{false, initial, inliers, result.rms, 0.0};
    pose.x += delta.x();
    pose.y += delta.y();
    pose.theta = wrapAngle(pose.theta + delta.z());
    if (delta.head<2>().norm() < 1e-5 && std::abs(delta.z()) < 1e-6)
      break;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(info);
  const double hi = eig.eigenvalues()(1);
  result.ok = true;
  result.pose = pose;
  result.constraint_ratio = hi > 0.0 ? eig.eigenvalues()(0) / hi : 0.0;
  return result;
}

}  // namespace mybot_navigation
