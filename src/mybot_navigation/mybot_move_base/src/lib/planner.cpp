#include "mybot_move_base/planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <sstream>

#include "mybot_nav_common/ray_cast.h"

namespace mybot_navigation
{

std::string validate(const PlannerParams& p)
{
  std::ostringstream e;
  if (!(p.neutral_cost > 0.0))
    e << "neutral_cost must be > 0 (got " << p.neutral_cost << ")";
  else if (p.cost_factor < 0.0)
    e << "cost_factor must be >= 0 (got " << p.cost_factor << ")";
  else if (p.lethal_cost < 1 || p.lethal_cost > 255)
    e << "lethal_cost must be in [1, 255] (got " << p.lethal_cost << ")";
  else if (p.default_tolerance < 0.0)
    e << "default_tolerance must be >= 0 (got " << p.default_tolerance << ")";
  return e.str();
}

const char* toString(PlanStatus s)
{
  switch (s)
  {
    case PlanStatus::Ok:
      return "ok";
    case PlanStatus::StartOffMap:
      return "the robot is outside the costmap";
    case PlanStatus::GoalOffMap:
      return "the goal is outside the map";
    case PlanStatus::GoalInObstacle:
      return "the goal is in an obstacle";
    case PlanStatus::NoPath:
      return "no path to the goal";
  }
  return "?";
}

double pathLength(const std::vector<Pose2D>& path)
{
  double l = 0.0;
  for (size_t i = 1; i < path.size(); ++i)
    l += std::hypot(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y);
  return l;
}

namespace
{
// The costmap as global_planner's search sees it, for one query from start cell (sx, sy).
struct SearchGrid
{
  const Costmap& cm;
  const PlannerParams& params;
  int sx, sy;
  double escape2;  // squared cells around the start the robot may escape through

  SearchGrid(const Costmap& costmap, const PlannerParams& p, int start_x, int start_y)
      : cm(costmap),
        params(p),
        sx(start_x),
        sy(start_y),
        // The robot may stand in inflated space (e.g. after being pushed): let it escape from
        // cells that are not lethal within its own circumscribed radius.
        escape2(std::pow(costmap.circumscribedRadius() / costmap.resolution() + 1.0, 2))
  {
  }
  bool passable(int x, int y) const
  {
    const uint8_t c = cm.cost(x, y);
    if (c == costs::kNoInformation)
      return params.allow_unknown;
    return c < params.lethal_cost;
  }
  bool traversable(int x, int y) const
  {
    if (passable(x, y))
      return true;
    const uint8_t c = cm.cost(x, y);
    return c != costs::kLethal && c != costs::kNoInformation && (x - sx) * (x - sx) + (y - sy) * (y - sy) <= escape2;
  }
  double cellCost(int x, int y) const
  {
    double c = cm.cost(x, y);
    if (c == costs::kNoInformation)
      c = 0.0;
    c = params.neutral_cost + params.cost_factor * c;
    return std::min(c, std::max(params.neutral_cost, params.lethal_cost - 1.0));  // global_planner's clamp
  }
};

// global_planner's default_tolerance: the nearest passable cell within the tolerance of a goal
// cell that is not passable itself. False when there is none.
bool nearestPassableGoal(const SearchGrid& grid, int& gx, int& gy)
{
  const int tol = static_cast<int>(std::floor(grid.params.default_tolerance / grid.cm.resolution()));
  double best = std::numeric_limits<double>::infinity();
  int bx = -1, by = -1;
  for (int dy = -tol; dy <= tol; ++dy)
    for (int dx = -tol; dx <= tol; ++dx)
    {
      const int x = gx + dx, y = gy + dy;
      const double d = std::hypot(dx, dy);
      if (d <= tol && grid.cm.inside(x, y) && grid.passable(x, y) && d < best)
      {
        best = d;
        bx = x;
        by = y;
      }
    }
  if (bx < 0)
    return false;
  gx = bx;
  gy = by;
  return true;
}

// A* (or Dijkstra with use_dijkstra) over the 8-connected grid, no corner cutting between two
// blocked cells. The cells from start to goal, or empty when the goal cannot be reached.
std::vector<int> searchGrid(const SearchGrid& grid, int gx, int gy, int& expanded)
{
  const int w = grid.cm.width(), h = grid.cm.height();
  const size_t n = static_cast<size_t>(w) * h;
  std::vector<float> g(n, std::numeric_limits<float>::infinity());
  std::vector<int> parent(n, -1);
  std::vector<uint8_t> closed(n, 0);
  using Node = std::pair<float, int>;
  std::priority_queue<Node, std::vector<Node>, std::greater<Node>> open;
  const double neutral = grid.params.neutral_cost;
  const bool dijkstra = grid.params.use_dijkstra;
  // Octile distance times the cheapest cell cost: admissible, so A* stays optimal.
  auto heuristic = [&](int x, int y)
  {
    if (dijkstra)
      return 0.0f;
    const int dx = std::abs(x - gx), dy = std::abs(y - gy);
    return static_cast<float>(neutral * (std::max(dx, dy) + (M_SQRT2 - 1.0) * std::min(dx, dy)));
  };
  const int start_i = grid.sy * w + grid.sx, goal_i = gy * w + gx;
  g[start_i] = 0.0f;
  open.push({heuristic(grid.sx, grid.sy), start_i});
  static const int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  static const int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  static const float kStep[8] = {1,
                                 1,
                                 1,
                                 1,
                                 static_cast<float>(M_SQRT2),
                                 static_cast<float>(M_SQRT2),
                                 static_cast<float>(M_SQRT2),
                                 static_cast<float>(M_SQRT2)};
  bool found = false;
  while (!open.empty())
  {
    const int i = open.top().second;
    open.pop();
    if (closed[i])
      continue;
    closed[i] = 1;
    ++expanded;
    if (i == goal_i)
    {
      found = true;
      break;
    }
    const int x = i % w, y = i / w;
    for (int k = 0; k < 8; ++k)
    {
      const int nx = x + kDx[k], ny = y + kDy[k];
      if (nx < 0 || ny < 0 || nx >= w || ny >= h)
        continue;
      const int j = ny * w + nx;
      if (closed[j] || !grid.traversable(nx, ny))
        continue;
      // No corner cutting between two blocked cells.
      if (k >= 4 && !grid.traversable(x + kDx[k], y) && !grid.traversable(x, y + kDy[k]))
        continue;
      const float ng = g[i] + kStep[k] * static_cast<float>(grid.cellCost(nx, ny));
      if (ng < g[j])
      {
        g[j] = ng;
        parent[j] = i;
        open.push({ng + heuristic(nx, ny), j});
      }
    }
  }
  std::vector<int> cells;
  if (!found)
    return cells;
  for (int i = goal_i; i >= 0; i = parent[i])
    cells.push_back(i);
  std::reverse(cells.begin(), cells.end());
  return cells;
}

// Shortcut: from each kept cell, jump to the farthest later cell whose straight segment stays
// traversable and no costlier than the grid path it replaces.
std::vector<int> shortcutPath(const SearchGrid& grid, const std::vector<int>& cells)
{
  const Costmap& cm = grid.cm;
  const int w = cm.width();
  std::vector<int> kept{cells.front()};
  size_t i = 0;
  while (i + 1 < cells.size())
  {
    size_t best = i + 1;
    uint8_t path_max = std::max(cm.data()[cells[i]], cm.data()[cells[i + 1]]);
    for (size_t j = i + 2; j < cells.size(); ++j)
    {
      path_max = std::max(path_max, cm.data()[cells[j]]);
      bool ok = true;
      traceLine(cells[i] % w, cells[i] / w, cells[j] % w, cells[j] / w,
                [&](int x, int y)
                {
                  const uint8_t c = cm.cost(x, y);
                  ok = grid.traversable(x, y) && (c == costs::kNoInformation || c <= path_max);
                  return ok;
                });
      if (ok)
        best = j;
      else if (j > best + 40)
        break;  // long blocked stretch: stop looking further
    }
    kept.push_back(cells[best]);
    i = best;
  }
  return kept;
}

// The polyline through the kept cells resampled at about one cell spacing, each pose facing
// along its segment; start and goal are the exact positions, the goal with its heading.
std::vector<Pose2D> resamplePath(const Costmap& cm, const std::vector<int>& kept, const Pose2D& start,
                                 const Point2D& goal_pt, double goal_theta)
{
  const int w = cm.width();
  std::vector<Point2D> pts;
  pts.push_back({start.x, start.y});
  for (size_t k = 1; k + 1 < kept.size(); ++k)
    pts.push_back(cm.mapToWorld(kept[k] % w, kept[k] / w));
  pts.push_back(goal_pt);
  const double step = cm.resolution();
  std::vector<Pose2D> path;
  for (size_t k = 0; k + 1 < pts.size(); ++k)
  {
    const double dx = pts[k + 1].x - pts[k].x, dy = pts[k + 1].y - pts[k].y;
    const double len = std::hypot(dx, dy);
    const int m = std::max(1, static_cast<int>(std::ceil(len / step)));
    const double yaw = std::atan2(dy, dx);
    for (int s = 0; s < m; ++s)
      path.push_back({pts[k].x + dx * s / m, pts[k].y + dy * s / m, yaw});
  }
  path.push_back({goal_pt.x, goal_pt.y, goal_theta});
  if (path.size() >= 2)
    path.front().theta = path[1].theta;
  return path;
}

PlanResult failed(PlanStatus status, int expanded = 0)
{
  PlanResult r;
  r.status = status;
  r.message = toString(status);
  r.expanded = expanded;
  return r;
}
}  // namespace

PlanResult GlobalPlanner::makePlan(const Costmap& cm, const Pose2D& start, const Pose2D& goal) const
{
  int sx, sy, gx, gy;
  if (!cm.worldToMap(start.x, start.y, sx, sy))
    return failed(PlanStatus::StartOffMap);
  if (!cm.worldToMap(goal.x, goal.y, gx, gy))
    return failed(PlanStatus::GoalOffMap);
  const SearchGrid grid(cm, params_, sx, sy);
  const bool goal_moved = !grid.passable(gx, gy);
  if (goal_moved && !nearestPassableGoal(grid, gx, gy))
    return failed(PlanStatus::GoalInObstacle);

  int expanded = 0;
  const std::vector<int> cells = searchGrid(grid, gx, gy, expanded);
  if (cells.empty())
    return failed(PlanStatus::NoPath, expanded);
  const std::vector<int> kept = params_.smooth_path && cells.size() > 2 ? shortcutPath(grid, cells) : cells;
  const Point2D goal_pt = goal_moved ? cm.mapToWorld(gx, gy) : Point2D{goal.x, goal.y};

  PlanResult r;
  r.expanded = expanded;
  r.path = resamplePath(cm, kept, start, goal_pt, goal.theta);
  r.length = pathLength(r.path);
  r.status = PlanStatus::Ok;
  r.message = toString(r.status);
  return r;
}

}  // namespace mybot_navigation
