// Slam's global loop search: where the local search (a candidate within loop_search_radius of
// the estimate, a 3 m window) cannot reach because drift since the place was last seen may be
// tens of metres, the recent path is matched as one rigid piece against the whole older map.
// Cartographer searches whole submaps for such "global" constraints with the same branch and
// bound (Hess et al. 2016, section V); a single 180-beam scan is too little for a window of
// 50 m in a building of repeated corridors, so the query here is the last
// loop_global_query_travel metres of keyframes, and the grid is coarse to keep it cheap.
#include <algorithm>
#include <cmath>

#include "mybot_slam/slam.h"

namespace mybot_navigation
{
namespace
{
// SE(2) exponential of (u, theta) scaled by `a`: the transform that moves along the same screw
// motion a fraction `a` of the way (a = 1 gives exp(u, theta) itself).
Pose2D scaledScrew(const Pose2D& t, double a)
{
  // log: t = (V(theta) u, theta) with V = [[A, -B], [B, A]], A = sin(th)/th, B = (1 - cos(th))/th.
  auto v = [](double th, double& A, double& B)
  {
    if (std::abs(th) < 1e-9)
    {
      A = 1.0;
      B = 0.0;
      return;
    }
    A = std::sin(th) / th;
    B = (1.0 - std::cos(th)) / th;
  };
  double A = 0, B = 0;
  v(t.theta, A, B);
  const double det = A * A + B * B;
  const double ux = (A * t.x + B * t.y) / det, uy = (-B * t.x + A * t.y) / det;
  const double th = a * t.theta;
  v(th, A, B);
  return Pose2D{A * a * ux - B * a * uy, B * a * ux + A * a * uy, th};
}
}  // namespace

bool Slam::globalSearchDue(int current, double& window) const
{
  if (params_.loop_global_interval <= 0.0)
    return false;
  const Keyframe& kf = keyframes_[static_cast<size_t>(current)];
  if (kf.travelled - last_global_travelled_ < params_.loop_global_interval)
    return false;
  // Some older keyframe must be within the drift possible since it, and that drift beyond the
  // local search's window.
  window = 0.0;
  for (int i = 0; i < current; ++i)
  {
    const Keyframe& k = keyframes_[static_cast<size_t>(i)];
    const double lag = kf.travelled - k.travelled;
    if (lag < params_.loop_global_query_travel + params_.loop_min_travel)
      break;
    const double bound = params_.loop_max_correction + params_.loop_global_max_correction_per_m * lag;
    const double d = std::hypot(k.pose.x - kf.pose.x, k.pose.y - kf.pose.y);
    if (bound > params_.loop_window_linear && d <= bound)
      window = std::max(window, std::min(bound, params_.loop_global_window_linear));
  }
  return window > 0.0;
}

void Slam::updateCoarseMap(int last)
{
  if (coarse_stale_)
  {
    coarse_.clear();
    coarse_count_ = 0;
    coarse_stale_ = false;
  }
  insertKeyframes(coarse_, coarse_count_, last + 1);
  coarse_count_ = std::max(coarse_count_, last + 1);
}

std::vector<Point2D> Slam::globalQuery(int current) const
{
  const Keyframe& kf = keyframes_[static_cast<size_t>(current)];
  const Pose2D to_current = inverse(kf.pose);
  std::vector<Point2D> points;
  for (int i = current; i >= 0; --i)
  {
    const Keyframe& k = keyframes_[static_cast<size_t>(i)];
    if (kf.travelled - k.travelled > params_.loop_global_query_travel)
      break;
    const Pose2D in_current = compose(to_current, k.pose);
    for (const Point2D& p : k.match_points)
      points.push_back(transformPoint(in_current, p));
  }
  return voxelFilter(points, params_.loop_global_resolution);
}

bool Slam::searchGlobally(int current, double window, LoopMatch& match)
{
  const Keyframe& kf = keyframes_[static_cast<size_t>(current)];
  // The map of everything before the query, less loop_min_travel (as for a local candidate).
  int last = -1;
  for (int i = 0; i < current; ++i)
  {
    if (kf.travelled - keyframes_[static_cast<size_t>(i)].travelled <
        params_.loop_global_query_travel + params_.loop_min_travel)
      break;
    last = i;
  }
  if (last < 0)
    return false;
  updateCoarseMap(last);
  const std::vector<Point2D> query = globalQuery(current);
  if (query.size() < 3 || coarse_.empty())
    return false;
  double extent = 0.0;
  for (const Point2D& p : query)
    extent = std::max(extent, std::hypot(p.x, p.y));
  const double res = coarse_.resolution();
  const double reach = window + extent + 1.0;
  const MatchField field(coarse_, std::max(params_.match_sigma, res), matchFieldLevels(window, res),
                         coarse_.worldToLattice(kf.pose.x - reach), coarse_.worldToLattice(kf.pose.y - reach),
                         coarse_.worldToLattice(kf.pose.x + reach), coarse_.worldToLattice(kf.pose.y + reach));
  MatchRequest req;
  req.initial = kf.pose;
  req.linear_window = window;
  req.angular_window = params_.loop_global_window_angular;
  req.min_score = params_.loop_global_min_score;
  const MatchResult res_match = matchScan(field, query, req);
  if (!res_match.ok)
    return false;
  // A corridor pins nothing along it (the other tests of a closure follow in tryLoopClosure,
  // on these coarse scores: implausibleClosure, confirmClosure).
  // Within the local search's reach, the local search (at full resolution) decides.
  const Pose2D correction = between(kf.pose, res_match.pose);
  if (std::abs(correction.x) <= params_.loop_window_linear && std::abs(correction.y) <= params_.loop_window_linear &&
      std::abs(correction.theta) <= params_.loop_window_angular)
    return false;
  const double ratio = translationConstraintRatio(field, query, res_match.pose);
  if (ratio < params_.loop_min_constraint_ratio)
    return false;
  match.global = true;
  match.result = res_match;
  match.constraint_ratio = ratio;
  match.score_at_estimate = scorePose(field, query, kf.pose);
  match.correction = correction;
  return true;
}

void Slam::spreadCorrection(int first, const Pose2D& map_correction)
{
  // Where the path since `first` has a step the matcher could not confirm (a weak match: the
  // odometry alone), the first such step most likely holds the error (a jump shows there first):
  // it takes the whole correction. Otherwise drift grew with the path: node i is moved the
  // fraction of the correction that its share of the path from `first` calls for. Either way along
  // the same screw motion, so the optimiser starts near the answer instead of tens of metres away
  // (the robust losses would barely pull from there).
  const int current = static_cast<int>(keyframes_.size()) - 1;
  int jump = -1;
  for (const PoseGraphEdge& e : graph_.edges())
    if (e.redescending && e.to == e.from + 1 && e.from >= first && e.to <= current && (jump < 0 || e.to < jump))
      jump = e.to;
  const double t0 = keyframes_[static_cast<size_t>(first)].travelled;
  const double span = keyframes_.back().travelled - t0;
  for (int i = first + 1; i <= current; ++i)
  {
    const double a = jump >= 0  ? (i >= jump ? 1.0 : 0.0)
                     : span > 0 ? std::clamp((keyframes_[static_cast<size_t>(i)].travelled - t0) / span, 0.0, 1.0)
                                : 1.0;
    if (a > 0.0)
      graph_.setNode(i, compose(scaledScrew(map_correction, a), graph_.node(i)));
  }
}

}  // namespace mybot_navigation
