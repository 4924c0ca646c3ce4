// Helpers of the costmap and planner tests: a round robot's costmap parameters, an empty room.
#pragma once

#include "mybot_move_base/costmap.h"
#include "synthetic_world.h"

namespace mybot_navigation
{
namespace costmap_test
{

inline CostmapParams circleParams(double radius = 0.2)
{
  CostmapParams p;
  p.robot_radius = radius;
  p.footprint_padding = 0.0;
  p.inflation_radius = 0.55;
  p.cost_scaling_factor = 10.0;
  return p;
}

inline GridMap emptyRoom()
{
  return makeWorld(6.0, 4.0, 0.05, {});
}

}  // namespace costmap_test
}  // namespace mybot_navigation
