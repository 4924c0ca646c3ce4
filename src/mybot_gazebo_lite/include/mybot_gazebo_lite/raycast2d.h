// Planar ray casting against the static world sliced at a height: a 720-beam
// laser costs a few grid walks instead of 720 Bullet ray tests.
#pragma once

#include "mybot_gazebo_lite/model.h"

#include <vector>

namespace mybot_gazebo_lite
{

struct Segment2
{
  double x0, y0, x1, y1;
};
struct Circle2
{
  double cx, cy, r;
};

// Cross-section of solids at a height: convex polygons (boxes, tilted
// cylinders), circles (upright cylinders, spheres) and loose segments (meshes).
struct Slice2D
{
  std::vector<std::vector<std::pair<double, double>>> polygons;
  std::vector<Circle2> circles;
  std::vector<Segment2> segments;  // mesh cuts
  bool empty() const { return polygons.empty() && circles.empty() && segments.empty(); }
  std::vector<Segment2> allSegments() const;  // polygon edges + segments
};

// Slices the static models of a world at height z (world frame).
Slice2D sliceWorld(const WorldSpec& world, double z, bool include_dynamic = false);
void sliceShape(const Shape& s, const btTransform& world_tf, double z, Slice2D& out);

class RayCaster2D
{
public:
  explicit RayCaster2D(const Slice2D& slice, double cell = 0.25);
  // Distance to the first hit along the unit direction (dx, dy), or +inf beyond max_range.
  double cast(double x, double y, double dx, double dy, double max_range) const;
  size_t numSegments() const { return segs_.size(); }

  // One crossing of the ray with a segment (index into the slice's allSegments()
  // order) or a circle boundary (index into its circles).
  struct Crossing
  {
    double t;
    int index;
    bool circle;
  };
  // Every crossing within max_range, each once, in no particular order (the cameras
  // need entry and exit of every solid, not just the first hit).
  void castAll(double x, double y, double dx, double dy, double max_range, std::vector<Crossing>& out) const;

private:
  struct Cell
  {
    std::vector<int> segs, circles;
  };
  template <class F>
  void walk(double x, double y, double dx, double dy, double max_range, F&& visit) const;
  std::vector<Segment2> segs_;
  std::vector<Circle2> circles_;
  double x0_ = 0, y0_ = 0, cell_ = 0.25;
  int nx_ = 0, ny_ = 0;
  std::vector<Cell> cells_;
};

// Renders a slice into an occupancy raster (row 0 = min y): 1 = occupied.
// Polygons and circles are filled, segments drawn.
void rasterizeSlice(const Slice2D& slice, double x0, double y0, double res, int w, int h, std::vector<uint8_t>& grid);

}  // namespace mybot_gazebo_lite
