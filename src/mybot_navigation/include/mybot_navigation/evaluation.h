// Map and trajectory scoring against ground truth.
#pragma once

#include <vector>

#include "mybot_navigation/grid_map.h"

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

}  // namespace mybot_navigation
