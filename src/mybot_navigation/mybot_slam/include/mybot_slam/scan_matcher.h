// Correlative multi-resolution scan matching (Olson 2009; branch and bound over max-pooled
// lookup grids as in Hess et al. 2016) followed by a Gauss-Newton refinement on a smooth field.
#pragma once

#include <cstdint>
#include <vector>

#include "mybot_nav_common/grid_map.h"
#include "mybot_slam/occupancy_grid.h"

namespace mybot_navigation
{

// Lookup field on the world lattice: 1 at occupied cells, a Gaussian fall-off around them, and
// `levels` max-pooled copies (level h = max over a 2^h x 2^h block) for branch and bound.
class MatchField
{
public:
  MatchField() = default;
  // Occupied cells: P(occ) > 0.5 in the grid, restricted to lattice box [x0,x1]x[y0,y1] if given.
  // In cells the grid never observed (log-odds still 0: behind a wall's mapped face, past where
  // its beams ended) the fall-off is multiplied by unobserved_weight (1 = no difference).
  MatchField(const OccupancyGrid& grid, double sigma, int levels);
  MatchField(const OccupancyGrid& grid, double sigma, int levels, int x0, int y0, int x1, int y1,
             double unobserved_weight = 1.0);
  // Occupied cells: value >= occupied_threshold in a static map (origin yaw must be 0).
  MatchField(const GridMap& map, double sigma, int levels, int occupied_threshold = 65);

  bool empty() const { return width_ == 0; }
  int levels() const { return static_cast<int>(levels_.size()); }
  double resolution() const { return resolution_; }
  // Value in [0,1] at a lattice cell for a level (0 outside).
  float value(int level, int gx, int gy) const
  {
    const int x = gx - min_x_, y = gy - min_y_;
    if (x < 0 || y < 0 || x >= width_ || y >= height_)
      return 0.0f;
    return levels_[level][static_cast<size_t>(y) * width_ + x] * (1.0f / 255.0f);
  }
  // The raw lattice of a level (values 0-255 for 0-1), row by row from lattice cell
  // (minCellX, minCellY), width() cells a row: for loops that check their bounds once.
  const uint8_t* data(int level) const { return levels_[level].data(); }
  int minCellX() const { return min_x_; }
  int minCellY() const { return min_y_; }
  int width() const { return width_; }
  int height() const { return height_; }
  // Bilinear interpolation of level 0 at a world point, with its gradient (per metre).
  double interpolate(double wx, double wy, double* dfdx, double* dfdy) const;

private:
  // Level 0: 1 at the occupied cells and the Gaussian fall-off around them.
  void splat(const std::vector<std::pair<int, int>>& occupied, int bx0, int by0, int bx1, int by1, double sigma,
             int levels);
  // Levels 1.. from level 0 by max-pooling.
  void pool(int levels);

  double resolution_ = 0.05;
  int min_x_ = 0, min_y_ = 0, width_ = 0, height_ = 0;
  std::vector<std::vector<uint8_t>> levels_;
};

// Enough max-pooled levels that the coarsest block spans a search window (m) at a resolution
// (m/cell), at most 7: the branch and bound then starts from a handful of blocks.
inline int matchFieldLevels(double window, double resolution)
{
  int levels = 1;
  while ((1 << (levels - 1)) * resolution < window && levels < 7)
    ++levels;
  return levels;
}

// The part of the field that matchScan (with its refinement, translationConstraintRatio and
// scorePose) can read when it searches points at most `reach` m from the base within `window`
// m of `around`: built over only that box of `grid`, and there equal to a field over the whole
// grid, cell for cell at every level (the box also holds the coarsest block past the window and
// the fall-off of walls just outside it). A loop-closure submap spans its candidate's whole pass
// and then 5 m of margin: building the field over all of it was a quarter of FR079's replay.
MatchField matchFieldAround(const OccupancyGrid& grid, double sigma, double window, const Pose2D& around, double reach,
                            double unobserved_weight = 1.0);

struct MatchRequest
{
  Pose2D initial;                // prior pose of the base in the world
  double linear_window = 0.3;    // m, half width of the square translation window
  double angular_window = 0.35;  // rad, half width of the rotation window
  double min_score = 0.0;        // candidates scoring below are never accepted
  bool refine = true;            // Gauss-Newton refinement after the discrete search
  // Motion prior: the score is reduced by weight * squared distance from `initial` (per m^2 and
  // per rad^2). In a corridor the match is flat along it; the prior keeps the prediction there
  // instead of an arbitrary end of the plateau.
  double translation_weight = 0.0;
  double rotation_weight = 0.0;
  // Beyond this distance from `initial` the translation penalty stops growing (m; 0: never
  // capped): a pose that fits clearly better still wins when the odometry is far off.
  double translation_prior_cap = 0.0;
  // Translations within exclude_radius of exclude_center are not candidates (m; 0: none): the
  // search for a second place that fits, away from the best match (loop closure's uniqueness).
  Pose2D exclude_center;
  double exclude_radius = 0.0;
};

struct MatchResult
{
  bool ok = false;
  Pose2D pose;
  double score = 0.0;  // mean field value of the scan points at the result, in [0,1]
};

// Points in the base frame reduced to at most one per `cell` (keeps matching cost bounded and
// removes the density bias towards nearby walls).
std::vector<Point2D> voxelFilter(const std::vector<Point2D>& points, double cell);

// voxelFilter at `cell`, or, where that keeps fewer than `min_points`, at half the cell, then a
// quarter (no finer): Cartographer's adaptive voxel filter (Hess et al. 2016's implementation,
// `adaptive_voxel_filter`: the largest cell up to max_length 0.5 m that keeps min_num_points 200),
// in halvings from our fixed cell. A match is only as sure as its points are many.
std::vector<Point2D> adaptiveVoxelFilter(const std::vector<Point2D>& points, double cell, size_t min_points);

MatchResult matchScan(const MatchField& field, const std::vector<Point2D>& points, const MatchRequest& request);

// Mean field value of the points at a pose (the score used by matchScan).
double scorePose(const MatchField& field, const std::vector<Point2D>& points, const Pose2D& pose);

// How well the points constrain translation at a pose: ratio of the smallest to the largest
// eigenvalue of the translational block of J^T J (near 0 in a featureless corridor).
double translationConstraintRatio(const MatchField& field, const std::vector<Point2D>& points, const Pose2D& pose);

// Gauss-Newton on sum (1 - f(T p))^2 with bilinear interpolation; stays within max_step of start.
// prior / translation_weight / rotation_weight pull the pose towards `prior` (0: no prior); the
// translation pull stops beyond translation_prior_cap (0: never).
Pose2D refinePose(const MatchField& field, const std::vector<Point2D>& points, const Pose2D& start, int iterations = 10,
                  double max_step = 0.1, const Pose2D* prior = nullptr, double translation_weight = 0.0,
                  double rotation_weight = 0.0, double translation_prior_cap = 0.0);

}  // namespace mybot_navigation
