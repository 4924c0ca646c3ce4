#include "mybot_slam/slam.h"

#include <algorithm>
#include <cmath>

namespace mybot_navigation
{
namespace
{
double maxRange(const std::vector<Point2D>& pts)
{
  double r = 0.0;
  for (const Point2D& p : pts)
    r = std::max(r, std::hypot(p.x, p.y));
  return r;
}

// Information-weighted mean of a scan-match edge and an odometry increment (per component).
Pose2D fuseIncrements(const PoseGraphEdge& match, const Pose2D& odom, double odom_sigma_xy, double odom_sigma_theta)
{
  const double wxy = 1.0 / (1.0 + std::pow(odom_sigma_xy / match.sigma_xy, 2));  // odometry's share
  const double wt = 1.0 / (1.0 + std::pow(odom_sigma_theta / match.sigma_theta, 2));
  const Pose2D& m = match.measurement;
  return Pose2D{m.x + wxy * (odom.x - m.x), m.y + wxy * (odom.y - m.y),
                wrapAngle(m.theta + wt * wrapAngle(odom.theta - m.theta))};
}

// Exactly the same: an odometry that sent nothing new repeats its last pose to the digit.
bool samePose(const Pose2D& a, const Pose2D& b)
{
  return a.x == b.x && a.y == b.y && a.theta == b.theta;
}
}  // namespace

Slam::Slam(const SlamParams& params) : params_(params), global_(params.grid)
{
  local_[0].grid = OccupancyGrid(params.grid);
  local_[1].grid = OccupancyGrid(params.grid);
  OccupancyGridParams coarse = params.grid;
  coarse.resolution = params.loop_global_resolution;
  coarse_ = OccupancyGrid(coarse);
}

size_t Slam::memoryBytes() const
{
  size_t bytes = global_.memoryBytes() + local_[0].grid.memoryBytes() + local_[1].grid.memoryBytes();
  for (const Keyframe& k : keyframes_)
    bytes += sizeof(Keyframe) +
             (k.scan.hits.capacity() + k.scan.misses.capacity() + k.match_points.capacity()) * sizeof(Point2D);
  return bytes;
}

bool Slam::wantsScan(double stamp, const Pose2D& odom) const
{
  if (stamp <= last_stamp_)
    return false;
  if (keyframes_.empty() || params_.track_every_scan)
    return true;
  const Keyframe& last = keyframes_.back();
  const Pose2D delta = between(last.odom, odom);
  return translationNorm(delta) >= params_.linear_update || std::abs(delta.theta) >= params_.angular_update ||
         (params_.temporal_update >= 0.0 && stamp - last.stamp >= params_.temporal_update);
}

void Slam::updateOdometry(const Pose2D& odom)
{
  if (!keyframes_.empty())
    current_pose_ = compose(map_to_odom_, odom);
}

const MatchField& Slam::localField(const Pose2D& around, const std::vector<Point2D>& points)
{
  const int source = local_[1].members.size() > local_[0].members.size() ? 1 : 0;
  if (local_field_dirty_ || source != local_field_source_)
  {
    const OccupancyGrid& g = local_[source].grid;
    const double reach = maxRange(points) + params_.search_window_linear + params_.linear_update + 1.0;
    local_field_ = MatchField(g, params_.match_sigma, matchFieldLevels(params_.search_window_linear, g.resolution()),
                              g.worldToLattice(around.x - reach), g.worldToLattice(around.y - reach),
                              g.worldToLattice(around.x + reach), g.worldToLattice(around.y + reach),
                              params_.match_unobserved_weight);
    local_field_source_ = source;
    local_field_dirty_ = false;
  }
  return local_field_;
}

std::vector<Point2D> Slam::pointsInReach(const std::vector<int>& map_keyframes, const Pose2D& pose,
                                         const std::vector<Point2D>& points) const
{
  // A map ends where its keyframes' usable range ended, not where the walls do. A point of the
  // scan beyond that end has no wall to match, and the lookup field's fall-off around the last
  // mapped cells pulls it back onto them: every match then falls short of the true motion.
  // With a 3.5 m usable range that shrank slam_loop_closure's map by 1.5 % even on ground-truth
  // odometry (precision 0.70; 0.995 without those points, and 0.94-0.99 instead of 0.59-0.80 on
  // its noisy odometry, seeds 1-8). 3 sigma: where the fall-off ends.
  const double margin = 3.0 * params_.match_sigma;
  std::vector<std::pair<Point2D, double>> sensors;  // position, squared reach
  for (int m : map_keyframes)
  {
    const Keyframe& k = keyframes_[static_cast<size_t>(m)];
    if (k.scan.usable_range <= 0.0)
      return points;  // a scan made without a known range: nothing to cut
    const double reach = std::max(0.0, k.scan.usable_range - margin);
    sensors.emplace_back(transformPoint(k.pose, k.scan.origin), reach * reach);
  }
  std::vector<Point2D> out;
  out.reserve(points.size());
  for (const Point2D& p : points)
  {
    const Point2D w = transformPoint(pose, p);
    for (const auto& [s, reach2] : sensors)
      if ((w.x - s.x) * (w.x - s.x) + (w.y - s.y) * (w.y - s.y) <= reach2)
      {
        out.push_back(p);
        break;
      }
  }
  return out;
}

std::vector<Point2D> Slam::localPointsInReach(const Pose2D& predicted, const std::vector<Point2D>& points)
{
  localField(predicted, points);  // picks the local map the match will use
  return pointsInReach(local_[local_field_source_].members, predicted, points);
}

MatchResult Slam::matchLocal(const Pose2D& predicted, const std::vector<Point2D>& points, bool allow_weak)
{
  const MatchField& field = localField(predicted, points);
  MatchRequest req;
  req.initial = predicted;
  req.linear_window = params_.search_window_linear;
  req.angular_window = params_.search_window_angular;
  req.min_score = params_.min_match_score;
  req.translation_weight = params_.match_translation_weight;
  req.rotation_weight = params_.match_rotation_weight;
  req.translation_prior_cap = params_.match_prior_cap;
  MatchResult res = matchScan(field, points, req);
  if (track_window_linear_ > req.linear_window)
  {
    // A long odometry step: the scan may lie beyond the usual window (twice the step away where
    // the odometry reports the wrong direction). The wider search wins only where it explains
    // clearly more, as a rival prediction must (matchFromRival).
    req.linear_window = track_window_linear_;
    const MatchResult wide = matchScan(field, points, req);
    if (wide.ok && (!res.ok || wide.score - res.score >= params_.track_min_gain))
      res = wide;
  }
  // A weak match near the odometry's prediction only where no rival prediction contradicts it
  // (allow_weak). Near a right prediction it takes the small correction a cluttered scan cannot
  // earn at min_match_score; near a wrong one (odometry 0.1 s late in a turn) a weak score is
  // found as easily, and only the rivals tell the two apart.
  if (!res.ok && allow_weak && params_.weak_match_min_score > 0.0)
  {
    req.linear_window = params_.weak_match_window_linear;
    req.angular_window = params_.weak_match_window_angular;
    req.min_score = params_.weak_match_min_score;
    res = matchScan(field, points, req);
  }
  stats_.last_match_score = res.ok ? res.score : scorePose(field, points, predicted);
  return res;
}

ScanOutcome Slam::addScan(double stamp, const Pose2D& odom, const RangeScan& scan)
{
  ++stats_.scans;
  if (stamp <= last_stamp_)
    return ScanOutcome::OutOfOrder;
  last_stamp_ = stamp;
  if (keyframes_.empty())
    return fitsMap(odom, scan) ? startMap(stamp, odom, scan) : ScanOutcome::BeyondMap;

  const Keyframe& last = keyframes_.back();
  const Pose2D delta = between(last.odom, odom);
  // Where the scan is, by odometry from the last tracked scan (from the last keyframe without
  // tracking: tracked_ is then the keyframe's pose).
  const Pose2D predicted = compose(tracked_, between(tracked_odom_, odom));
  if (!fitsMap(predicted, scan))
    return ScanOutcome::BeyondMap;  // nothing tracked: the odometry's jump is no motion of the map's
  track_window_linear_ = std::min(params_.search_window_motion_max,
                                  params_.search_window_motion_scale * translationNorm(between(tracked_odom_, odom)));
  const bool moved = translationNorm(delta) >= params_.linear_update ||
                     std::abs(delta.theta) >= params_.angular_update ||
                     (params_.temporal_update >= 0.0 && stamp - last.stamp >= params_.temporal_update);
  Pose2D motion_pose, undoing_pose;
  RivalPredictions rivals;
  if (predictFromMotion(stamp, predicted, motion_pose))
    rivals.from_motion = &motion_pose;
  if (predictUndoingCorrection(odom, undoing_pose))
    rivals.undoing = &undoing_pose;
  // The odometry repeated itself for the last scan (nothing new had reached the mapper) and
  // moved for this one: it may bring all the motion since at once.
  const bool catching_up = odom_stale_ && !samePose(odom, last_scan_odom_);
  odom_stale_ = samePose(odom, last_scan_odom_);
  last_scan_odom_ = odom;
  Pose2D turn_pose;
  if (catching_up && predictMapTurn(predicted, turn_pose))
    rivals.map_turn = &turn_pose;
  const Pose2D before = tracked_;
  const double before_stamp = tracked_stamp_;
  // The last step is kept as the map measured it (`step` from the scan before to this one): a
  // closure moves both poses, not the motion between them.
  auto remember = [&](const Pose2D& step)
  {
    prev_tracked_ = compose(tracked_, inverse(step));
    prev_tracked_stamp_ = before_stamp;
    tracked_stamp_ = stamp;
    have_motion_ = before_stamp > 0.0;
  };
  if (!moved || scan.hits.size() < 3)
  {
    trackScan(odom, scan, predicted, rivals);
    remember(between(before, tracked_));
    return moved ? ScanOutcome::NoValidPoints : ScanOutcome::Skipped;
  }
  addKeyframe(stamp, odom, scan, predicted, rivals);
  extendReach(keyframes_.back().pose, scan);
  const int index = static_cast<int>(keyframes_.size()) - 1;
  const Pose2D step = between(before, keyframes_.back().pose);  // before a closure moves the keyframe
  if (params_.loop_closure && index - last_loop_attempt_ >= params_.loop_check_interval)
    tryLoopClosure(index);

  const Keyframe& now = keyframes_.back();
  map_to_odom_ = compose(now.pose, inverse(now.odom));
  current_pose_ = tracked_ = now.pose;
  tracked_odom_ = now.odom;
  last_scan_in_keyframe_ = Pose2D{};
  remember(step);
  return ScanOutcome::Processed;
}

std::vector<Point2D> Slam::matchPoints(const std::vector<Point2D>& hits) const
{
  return adaptiveVoxelFilter(hits, params_.match_point_spacing, static_cast<size_t>(params_.match_min_points));
}

namespace
{
// How far from the robot a scan reaches: its usable range (0 = unknown: its farthest point) and
// the margin a grid grows by.
double scanReach(const RangeScan& scan, double grow_margin)
{
  const double reach =
      scan.usable_range > 0.0 ? scan.usable_range : std::max(maxRange(scan.hits), maxRange(scan.misses));
  return reach + grow_margin;
}
}  // namespace

bool Slam::fitsMap(const Pose2D& pose, const RangeScan& scan) const
{
  if (!poseError(pose).empty())
    return false;
  if (keyframes_.empty())
    return true;
  const double reach = scanReach(scan, params_.grid.grow_margin);
  const double side = kMaxMapSide * params_.grid.resolution;
  return std::max(reach_hi_.x, pose.x + reach) - std::min(reach_lo_.x, pose.x - reach) <= side &&
         std::max(reach_hi_.y, pose.y + reach) - std::min(reach_lo_.y, pose.y - reach) <= side;
}

void Slam::extendReach(const Pose2D& pose, const RangeScan& scan)
{
  const double reach = scanReach(scan, params_.grid.grow_margin);
  reach_lo_ = {std::min(reach_lo_.x, pose.x - reach), std::min(reach_lo_.y, pose.y - reach)};
  reach_hi_ = {std::max(reach_hi_.x, pose.x + reach), std::max(reach_hi_.y, pose.y + reach)};
}

ScanOutcome Slam::startMap(double stamp, const Pose2D& odom, const RangeScan& scan)
{
  if (scan.hits.size() < 3)
    return ScanOutcome::NoValidPoints;
  Keyframe kf;
  kf.stamp = stamp;
  kf.odom = odom;
  kf.pose = odom;  // the map frame coincides with the odometry frame at start
  kf.scan = scan;
  kf.match_points = matchPoints(scan.hits);
  keyframes_.push_back(std::move(kf));
  reach_lo_ = reach_hi_ = {odom.x, odom.y};
  extendReach(odom, scan);
  graph_.addNode(odom);
  if (!global_stale_)
    global_.insertScan(odom, scan);
  insertIntoLocalMaps(0);
  map_to_odom_ = Pose2D{};
  current_pose_ = tracked_ = tracked_odom_ = last_scan_odom_ = odom;
  last_scan_in_keyframe_ = Pose2D{};
  ++stats_.keyframes;
  ++map_version_;
  return ScanOutcome::Processed;
}

bool Slam::predictFromMotion(double stamp, const Pose2D& predicted, Pose2D& from_motion) const
{
  if (!params_.track_motion_fallback || !params_.track_every_scan || !have_motion_ ||
      tracked_stamp_ <= prev_tracked_stamp_)
    return false;
  // The map's last step scaled to this scan's interval (a dropped scan doubles it; after a gap
  // of more than three steps it says nothing of the motion now).
  const double ratio = (stamp - tracked_stamp_) / (tracked_stamp_ - prev_tracked_stamp_);
  if (ratio <= 0.0 || ratio > 3.0)
    return false;
  const Pose2D step = between(prev_tracked_, tracked_);
  from_motion = compose(tracked_, Pose2D{step.x * ratio, step.y * ratio, step.theta * ratio});
  // Only odometry that reverses what the map just saw: a fallback wherever the odometry's match
  // fails changed which closures ACES and the hospital found, and lost a loop in each.
  const Pose2D by_odom = between(tracked_, predicted), by_map = between(tracked_, from_motion);
  return by_odom.x * by_map.x + by_odom.y * by_map.y < 0.0 && translationNorm(by_odom) > 0.03 &&
         translationNorm(by_map) > 0.03;
}

bool Slam::predictMapTurn(const Pose2D& predicted, Pose2D& map_turn) const
{
  if (!params_.track_turn_fallback || !params_.track_every_scan || !have_motion_)
    return false;
  // The step as it was, not scaled to this scan's interval as predictFromMotion's is: logs
  // written in bursts stamp scans 1 ms apart that were taken a laser period apart (Intel).
  const Pose2D step = between(prev_tracked_, tracked_);
  const Pose2D by_odom = between(tracked_, predicted);
  if (std::abs(wrapAngle(by_odom.theta - step.theta)) <= 0.5 * params_.search_window_angular)
    return false;
  map_turn = compose(tracked_, step);
  return true;
}

bool Slam::predictUndoingCorrection(const Pose2D& odom, Pose2D& undoing) const
{
  if (!have_uncorrected_)
    return false;
  undoing = compose(uncorrected_, between(tracked_odom_, odom));
  return true;
}

void Slam::rememberCorrection(const Pose2D& predicted, const Pose2D& pose)
{
  const Pose2D correction = between(predicted, pose);
  have_uncorrected_ = params_.track_undo_correction && params_.track_every_scan &&
                      (translationNorm(correction) > 0.5 * params_.search_window_linear ||
                       std::abs(correction.theta) > 0.5 * params_.search_window_angular);
  uncorrected_ = predicted;
}

MatchResult Slam::matchFromRival(const MatchResult& from_odometry, const Pose2D& predicted, const Pose2D* rival,
                                 const std::vector<Point2D>& points, int& wins)
{
  // Where the two predictions are within the lookup field's fall-off, the first match said all.
  if (rival == nullptr || (translationNorm(between(predicted, *rival)) < 2.0 * params_.match_sigma &&
                           std::abs(wrapAngle(rival->theta - predicted.theta)) < 0.05))
    return from_odometry;
  const double odometry_score = stats_.last_match_score;  // what a node reports, if the odometry's match stays
  const std::vector<Point2D> pts = localPointsInReach(*rival, points);
  // A weak match near the rival too: through a crowd its own match is weak as the odometry's is
  // (test_slam's AWeakMatchLetsTheMapsMotionOutrunReversedOdometryThroughACrowd). It still has to
  // explain clearly more than the incumbent, below.
  const MatchResult res = matchLocal(*rival, pts, true);
  // Both judged on the same local map and points. A match from the wrong prediction can succeed
  // on a lesser optimum at its window's edge (0.3 m towards the truth from 0.4 m off), so it is
  // not enough that it succeeded: the rival wins where it explains clearly more.
  const Pose2D incumbent = from_odometry.ok ? from_odometry.pose : predicted;
  if (!res.ok || res.score - scorePose(local_field_, pts, incumbent) < params_.track_min_gain)
  {
    stats_.last_match_score = odometry_score;
    return from_odometry;
  }
  ++wins;
  return res;
}

MatchResult Slam::matchFromRivals(const MatchResult& from_odometry, const Pose2D& predicted,
                                  const RivalPredictions& rivals, const std::vector<Point2D>& points)
{
  const MatchResult res = matchFromRival(from_odometry, predicted, rivals.from_motion, points, stats_.motion_fallbacks);
  const MatchResult undone = matchFromRival(res, predicted, rivals.undoing, points, stats_.corrections_undone);
  return matchFromRival(undone, predicted, rivals.map_turn, points, stats_.turn_fallbacks);
}

MatchResult Slam::matchInWiderHeadings(const MatchResult& from_predictions, const Pose2D& predicted,
                                       const std::vector<Point2D>& points)
{
  const bool stalled = odom_stale_ && params_.track_stall_search;
  const bool retry = !odom_stale_ && params_.track_retry_window_angular > params_.search_window_angular;
  if (from_predictions.ok || stall_search_spent_ || !(stalled || retry))
    return from_predictions;
  ++(stalled ? stats_.stall_searches : stats_.retry_searches);
  // All the scan's points: which of them the local map's keyframes could have seen depends on
  // the heading, which is what is searched for.
  const MatchField& field = localField(predicted, points);
  MatchRequest req;
  req.initial = predicted;
  req.linear_window = params_.track_stall_window_linear;
  req.angular_window = stalled ? M_PI : params_.track_retry_window_angular;
  req.min_score = params_.track_stall_min_score;
  // The heading is free, the translation is not: the ordinary motion prior keeps a match that
  // slides along a wall (Intel, replayed with its beam angles as the bag has them: a 0.22 m
  // jump, worst relation 0.14 -> 0.22 m) from winning where the robot only turned.
  req.translation_weight = params_.match_translation_weight;
  req.translation_prior_cap = params_.match_prior_cap;
  const MatchResult found = matchScan(field, points, req);
  // The retry is for a heading the ordinary window could not reach. A best fit within that window
  // is one the ordinary match judged too weak, and its wider linear window must not overrule
  // that (the mybot room's 3.5 m laser: 35 such scans a run, precision 0.892 -> 0.871 in one).
  bool unique =
      found.ok && (stalled || std::abs(wrapAngle(found.pose.theta - predicted.theta)) > params_.search_window_angular);
  if (unique)
  {
    // Every heading outside the ordinary window around the match: a corridor, a symmetric room
    // seen from its middle, fits the opposite way as well, and the scans cannot say which.
    MatchRequest rival = req;
    rival.initial.theta = wrapAngle(found.pose.theta + M_PI);
    rival.angular_window = M_PI - params_.search_window_angular;
    rival.min_score = params_.track_stall_unique_ratio * found.score;
    rival.refine = false;
    unique = !matchScan(field, points, rival).ok;
  }
  if (!unique)
  {
    stall_search_spent_ = true;
    return from_predictions;
  }
  ++(stalled ? stats_.stall_matches : stats_.retry_matches);
  stats_.last_match_score = found.score;
  return found;
}

void Slam::trackScan(const Pose2D& odom, const RangeScan& scan, const Pose2D& predicted, const RivalPredictions& rivals)
{
  const Keyframe& last = keyframes_.back();
  const Pose2D last_tracked = tracked_;
  tracked_ = predicted;
  have_uncorrected_ = false;  // unless this scan's match moves it far
  if (params_.track_every_scan && scan.hits.size() >= 3)
  {
    const std::vector<Point2D> filtered = matchPoints(scan.hits);
    const std::vector<Point2D> points = localPointsInReach(predicted, filtered);
    MatchResult res = matchLocal(predicted, points, !rivals.any());
    if (res.ok)
      stall_search_spent_ = false;
    const bool matched = res.ok;
    // Along a corridor the match is flat but for small bumps, and every scan that followed one
    // would carry its error into the next prediction: the tracked pose leaves the odometry's
    // only where the match explains clearly more of the scan.
    if (res.ok && res.score - scorePose(local_field_, points, predicted) < params_.track_min_gain)
      res.ok = false;
    res = matchFromRivals(res, predicted, rivals, filtered);
    if (!matched)
      res = matchInWiderHeadings(res, predicted, filtered);
    if (res.ok)
      tracked_ = res.pose;
    rememberCorrection(predicted, tracked_);
    if (res.ok && params_.odom_edge_sigma_xy > 0.0 && params_.odom_edge_sigma_theta > 0.0)
    {
      // Trusted odometry holds the tracked heading as it holds the keyframes' (addKeyframe).
      PoseGraphEdge m;
      m.measurement = between(last_tracked, res.pose);
      m.sigma_xy = params_.sigma_xy;
      m.sigma_theta = params_.sigma_theta;
      tracked_ = compose(last_tracked, fuseIncrements(m, between(tracked_odom_, odom), params_.odom_edge_sigma_xy,
                                                      params_.odom_edge_sigma_theta));
    }
  }
  if (params_.track_every_scan)
  {
    tracked_odom_ = odom;
    map_to_odom_ = compose(tracked_, inverse(odom));
  }
  else
    tracked_ = last.pose;  // the odometry since the keyframe stays the prediction
  current_pose_ = params_.track_every_scan ? tracked_ : predicted;
  last_scan_in_keyframe_ = between(last.pose, current_pose_);
}

void Slam::addKeyframe(double stamp, const Pose2D& odom, const RangeScan& scan, const Pose2D& predicted,
                       const RivalPredictions& rivals)
{
  const Keyframe& last = keyframes_.back();
  const Pose2D delta = between(last.odom, odom);
  Keyframe kf;
  kf.stamp = stamp;
  kf.odom = odom;
  kf.scan = scan;
  kf.match_points = matchPoints(scan.hits);
  kf.travelled = last.travelled + translationNorm(delta);
  current_pose_ = predicted;

  MatchResult res = matchLocal(predicted, localPointsInReach(predicted, kf.match_points), !rivals.any());
  if (res.ok)
    stall_search_spent_ = false;
  res = matchFromRivals(res, predicted, rivals, kf.match_points);
  res = matchInWiderHeadings(res, predicted, kf.match_points);
  PoseGraphEdge edge;
  edge.from = static_cast<int>(keyframes_.size()) - 1;
  edge.sigma_xy = params_.sigma_xy;
  edge.sigma_theta = params_.sigma_theta;
  if (res.ok)
  {
    kf.pose = res.pose;
  }
  else
  {
    // Nothing reliable to match against (e.g. open space), or the odometry jumped beyond the
    // window: trust odometry, loosely (and with weak_step_cauchy so that a closure can overrule
    // it whole).
    ++stats_.weak_matches;
    kf.pose = predicted;
    edge.sigma_xy *= 5.0;
    edge.sigma_theta *= 5.0;
    edge.redescending = params_.weak_step_cauchy;
  }
  rememberCorrection(predicted, kf.pose);
  edge.measurement = between(last.pose, kf.pose);
  const bool odom_edges = params_.odom_edge_sigma_xy > 0.0 && params_.odom_edge_sigma_theta > 0.0;
  if (odom_edges)
  {
    // Start the new node where the two edges to it agree best (the optimum of this chain link):
    // the graph is optimised only at loop closures, and the matcher alone lets the heading creep
    // by a fraction of a degree per keyframe towards a local map that is itself a little turned.
    kf.pose =
        compose(last.pose, fuseIncrements(edge, delta, params_.odom_edge_sigma_xy, params_.odom_edge_sigma_theta));
  }
  keyframes_.push_back(std::move(kf));
  const int index = static_cast<int>(keyframes_.size()) - 1;
  graph_.addNode(keyframes_.back().pose);
  edge.to = index;
  graph_.addEdge(edge);
  if (odom_edges)
  {
    PoseGraphEdge odom_edge;
    odom_edge.from = edge.from;
    odom_edge.to = index;
    odom_edge.measurement = delta;
    odom_edge.sigma_xy = params_.odom_edge_sigma_xy;
    odom_edge.sigma_theta = params_.odom_edge_sigma_theta;
    graph_.addEdge(odom_edge);
  }
  if (!global_stale_)
    global_.insertScan(keyframes_.back().pose, keyframes_.back().scan);
  insertIntoLocalMaps(index);
  ++stats_.keyframes;
  ++map_version_;
}

void Slam::insertIntoLocalMaps(int index)
{
  const int n = std::max(2, params_.local_map_scans);
  for (int m = 0; m < 2; ++m)
  {
    LocalMap& lm = local_[m];
    if (m == 1 && index < n / 2)
      continue;  // staggered so one local map is always well populated
    if (static_cast<int>(lm.members.size()) >= n)
    {
      lm.grid.clear();
      lm.members.clear();
    }
    const Keyframe& k = keyframes_[static_cast<size_t>(index)];
    lm.grid.insertScan(k.pose, k.scan);
    lm.members.push_back(index);
  }
  local_field_dirty_ = true;
}

void Slam::rebuildLocalMaps()
{
  for (LocalMap& lm : local_)
  {
    lm.grid.clear();
    for (int i : lm.members)
      lm.grid.insertScan(keyframes_[static_cast<size_t>(i)].pose, keyframes_[static_cast<size_t>(i)].scan);
  }
  local_field_dirty_ = true;
}

const OccupancyGrid& Slam::globalMap() const
{
  if (global_stale_)
  {
    global_.clear();
    insertKeyframes(global_, 0, static_cast<int>(keyframes_.size()));
    global_stale_ = false;
  }
  return global_;
}

void Slam::insertKeyframes(OccupancyGrid& grid, int first, int end) const
{
  std::vector<int> which;
  for (int i = first; i < end; ++i)
    which.push_back(i);
  insertKeyframes(grid, which);
}

void Slam::insertKeyframes(OccupancyGrid& grid, const std::vector<int>& which) const
{
  if (which.empty())
    return;
  Point2D lo{1e300, 1e300}, hi{-1e300, -1e300};
  auto extend = [&](const Point2D& p)
  {
    lo = Point2D{std::min(lo.x, p.x), std::min(lo.y, p.y)};
    hi = Point2D{std::max(hi.x, p.x), std::max(hi.y, p.y)};
  };
  for (int i : which)
  {
    const Keyframe& k = keyframes_[static_cast<size_t>(i)];
    extend(transformPoint(k.pose, k.scan.origin));
    for (const Point2D& p : k.scan.hits)
      extend(transformPoint(k.pose, p));
    for (const Point2D& p : k.scan.misses)
      extend(transformPoint(k.pose, p));
  }
  grid.reserve(lo, hi);
  for (int i : which)
    grid.insertScan(keyframes_[static_cast<size_t>(i)].pose, keyframes_[static_cast<size_t>(i)].scan);
}

void Slam::markGlobalMapStale()
{
  global_ = OccupancyGrid(params_.grid);  // its memory is not needed until it is rendered again
  global_stale_ = true;
  ++map_version_;
}

bool Slam::tryLoopClosure(int current)
{
  const Keyframe& kf = keyframes_[static_cast<size_t>(current)];
  LoopMatch match;
  // The nearest keyframe of each earlier pass near the estimate, nearest first (loop_max_candidates).
  const std::vector<int> passes =
      loopCandidatesByPass(keyframes_, current, kf.pose, current, params_.loop_search_radius, params_.loop_min_travel,
                           params_.loop_submap_scans, std::max(1, params_.loop_max_candidates));
  int candidate = passes.empty() ? -1 : passes.front();
  // Every loop_global_interval of path, wherever the estimate is: drift may have put it among
  // no walls, or among the wrong ones, where the recent path agrees with itself.
  double window = 0.0;
  if (globalSearchDue(current, window))
  {
    last_global_travelled_ = kf.travelled;
    ++stats_.loop_global_attempts;
    if (searchGlobally(current, window, match))
    {
      // Among the keyframes of the coarse map the query was matched against: a newer one near
      // the matched pose lies on the drifted path itself. The Freiburg hospital's return, drawn
      // 9 m along its first corridor, had one there; the closure was then judged by the drift
      // possible since it (0.8 m) and rejected, twice, until the log ended (0.52 m mean error).
      const int place = findLoopCandidate(current, match.result.pose, coarse_count_);
      if (place >= 0)
      {
        candidate = place;
        ++stats_.loop_global_matches;
      }
      else
        match.global = false;
    }
  }
  if (candidate < 0)
    return false;
  last_loop_attempt_ = current;
  ++stats_.loop_attempts;
  expireHeldClosures();
  if (!match.global)
  {
    // The nearest keyframe's pass may have looked the other way: a forward-looking laser sees
    // a corridor's two ends from its two passes. The next pass's submap may show what this
    // keyframe sees.
    bool matched = false;
    for (const int c : passes)
      if (matchCandidateSubmap(current, c, match))
      {
        candidate = c;
        matched = true;
        break;
      }
    if (!matched)
      return false;
  }
  return closeLoop(current, candidate, match);
}

bool Slam::closeLoop(int current, int candidate, LoopMatch& match)
{
  stats_.last_closure = {
      candidate, current, match.result.score, match.score_at_estimate, match.constraint_ratio, match.correction, false,
      false,     ""};
  if (const char* why = implausibleClosure(current, candidate, match))
    return rejectClosure(why);
  std::vector<PoseGraphEdge> added;
  if (!confirmClosure(current, candidate, match, added))
    return false;
  return applyClosure(added, match);
}

int Slam::findLoopCandidate(int current, const Pose2D& around, int end) const
{
  return nearestLoopCandidate(keyframes_, current, around, end, params_.loop_search_radius, params_.loop_min_travel);
}

bool closureNeedsConfirmation(const SlamParams& params, double moved, double score, bool unique)
{
  if (params.loop_confirm_correction <= 0.0 || moved <= params.loop_confirm_correction)
    return false;
  return !(unique && moved <= params.loop_large_correction && score >= params.loop_min_score_large);
}

int nearestLoopCandidate(const std::vector<Keyframe>& keyframes, int current, const Pose2D& around, int end,
                         double radius, double min_travel)
{
  const std::vector<int> nearest = loopCandidatesByPass(keyframes, current, around, end, radius, min_travel, 0, 1);
  return nearest.empty() ? -1 : nearest.front();
}

std::vector<int> loopCandidatesByPass(const std::vector<Keyframe>& keyframes, int current, const Pose2D& around,
                                      int end, double radius, double min_travel, int separation, int count)
{
  const Keyframe& kf = keyframes[static_cast<size_t>(current)];
  std::vector<std::pair<double, int>> near;
  for (int i = 0; i < std::min(current, end); ++i)
  {
    const Keyframe& k = keyframes[static_cast<size_t>(i)];
    if (kf.travelled - k.travelled < min_travel)
      break;  // travelled grows with the index
    const double d = std::hypot(k.pose.x - around.x, k.pose.y - around.y);
    if (d < radius)
      near.emplace_back(d, i);
  }
  std::sort(near.begin(), near.end());
  std::vector<int> chosen;
  for (const auto& [d, i] : near)
  {
    if (static_cast<int>(chosen.size()) >= count)
      break;
    if (std::all_of(chosen.begin(), chosen.end(), [&](int c) { return std::abs(c - i) > separation; }))
      chosen.push_back(i);
  }
  return chosen;
}

void Slam::expireHeldClosures()
{
  // Global hits come one per loop_global_interval of travel, local attempts every few keyframes.
  const double global_wait = params_.loop_global_interval * params_.loop_global_confirmations;
  for (auto it = held_.begin(); it != held_.end();)
  {
    if (it->global ? keyframes_.back().travelled - it->travelled <= global_wait : it->attempts_left-- > 0)
    {
      ++it;
      continue;
    }
    ++stats_.loop_unconfirmed;
    stats_.last_unconfirmed = it->record;
    stats_.last_unconfirmed.reason = "dropped: no later attempt confirmed it";
    it = held_.erase(it);
  }
}

bool Slam::matchCandidateSubmap(int current, int candidate, LoopMatch& match) const
{
  const Keyframe& kf = keyframes_[static_cast<size_t>(current)];
  // Render the candidate's neighbourhood (only keyframes well separated from the current one).
  OccupancyGrid sub(params_.grid);
  std::vector<int> members;
  // The window grows with the drift possible since the candidate (implausibleClosure's bound),
  // and then the submap follows the candidate's own pass that far (plus the path its
  // loop_submap_scans neighbours span): drift along a corridor puts the true place metres down
  // the old pass, outside a submap of a few metres. ACES comes back to its first corridors 4.7 m
  // off after 117 m when 53 of its scans take the odometry recorded with them (3 m window:
  // missed, 0.099 m mean error, worst relation 2.4 m; this: 0.034). Where the window does not
  // grow, the submap stays the candidate's neighbours: grown for every closure, it merged more of
  // a drifted pass (slam_loop_closure seed 4, 3.5 m laser: closed precision 0.96 -> 0.87).
  const double candidate_travelled = keyframes_[static_cast<size_t>(candidate)].travelled;
  const double window =
      std::clamp(params_.loop_max_correction + params_.loop_max_correction_per_m * (kf.travelled - candidate_travelled),
                 params_.loop_window_linear, std::max(params_.loop_window_linear, params_.loop_window_linear_max));
  const double along =
      window > params_.loop_window_linear ? window + params_.loop_submap_scans * params_.linear_update : 0.0;
  int lo = std::max(0, candidate - params_.loop_submap_scans);
  int hi = std::min(current - 1, candidate + params_.loop_submap_scans);
  while (lo > 0 && candidate_travelled - keyframes_[static_cast<size_t>(lo - 1)].travelled <= along)
    --lo;
  while (hi < current - 1 && keyframes_[static_cast<size_t>(hi + 1)].travelled - candidate_travelled <= along)
    ++hi;
  for (int j = lo; j <= hi; ++j)
    if (kf.travelled - keyframes_[static_cast<size_t>(j)].travelled >= 0.5 * params_.loop_min_travel)
      members.push_back(j);
  insertKeyframes(sub, members);
  if (sub.empty())
    return false;
  // Chosen at the estimate: the closure may move the scan by up to the window, but a point is
  // only wrongly kept or left out where the submap's reach ends.
  const std::vector<Point2D> points = pointsInReach(members, kf.pose, kf.match_points);
  const MatchField field = matchFieldAround(sub, params_.match_sigma, window, kf.pose, maxRange(points));
  MatchRequest req;
  req.initial = kf.pose;
  req.linear_window = window;
  req.angular_window = params_.loop_window_angular;
  req.min_score = params_.loop_min_score;
  match.result = matchScan(field, points, req);
  if (!match.result.ok)
    return false;
  // A corridor matches equally well anywhere along it: such a closure would pull the graph by
  // an arbitrary amount in that direction.
  match.constraint_ratio = translationConstraintRatio(field, points, match.result.pose);
  if (match.constraint_ratio < params_.loop_min_constraint_ratio)
    return false;
  match.correction = between(kf.pose, match.result.pose);
  match.score_at_estimate = scorePose(field, points, kf.pose);
  const double moved = translationNorm(match.correction);
  if (params_.loop_unique_ratio > 0.0 && closureNeedsConfirmation(params_, moved, match.result.score, false) &&
      !closureNeedsConfirmation(params_, moved, match.result.score, true))
  {
    // Searched only where its answer spares a confirmation (the only use of `unique`): the best
    // that fits elsewhere, the same search with the best match's surroundings left out,
    // accepting only what scores loop_unique_ratio of it.
    MatchRequest elsewhere = req;
    elsewhere.refine = false;
    elsewhere.exclude_center = match.result.pose;
    elsewhere.exclude_radius = params_.loop_unique_separation;
    elsewhere.min_score = params_.loop_unique_ratio * match.result.score;
    match.unique = !matchScan(field, points, elsewhere).ok;
  }
  return true;
}

const char* Slam::implausibleClosure(int current, int candidate, const LoopMatch& match) const
{
  const Keyframe& kf = keyframes_[static_cast<size_t>(current)];
  const double moved = translationNorm(match.correction);
  // A closure that merely confirms the estimate is harmless however weak. One that moves the
  // pose must fit clearly better there than at the estimate: in a well-structured place a
  // few centimetres off costs most of the score, while along an aisle of identical shelves
  // (or seen from the opposite side) both poses fit about equally.
  if (moved > 2.0 * params_.grid.resolution &&
      match.result.score < params_.loop_min_score_gain * match.score_at_estimate)
    return "rejected: it fits hardly better than the current estimate (ambiguous place)";
  // A global proposal agreed with itself over a query of loop_global_query_travel metres, and waits
  // for loop_global_confirmations agreeing attempts: it may correct more drift than one scan's.
  const double per_m = match.global ? params_.loop_global_max_correction_per_m : params_.loop_max_correction_per_m;
  const double max_correction =
      params_.loop_max_correction + per_m * (kf.travelled - keyframes_[static_cast<size_t>(candidate)].travelled);
  if (moved > max_correction)
    return "rejected: correction larger than the drift possible since the candidate";
  return nullptr;
}

// A large correction is held until a later attempt finds the same one (a one-off match in a
// repetitive place is not seen again; a weak one needs loop_weak_confirmations attempts in all);
// then the edges of all agreeing attempts go in. False while held.
bool Slam::confirmClosure(int current, int candidate, LoopMatch& match, std::vector<PoseGraphEdge>& added)
{
  const Keyframe& kf = keyframes_[static_cast<size_t>(current)];
  PoseGraphEdge edge;
  edge.from = candidate;
  edge.to = current;
  edge.measurement = between(keyframes_[static_cast<size_t>(candidate)].pose, match.result.pose);
  edge.sigma_xy = params_.loop_sigma_xy;
  edge.sigma_theta = params_.loop_sigma_theta;
  edge.robust = true;
  if (match.global)  // matched on the coarse grid
    edge.sigma_xy = std::max(edge.sigma_xy, 0.5 * params_.loop_global_resolution);

  const double moved = translationNorm(match.correction);
  if (closureNeedsConfirmation(params_, moved, match.result.score, match.unique))
  {
    HeldClosure now;
    now.edge = edge;
    now.map_correction = compose(match.result.pose, inverse(kf.pose));
    now.record = stats_.last_closure;
    now.attempts_left = params_.loop_confirm_attempts;
    now.strong = moved <= params_.loop_large_correction || match.result.score >= params_.loop_min_score_large;
    now.global = match.global;
    now.travelled = kf.travelled;
    // Attempts agree when their corrections, applied to the current pose, land in the same
    // place: the drift they remove grows only slowly between two attempts a few keyframes apart.
    const Pose2D a = compose(now.map_correction, kf.pose);
    std::vector<size_t> agreeing;
    bool strong = now.strong;
    for (size_t i = 0; i < held_.size(); ++i)
    {
      const Pose2D b = compose(held_[i].map_correction, kf.pose);
      // Global hits are a coarse cell apart at best, and loop_global_interval of path apart.
      const double tolerance = match.global || held_[i].global
                                   ? std::max(params_.loop_confirm_tolerance, params_.loop_global_resolution)
                                   : params_.loop_confirm_tolerance;
      if (std::hypot(a.x - b.x, a.y - b.y) <= tolerance && std::abs(wrapAngle(a.theta - b.theta)) <= 0.05)
      {
        agreeing.push_back(i);
        strong = strong || held_[i].strong;
        match.global = match.global || held_[i].global;
      }
    }
    now.global = match.global;
    // A global hit is scored on the coarse grid (0.5-0.75 for the hospital's true place), so the
    // weak-match rule does not apply; its own count does.
    const size_t needed = match.global ? static_cast<size_t>(params_.loop_global_confirmations)
                          : strong     ? 2
                                       : static_cast<size_t>(std::max(2, params_.loop_weak_confirmations));
    if (agreeing.size() + 1 < needed)
    {
      now.record.reason = match.global ? "held: a place a global search found, until more attempts agree"
                          : now.strong ? "held until a later attempt finds the same correction"
                                       : "held: a large correction from a weak match, until more attempts agree";
      stats_.last_closure.reason = now.record.reason;
      held_.push_back(now);
      ++stats_.loop_held;
      return false;
    }
    for (size_t i : agreeing)
      added.push_back(held_[i].edge);
    // The others disagree with a closure about to be applied, and their corrections were
    // measured against poses the optimisation is about to move.
    for (size_t i = 0; i < held_.size(); ++i)
      if (std::find(agreeing.begin(), agreeing.end(), i) == agreeing.end())
      {
        ++stats_.loop_unconfirmed;
        stats_.last_unconfirmed = held_[i].record;
        stats_.last_unconfirmed.reason = "dropped: a closure that disagrees with it was confirmed";
      }
    held_.clear();
  }
  added.push_back(edge);
  return true;
}

// The edges go into the graph, which is optimised and the map re-rendered; a closure the
// optimised graph cannot honour is undone.
bool Slam::applyClosure(const std::vector<PoseGraphEdge>& added, const LoopMatch& match)
{
  for (const PoseGraphEdge& e : added)
    graph_.addEdge(e);
  const Pose2D& correction = match.correction;
  if (translationNorm(correction) < params_.grid.resolution && std::abs(correction.theta) < 0.01)
  {
    ++stats_.loop_closures;
    stats_.last_closure.accepted = true;
    stats_.last_closure.unique = match.unique;
    return true;  // already consistent: keep the constraint, skip the expensive re-render
  }
  if (match.global)
  {
    int first = added.front().from;
    for (const PoseGraphEdge& e : added)
      first = std::min(first, e.from);
    const Keyframe& kf = keyframes_[static_cast<size_t>(added.back().to)];
    spreadCorrection(first, compose(match.result.pose, inverse(kf.pose)));
  }
  graph_.optimize();
  // The robust loss lets a wrong closure sit in the graph half-satisfied while it bends the
  // rest.
  for (const PoseGraphEdge& e : added)
  {
    const Pose2D r = graph_.residual(e);
    if (translationNorm(r) > params_.loop_max_residual_sigma * params_.loop_sigma_xy ||
        std::abs(r.theta) > params_.loop_max_residual_sigma * params_.loop_sigma_theta)
    {
      for (size_t k = 0; k < added.size(); ++k)
        graph_.popEdge();
      for (size_t i = 0; i < keyframes_.size(); ++i)
        graph_.setNode(static_cast<int>(i), keyframes_[i].pose);
      return rejectClosure("rejected: the optimised graph disagrees with it");
    }
  }
  ++stats_.loop_closures;
  if (match.global)
    ++stats_.loop_global_closures;
  stats_.last_closure.accepted = true;
  stats_.last_closure.unique = match.unique;
  for (size_t i = 0; i < keyframes_.size(); ++i)
    keyframes_[i].pose = graph_.node(static_cast<int>(i));
  have_uncorrected_ = false;  // in the map as it was before the closure moved it
  coarse_stale_ = true;
  markGlobalMapStale();
  rebuildLocalMaps();
  return true;
}

std::vector<LoopClosureRecord> loopClosureEvents(const SlamStats& before, const SlamStats& after)
{
  std::vector<LoopClosureRecord> events;
  if (after.loop_unconfirmed != before.loop_unconfirmed)
    events.push_back(after.last_unconfirmed);
  if (after.loop_closures != before.loop_closures || after.loop_rejected != before.loop_rejected ||
      after.loop_held != before.loop_held)
  {
    events.push_back(after.last_closure);
    if (after.last_closure.accepted)
      events.back().reason = after.last_closure.unique ? "accepted at once: unique and strong" : "accepted";
  }
  return events;
}

bool Slam::rejectClosure(const char* reason)
{
  ++stats_.loop_rejected;
  stats_.last_closure.reason = reason;
  return false;
}

}  // namespace mybot_navigation
