// Global planner on a costmap: A* or Dijkstra (global_planner's names and cell cost model), then
// line-of-sight smoothing that never trades clearance for length. No ROS types.
#pragma once

#include <string>
#include <vector>

#include "mybot_move_base/costmap.h"

namespace mybot_navigation
{

struct PlannerParams
{
  bool use_dijkstra = true;        // global_planner: false = A*
  bool allow_unknown = true;       // plan through NO_INFORMATION cells
  double default_tolerance = 0.0;  // m; a blocked goal is moved to the nearest free cell within it
  double neutral_cost = 50.0;      // cost of a free cell
  double cost_factor = 3.0;        // cell cost = neutral_cost + cost_factor * costmap cost
  int lethal_cost = 253;           // costmap values >= this are not traversable
  bool smooth_path = true;         // shortcut the grid path where clearance is not worse
};

std::string validate(const PlannerParams& p);

enum class PlanStatus
{
  Ok,
  StartOffMap,
  GoalOffMap,
  GoalInObstacle,
  NoPath
};

struct PlanResult
{
  PlanStatus status = PlanStatus::NoPath;
  std::string message;
  std::vector<Pose2D> path;  // start .. goal, about one cell apart, heading along the path
  double length = 0.0;       // m
  int expanded = 0;          // cells popped from the open list
};

const char* toString(PlanStatus s);

class GlobalPlanner
{
public:
  explicit GlobalPlanner(const PlannerParams& params = PlannerParams()) : params_(params) {}
  PlanResult makePlan(const Costmap& costmap, const Pose2D& start, const Pose2D& goal) const;
  const PlannerParams& params() const { return params_; }

private:
  PlannerParams params_;
};

// Length of a polyline (m).
double pathLength(const std::vector<Pose2D>& path);

}  // namespace mybot_navigation
