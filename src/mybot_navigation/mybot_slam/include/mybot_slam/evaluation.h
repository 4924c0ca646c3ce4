// Map and trajectory scoring against ground truth.
#pragma once

#include <string>
#include <vector>

#include "mybot_nav_common/grid_map.h"

namespace mybot_navigation
{

struct MapScore
{
  double precision = 0.0;  // occupied cells of the estimate that are occupied in the truth (within tolerance)
  double recall = 0.0;     // occupied truth cells that the estimate saw and marked occupied (within tolerance)
  int estimate_occupied = 0;
  int truth_occupied = 0;
};

// `truth_from_estimate` maps estimate-frame points into the truth frame. Recall only counts truth
// cells the estimate observed (known, within tolerance): walls never seen by the laser are not
// the mapper's fault. tolerance_cells (in estimate cells) = 1 accepts a one-cell offset.
MapScore scoreMap(const GridMap& estimate, const GridMap& truth, const Pose2D& truth_from_estimate,
                  int tolerance_cells = 1, int occupied_threshold = 65);

// Least-squares rigid alignment (rotation + translation) taking `estimate` onto `truth` positions.
Pose2D alignTrajectories(const std::vector<Pose2D>& estimate, const std::vector<Pose2D>& truth);

// Absolute trajectory error (RMS of position differences after applying `truth_from_estimate`).
double absoluteTrajectoryRmse(const std::vector<Pose2D>& estimate, const std::vector<Pose2D>& truth,
                              const Pose2D& truth_from_estimate);

struct RelativePoseError
{
  double translation_rms = 0.0;  // m
  double rotation_rms = 0.0;     // rad
  int pairs = 0;
};

// Kuemmerle et al. 2009: compare relative motions between pose pairs `step` apart (indices).
RelativePoseError relativePoseError(const std::vector<Pose2D>& estimate, const std::vector<Pose2D>& truth,
                                    int step = 1);

// Kuemmerle et al. 2009, "On measuring the accuracy of SLAM algorithms": the error of a
// trajectory on a set of relations, each the true relative pose inv(P(t1)) * P(t2) between the
// robot's poses at two scan stamps. Per relation, the estimate's relative pose is compared with
// it: translational error |t_est - t_true| (m), rotational error |wrap(yaw_est - yaw_true)|.
struct Relation
{
  double t1 = 0.0, t2 = 0.0;  // scan stamps (s)
  Pose2D motion;              // true inv(P(t1)) * P(t2): x, y (m), yaw (rad)
};

struct ErrorStats
{
  int count = 0;
  double mean = 0.0, std = 0.0, max = 0.0;  // of the absolute error
  double squared_mean = 0.0, squared_std = 0.0;
};

struct RelationScore
{
  ErrorStats translation, rotation_deg;              // all relations
  ErrorStats local_translation, local_rotation_deg;  // t2 - t1 <= local_max_dt
  ErrorStats loop_translation, loop_rotation_deg;    // longer relations: loops and revisits
  int missing = 0;                                   // relations whose stamps the trajectory lacks
};

struct StampedPose
{
  double stamp = 0.0;
  Pose2D pose;
};

// `trajectory`: poses by scan stamp (any order); a relation's stamp takes the pose stamped
// nearest to it, within `stamp_tolerance` s (none there: the relation is missing). Relations under `local_max_dt` s
// apart count as local (2 s: consecutive scans and short stretches, where odometry alone does well).
RelationScore scoreRelations(const std::vector<StampedPose>& trajectory, const std::vector<Relation>& relations,
                             double local_max_dt = 2.0, double stamp_tolerance = 1e-3);

// Reads a relations file: "t1 t2 x y z roll pitch yaw" per line, '#' comments. Throws
// std::runtime_error naming the file and line.
std::vector<Relation> readRelations(const std::string& path);

}  // namespace mybot_navigation
