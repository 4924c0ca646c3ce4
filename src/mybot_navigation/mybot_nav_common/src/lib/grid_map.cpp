#include "mybot_nav_common/grid_map.h"

#include <cmath>

namespace mybot_navigation
{

bool GridMap::worldToCell(double wx, double wy, int& cx, int& cy) const
{
  const Point2D local = transformPoint(inverse(info.origin), {wx, wy});
  cx = cellIndex(local.x / info.resolution);
  cy = cellIndex(local.y / info.resolution);
  return inside(cx, cy);
}

Point2D GridMap::cellCenter(int cx, int cy) const
{
  return transformPoint(info.origin, {(cx + 0.5) * info.resolution, (cy + 0.5) * info.resolution});
}

}  // namespace mybot_navigation
