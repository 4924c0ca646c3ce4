// The 2D ray caster and the laser's Gazebo range semantics.
#include "mybot_gazebo_lite/raycast2d.h"
#include "mybot_gazebo_lite/kinematics.h"
#include "mybot_gazebo_lite/model.h"
#include "mybot_gazebo_lite/parsing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

using namespace mybot_gazebo_lite;

namespace
{
WorldModel boxModel(double x, double y, double sx, double sy, double yaw = 0)
{
  WorldModel m;
  m.name = "b";
  m.is_static = true;
  m.pose = makeTransform(btVector3(x, y, 0.5), btVector3(0, 0, yaw));
  WorldLink l;
  Shape s;
  s.type = Shape::BOX;
  s.size = btVector3(sx, sy, 1.0);
  l.shapes.push_back(s);
  m.links.push_back(l);
  return m;
}
}  // namespace

TEST(RayCaster, HitsBoxFaceAndCircle)
{
  WorldSpec w;
  w.models.push_back(boxModel(5.0, 0.0, 0.2, 4.0));
  WorldModel c;
  c.is_static = true;
  c.pose = makeTransform(btVector3(0, 3, 0.5), btVector3(0, 0, 0));
  WorldLink l;
  Shape cyl;
  cyl.type = Shape::CYLINDER;
  cyl.radius = 0.5;
  cyl.length = 1.0;
  l.shapes.push_back(cyl);
  c.links.push_back(l);
  w.models.push_back(c);
  RayCaster2D rc(sliceWorld(w, 0.3));
  EXPECT_NEAR(rc.cast(0, 0, 1, 0, 30), 4.9, 1e-9);
  EXPECT_NEAR(rc.cast(0, 0, 0, 1, 30), 2.5, 1e-9);
  EXPECT_TRUE(std::isinf(rc.cast(0, 0, -1, 0, 30)));
  EXPECT_TRUE(std::isinf(rc.cast(0, 0, 1, 0, 4.0)));  // beyond max range
  // Above the box: nothing.
  RayCaster2D high(sliceWorld(w, 1.5));
  EXPECT_TRUE(std::isinf(high.cast(0, 0, 1, 0, 30)));
}

TEST(RayCaster, MatchesBruteForceOnRotatedBoxes)
{
  WorldSpec w;
  for (int i = 0; i < 20; ++i)
    w.models.push_back(boxModel(-8 + i * 0.9, std::sin(i) * 6, 0.5, 0.3, i * 0.4));
  Slice2D s = sliceWorld(w, 0.5);
  RayCaster2D rc(s, 0.37);
  auto segs = s.allSegments();
  for (int k = 0; k < 360; ++k)
  {
    double a = k * M_PI / 180, dx = std::cos(a), dy = std::sin(a);
    double best = std::numeric_limits<double>::infinity();
    for (const auto& g : segs)
    {
      double ex = g.x1 - g.x0, ey = g.y1 - g.y0, den = dx * ey - dy * ex;
      if (std::abs(den) < 1e-15)
        continue;
      double t = (g.x0 * ey - g.y0 * ex) / den, u = (g.x0 * dy - g.y0 * dx) / den;
      if (t >= 0 && u >= 0 && u <= 1)
        best = std::min(best, t);
    }
    if (best > 20)
      best = std::numeric_limits<double>::infinity();
    double got = rc.cast(0, 0, dx, dy, 20);
    if (std::isinf(best))
      EXPECT_TRUE(std::isinf(got)) << k;
    else
      EXPECT_NEAR(got, best, 1e-9) << k;
  }
}

TEST(Rasterize, MarksExactlyTheCellsASolidCovers)
{
  // A 1 x 0.5 m box from (1.0, 2.0) to (2.0, 2.5) and a 0.25 m circle at (4.0, 1.0), on a 5 cm
  // grid from the origin: every face lies on a cell boundary. Cells 20..39 x 40..49 for the box
  // (not 40 or 50: those lie beyond its +x and +y faces), and for the circle the cells it covers
  // with some area.
  Slice2D slice;
  slice.polygons.push_back({{1.0, 2.0}, {2.0, 2.0}, {2.0, 2.5}, {1.0, 2.5}});
  slice.polygons.push_back({{1.0, 2.0}, {1.0, 2.5}, {2.0, 2.5}, {2.0, 2.0}});  // the same, clockwise
  slice.circles.push_back({4.0, 1.0, 0.25});
  const double res = 0.05;
  const int w = 120, h = 80;
  std::vector<uint8_t> grid;
  rasterizeSlice(slice, 0.0, 0.0, res, w, h, grid);
  for (int cy = 0; cy < h; ++cy)
    for (int cx = 0; cx < w; ++cx)
    {
      const bool in_box = cx >= 20 && cx <= 39 && cy >= 40 && cy <= 49;
      // The circle covers part of the cell when the cell's nearest point is strictly inside it.
      const double nx = std::clamp(4.0, cx * res, (cx + 1) * res), ny = std::clamp(1.0, cy * res, (cy + 1) * res);
      const bool in_circle = std::hypot(nx - 4.0, ny - 1.0) < 0.25 - 1e-9;
      EXPECT_EQ(grid[static_cast<size_t>(cy) * w + cx] != 0, in_box || in_circle) << "cell " << cx << ", " << cy;
    }
  // A wall thinner than a cell still marks the cells it passes through.
  Slice2D thin;
  thin.polygons.push_back({{1.01, 0.0}, {1.02, 0.0}, {1.02, 1.0}, {1.01, 1.0}});
  rasterizeSlice(thin, 0.0, 0.0, res, w, h, grid);
  for (int cy = 0; cy < 20; ++cy)
  {
    EXPECT_EQ(grid[static_cast<size_t>(cy) * w + 20], 1) << "row " << cy;
    EXPECT_EQ(grid[static_cast<size_t>(cy) * w + 19], 0) << "row " << cy;
    EXPECT_EQ(grid[static_cast<size_t>(cy) * w + 21], 0) << "row " << cy;
  }
  EXPECT_EQ(grid[static_cast<size_t>(20) * w + 20], 0);  // the wall ends at y = 1.0
}

TEST(Laser, GazeboOutOfRangeSemantics)
{
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(laserRange(inf, 0.1, 30, 0.0), inf);
  EXPECT_EQ(laserRange(30.0, 0.1, 30, 0.0), inf);
  EXPECT_EQ(laserRange(0.05, 0.1, 30, 0.0), -inf);
  EXPECT_DOUBLE_EQ(laserRange(5.0, 0.1, 30, 0.01), 5.01);
  EXPECT_DOUBLE_EQ(laserRange(29.999, 0.1, 30, 0.5), 30.0);  // clamped after noise
}
