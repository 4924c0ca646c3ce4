// A layered 2D costmap with costmap_2d's cost values and parameter names: static layer (from a
// map), obstacle layer (marking and ray-traced clearing from laser scans) and inflation layer.
// Either sized to the static map (global costmap) or a rolling window around the robot (local
// costmap). No ROS types.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mybot_nav_common/grid_map.h"

namespace mybot_navigation
{

namespace costs
{
constexpr uint8_t kFree = 0;             // costmap_2d::FREE_SPACE
constexpr uint8_t kInscribed = 253;      // costmap_2d::INSCRIBED_INFLATED_OBSTACLE
constexpr uint8_t kLethal = 254;         // costmap_2d::LETHAL_OBSTACLE
constexpr uint8_t kNoInformation = 255;  // costmap_2d::NO_INFORMATION
}  // namespace costs

struct CostmapParams
{
  double resolution = 0.05;  // m/cell (rolling window; a static map brings its own)
  bool rolling_window = false;
  double width = 10.0;  // m, rolling window size
  double height = 10.0;
  // Footprint polygon in the base frame (>= 3 points) or, when empty, a circle of robot_radius.
  std::vector<Point2D> footprint;
  double robot_radius = 0.46;
  double footprint_padding = 0.01;
  // static layer
  bool use_static_map = true;
  bool track_unknown_space = false;
  int lethal_cost_threshold = 100;
  // obstacle layer
  bool use_obstacles = true;
  double obstacle_range = 2.5;  // m, marking range
  double raytrace_range = 3.0;  // m, clearing range
  // costmap_2d's ObstacleLayer footprint_clearing_enabled: marks under the robot are cleared.
  bool footprint_clearing_enabled = true;
  // inflation layer
  double inflation_radius = 0.55;
  double cost_scaling_factor = 10.0;
};

// Empty when valid, else a message naming the parameter.
std::string validate(const CostmapParams& p);

// The padded footprint polygon (a 16-gon for a circular robot), and its radii.
std::vector<Point2D> paddedFootprint(const CostmapParams& p);
double inscribedRadius(const std::vector<Point2D>& polygon);
double circumscribedRadius(const std::vector<Point2D>& polygon);

class Costmap
{
public:
  explicit Costmap(const CostmapParams& params);

  // Static layer source. A global costmap takes the map's size and origin.
  void setStaticMap(const GridMap& map);
  bool hasStaticMap() const { return has_static_; }
  // Rolling window: recentres the window on the robot, keeping overlapping obstacles.
  void updateOrigin(double robot_x, double robot_y);

  // Obstacle layer update from one scan: `sensor` and end points in the costmap's frame.
  // Beams listed in `hits` mark their end point (within obstacle_range) and clear the cells
  // before it; `free_ends` are end points of beams that saw nothing (max range): clear only.
  void updateWithScan(const Point2D& sensor, const std::vector<Point2D>& hits, const std::vector<Point2D>& free_ends);
  // Recomputes the master grid (static max obstacles, then inflation) where something changed.
  void updateCosts();

  // Clears obstacle layer cells farther than `distance` from (x, y) (move_base's reset
  // recoveries: conservative and aggressive); a negative distance clears everything.
  void clearObstaclesOutside(double x, double y, double distance);
  // costmap_2d's ObstacleLayer footprint_clearing_enabled: the robot is where it is, so obstacle
  // layer marks under its (padded) footprint at `pose` are stale and are cleared. In a demo run a
  // pillar corner marked with 4 cm of localization error ended up under the padding, outside the
  // 180-degree laser's view, and no move was valid for 850 s. Call with the robot pose before
  // updateCosts(); the static layer is untouched.
  void clearFootprint(const Pose2D& pose);
  // Clears the obstacle layer completely (clear_costmaps service) and re-applies the static map.
  void reset();

  // Geometry
  const MapInfo& info() const { return info_; }
  int width() const { return info_.width; }
  int height() const { return info_.height; }
  double resolution() const { return info_.resolution; }
  bool worldToMap(double wx, double wy, int& cx, int& cy) const;
  Point2D mapToWorld(int cx, int cy) const;
  bool inside(int cx, int cy) const { return cx >= 0 && cy >= 0 && cx < info_.width && cy < info_.height; }

  uint8_t cost(int cx, int cy) const { return master_[idx(cx, cy)]; }
  // Cost at a world point; kNoInformation outside the grid.
  uint8_t costAt(double wx, double wy) const;
  const std::vector<uint8_t>& data() const { return master_; }
  bool isObstacle(int cx, int cy) const { return obstacles_[idx(cx, cy)] != 0; }

  // base_local_planner's footprint check: -1 if the footprint at `pose` touches a lethal cell
  // (or, for a circular robot, the centre is within the inscribed radius of one), -2 if it
  // touches unknown space when track_unknown_space, -3 off the grid; else the highest cost.
  double footprintCost(const Pose2D& pose) const;
  // The same check for any polygon (robot frame), by its outline only.
  double polygonCost(const Pose2D& pose, const std::vector<Point2D>& polygon) const;
  // For a footprint that already touches an obstacle at `pose`: the footprint shrunk towards its
  // centre by the least of max_shrink / 3, 2/3, max_shrink (m, per axis) that clears `pose`;
  // empty if none does. Escapes move while staying clear with it, so they graze no deeper.
  std::vector<Point2D> footprintClearing(const Pose2D& pose, double max_shrink) const;

  const std::vector<Point2D>& footprint() const { return footprint_; }
  double inscribedRadius() const { return inscribed_; }
  double circumscribedRadius() const { return circumscribed_; }
  const CostmapParams& params() const { return params_; }

  // Cost given a distance (m) to the nearest lethal cell (costmap_2d's InflationLayer formula).
  uint8_t inflationCost(double distance) const;

  // nav_msgs/OccupancyGrid values for rviz (costmap_2d's translation table).
  std::vector<int8_t> toOccupancyValues() const;

private:
  size_t idx(int cx, int cy) const { return static_cast<size_t>(cy) * info_.width + cx; }
  void resize(const MapInfo& info);
  uint8_t staticCostFromMap(int8_t value) const;
  void refreshStaticLayer();
  void markDirty(int x0, int y0, int x1, int y1);

  CostmapParams params_;
  MapInfo info_;
  GridMap static_map_;
  bool has_static_ = false;
  std::vector<uint8_t> static_;     // static layer costs
  std::vector<uint8_t> obstacles_;  // obstacle layer: 1 = marked
  std::vector<uint8_t> master_;
  std::vector<Point2D> footprint_;
  double inscribed_ = 0.0, circumscribed_ = 0.0;
  int origin_ix_ = 0, origin_iy_ = 0;  // rolling window origin on the world cell lattice
  bool dirty_ = true;
  int dirty_x0_ = 0, dirty_y0_ = 0, dirty_x1_ = -1, dirty_y1_ = -1;
};

}  // namespace mybot_navigation
