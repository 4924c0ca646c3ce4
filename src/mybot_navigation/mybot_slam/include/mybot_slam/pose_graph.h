// 2D pose graph: nodes are poses, edges relative-pose measurements with a diagonal information.
// Optimised with Ceres (sparse Cholesky), loop edges under a Huber loss so one wrong closure
// cannot tear the map apart.
#pragma once

#include <vector>

#include "mybot_nav_common/pose2d.h"

namespace mybot_navigation
{

struct PoseGraphEdge
{
  int from = 0;
  int to = 0;
  Pose2D measurement;         // pose of `to` in the frame of `from`
  double sigma_xy = 0.05;     // m
  double sigma_theta = 0.02;  // rad
  bool robust = false;        // Huber loss (loop closures)
  // Cauchy loss instead (steps the scan matcher could not confirm): its cost hardly grows beyond
  // a few sigma, so one such step takes a whole jump rather than sharing it with the others.
  bool redescending = false;
};

struct OptimizationSummary
{
  bool converged = false;
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
};

class PoseGraph
{
public:
  int addNode(const Pose2D& pose);
  void addEdge(const PoseGraphEdge& edge);
  size_t size() const { return nodes_.size(); }
  const Pose2D& node(int i) const { return nodes_[static_cast<size_t>(i)]; }
  void setNode(int i, const Pose2D& p) { nodes_[static_cast<size_t>(i)] = p; }
  const std::vector<PoseGraphEdge>& edges() const { return edges_; }
  // Drops the newest edge (a loop closure that failed its consistency check).
  void popEdge() { edges_.pop_back(); }
  // How far the current node poses are from satisfying an edge: the measured pose of `to`
  // relative to where `from` currently puts it, in `from`'s frame (zero when consistent).
  Pose2D residual(const PoseGraphEdge& edge) const;

  // Optimises every node except the first (the gauge). Poses are updated in place.
  OptimizationSummary optimize(int max_iterations = 50, double huber_scale = 1.0);

private:
  std::vector<Pose2D> nodes_;
  std::vector<PoseGraphEdge> edges_;
};

}  // namespace mybot_navigation
