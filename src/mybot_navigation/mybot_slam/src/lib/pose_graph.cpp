#include "mybot_slam/pose_graph.h"

#include <stdexcept>

#include <ceres/ceres.h>

namespace mybot_navigation
{
namespace
{
template <typename T>
T wrap(const T& a)
{
  const T two_pi(2.0 * M_PI);
  return a - two_pi * ceres::floor((a + T(M_PI)) / two_pi);
}

struct RelativePoseError
{
  RelativePoseError(const Pose2D& z, double sxy, double st) : z_(z), w_xy_(1.0 / sxy), w_t_(1.0 / st) {}

  template <typename T>
  bool operator()(const T* a, const T* b, T* r) const
  {
    const T c = ceres::cos(a[2]), s = ceres::sin(a[2]);
    const T dx = b[0] - a[0], dy = b[1] - a[1];
    // Pose of b in a's frame minus the measurement.
    r[0] = T(w_xy_) * (c * dx + s * dy - T(z_.x));
    r[1] = T(w_xy_) * (-s * dx + c * dy - T(z_.y));
    r[2] = T(w_t_) * wrap(b[2] - a[2] - T(z_.theta));
    return true;
  }

  Pose2D z_;
  double w_xy_, w_t_;
};
}  // namespace

int PoseGraph::addNode(const Pose2D& pose)
{
  nodes_.push_back(pose);
  return static_cast<int>(nodes_.size()) - 1;
}

void PoseGraph::addEdge(const PoseGraphEdge& e)
{
  if (e.from < 0 || e.to < 0 || e.from >= static_cast<int>(nodes_.size()) || e.to >= static_cast<int>(nodes_.size()))
    throw std::out_of_range("PoseGraph::addEdge: node index out of range");
  edges_.push_back(e);
}

Pose2D PoseGraph::residual(const PoseGraphEdge& e) const
{
  return between(between(node(e.from), node(e.to)), e.measurement);
}

OptimizationSummary PoseGraph::optimize(int max_iterations, double huber_scale)
{
  OptimizationSummary out;
  if (nodes_.size() < 2 || edges_.empty())
    return out;
  std::vector<double> x(nodes_.size() * 3);
  for (size_t i = 0; i < nodes_.size(); ++i)
  {
    x[3 * i] = nodes_[i].x;
    x[3 * i + 1] = nodes_[i].y;
    x[3 * i + 2] = nodes_[i].theta;
  }
  ceres::Problem problem;
  for (const PoseGraphEdge& e : edges_)
  {
    auto* cost = new ceres::AutoDiffCostFunction<RelativePoseError, 3, 3, 3>(
        new RelativePoseError(e.measurement, e.sigma_xy, e.sigma_theta));
    ceres::LossFunction* loss = nullptr;
    if (e.redescending)
      loss = new ceres::CauchyLoss(huber_scale);
    else if (e.robust)
      loss = new ceres::HuberLoss(huber_scale);
    problem.AddResidualBlock(cost, loss, &x[3 * static_cast<size_t>(e.from)], &x[3 * static_cast<size_t>(e.to)]);
  }
  problem.SetParameterBlockConstant(&x[0]);
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = max_iterations;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  out.iterations = static_cast<int>(summary.iterations.size());
  out.initial_cost = summary.initial_cost;
  out.final_cost = summary.final_cost;
  for (size_t i = 0; i < nodes_.size(); ++i)
    nodes_[i] = {x[3 * i], x[3 * i + 1], wrapAngle(x[3 * i + 2])};
  return out;
}

}  // namespace mybot_navigation
