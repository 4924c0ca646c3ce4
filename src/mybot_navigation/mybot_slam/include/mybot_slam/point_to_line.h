// Point-to-line registration of a scan against reference points (Censi 2008, "An ICP variant
// using a point-to-line metric"; the 2D form of Chen and Medioni's point-to-plane error). The
// grid matchers (scan_matcher.h) find the right basin but see walls only as cell centres of a
// 5 cm lattice; this refines a pose against the beam end points themselves, where a wall is a
// line through them and a scan point's error is its distance to that line. No ROS.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "mybot_nav_common/grid_map.h"
#include "mybot_nav_common/pose2d.h"

namespace mybot_navigation
{

// Reference points (world frame) with the normal of the line through each one's neighbours,
// looked up by a spatial hash. Points whose neighbours do not form a line (a corner, clutter,
// fewer than three) get no normal and are never matched.
class LineReference
{
public:
  // neighbour_radius: the neighbourhood a normal is fitted to (m); max_flatness: the largest
  // ratio of the fit's smaller to larger spread (eigenvalue) that still counts as a line;
  // sparse_radius: where no line fits within neighbour_radius, the wider neighbourhood tried next.
  // A laser's hits thin out with range (1 deg beams: 0.15 m apart at 8.6 m), and in a corridor
  // the far walls across it are what pins the pose along it: on ACES (50 m laser, long
  // corridors) 0.15 alone left them unmatched, 0.3 alone blurred Intel's near corners.
  LineReference(const std::vector<Point2D>& points, double neighbour_radius = 0.15, double max_flatness = 0.05,
                double sparse_radius = 0.3);

  size_t size() const { return points_.size(); }
  // The reference point with a normal nearest to `w` within max_distance (m); false if none.
  // max_distance must not exceed the neighbour_radius the reference was built with.
  bool nearest(const Point2D& w, double max_distance, Point2D& point, Point2D& normal) const;

private:
  using Buckets = std::unordered_map<std::uint64_t, std::vector<int>>;
  template <typename F>
  void forEachNear(const Buckets& buckets, int cx, int cy, int ring, F&& f) const;
  // The line through p's neighbours within radius: their mean and unit normal; false if they are
  // fewer than three or not a line.
  bool fitLine(const std::vector<Point2D>& points, const Buckets& all, const Point2D& p, double radius,
               double max_flatness, Point2D& mean, Point2D& normal) const;
  std::uint64_t key(int cx, int cy) const { return cellKey(cx, cy); }
  int cellOf(double v) const;

  double cell_;
  std::vector<Point2D> points_;   // with a normal only
  std::vector<Point2D> normals_;  // unit
  Buckets buckets_;
};

struct PointToLineParams
{
  int iterations = 20;
  double max_distance = 0.1;  // m: scan points farther from every line are outliers
  double huber = 0.02;        // m: residuals beyond weigh as |r| (one bad wall cannot pull)
  // Pull towards the initial pose, as if this many points sat at their own residual from it:
  // along a corridor the lines say nothing, and the pose stays where it started.
  double prior_weight = 1.0;
  double min_inlier_ratio = 0.5;  // of the scan points: fewer matched, no result
};

struct PointToLineResult
{
  bool ok = false;
  Pose2D pose;
  int inliers = 0;                // scan points within max_distance of a line at the result
  double rms = 0.0;               // m, their point-to-line distance
  double constraint_ratio = 0.0;  // smaller / larger eigenvalue of the translational information
};

// Gauss-Newton on sum huber(n_i . (T p_i - q_i)) over the scan points p_i (base frame) and their
// nearest reference lines (q_i, n_i), from `initial`, re-associating at every iteration.
PointToLineResult refinePointToLine(const LineReference& reference, const std::vector<Point2D>& points,
                                    const Pose2D& initial, const PointToLineParams& params = PointToLineParams());

}  // namespace mybot_navigation
