#include "mybot_gazebo_lite/raycast2d.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace mybot_gazebo_lite
{

namespace
{
constexpr double kInf = std::numeric_limits<double>::infinity();
using P2 = std::pair<double, double>;

std::vector<P2> convexHull(std::vector<P2> pts)
{
  std::sort(pts.begin(), pts.end());
  pts.erase(std::unique(pts.begin(), pts.end(),
                        [](const P2& a, const P2& b)
                        { return std::abs(a.first - b.first) < 1e-9 && std::abs(a.second - b.second) < 1e-9; }),
            pts.end());
  if (pts.size() < 3)
    return pts;
  auto cross = [](const P2& o, const P2& a, const P2& b)
  { return (a.first - o.first) * (b.second - o.second) - (a.second - o.second) * (b.first - o.first); };
  std::vector<P2> h(2 * pts.size());
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i)
  {
    while (k >= 2 && cross(h[k - 2], h[k - 1], pts[i]) <= 0)
      --k;
    h[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, t = k + 1; i > 0; --i)
  {
    while (k >= t && cross(h[k - 2], h[k - 1], pts[i - 1]) <= 0)
      --k;
    h[k++] = pts[i - 1];
  }
  h.resize(k - 1);
  return h;
}

// Cross-section of a convex solid given by its edges.
void sliceEdges(const std::vector<std::pair<btVector3, btVector3>>& edges, double z, Slice2D& out)
{
  std::vector<P2> pts;
  for (const auto& [a, b] : edges)
  {
    double da = a.z() - z, db = b.z() - z;
    if ((da > 0 && db > 0) || (da < 0 && db < 0))
      continue;
    if (std::abs(da - db) < 1e-12)
    {
      pts.push_back({a.x(), a.y()});
      pts.push_back({b.x(), b.y()});
      continue;
    }
    double t = da / (da - db);
    btVector3 p = a + (b - a) * t;
    pts.push_back({p.x(), p.y()});
  }
  auto hull = convexHull(pts);
  if (hull.size() >= 3)
    out.polygons.push_back(hull);
}

// Distance along the unit ray to segment s, or -1 when it misses.
double raySegment(const Segment2& s, double x, double y, double dx, double dy)
{
  double ex = s.x1 - s.x0, ey = s.y1 - s.y0;
  double den = dx * ey - dy * ex;
  if (std::abs(den) < 1e-15)
    return -1;
  double wx = s.x0 - x, wy = s.y0 - y;
  double t = (wx * ey - wy * ex) / den;
  double u = (wx * dy - wy * dx) / den;
  return (t >= 0 && u >= 0 && u <= 1) ? t : -1;
}

// Both crossings of the unit ray's line with circle c (t0 <= t1), false when it misses.
bool rayCircle(const Circle2& c, double x, double y, double dx, double dy, double& t0, double& t1)
{
  double ox = x - c.cx, oy = y - c.cy;
  double b = ox * dx + oy * dy;
  double disc = b * b - (ox * ox + oy * oy - c.r * c.r);
  if (disc < 0)
    return false;
  double sq = std::sqrt(disc);
  t0 = -b - sq;
  t1 = -b + sq;
  return true;
}
}  // namespace

std::vector<Segment2> Slice2D::allSegments() const
{
  std::vector<Segment2> s = segments;
  for (const auto& poly : polygons)
    for (size_t i = 0; i < poly.size(); ++i)
    {
      const auto& a = poly[i];
      const auto& b = poly[(i + 1) % poly.size()];
      s.push_back({a.first, a.second, b.first, b.second});
    }
  return s;
}

void sliceShape(const Shape& s, const btTransform& tf, double z, Slice2D& out)
{
  switch (s.type)
  {
    case Shape::PLANE:
      return;
    case Shape::SPHERE:
    {
      double dz = tf.getOrigin().z() - z;
      if (std::abs(dz) >= s.radius)
        return;
      out.circles.push_back({tf.getOrigin().x(), tf.getOrigin().y(), std::sqrt(s.radius * s.radius - dz * dz)});
      return;
    }
    case Shape::CYLINDER:
    {
      btVector3 axis = tf.getBasis().getColumn(2);
      if (std::abs(axis.z()) > 0.9999)
      {
        if (std::abs(tf.getOrigin().z() - z) > s.length / 2)
          return;
        out.circles.push_back({tf.getOrigin().x(), tf.getOrigin().y(), s.radius});
        return;
      }
      // Tilted cylinder: a 32-sided prism.
      const int n = 32;
      std::vector<btVector3> top, bot;
      for (int i = 0; i < n; ++i)
      {
        double a = 2 * M_PI * i / n;
        btVector3 p(s.radius * std::cos(a), s.radius * std::sin(a), 0);
        top.push_back(tf * (p + btVector3(0, 0, s.length / 2)));
        bot.push_back(tf * (p - btVector3(0, 0, s.length / 2)));
      }
      std::vector<std::pair<btVector3, btVector3>> edges;
      for (int i = 0; i < n; ++i)
      {
        edges.push_back({top[i], bot[i]});
        edges.push_back({top[i], top[(i + 1) % n]});
        edges.push_back({bot[i], bot[(i + 1) % n]});
      }
      sliceEdges(edges, z, out);
      return;
    }
    case Shape::BOX:
    {
      btVector3 h = s.size * 0.5;
      btVector3 c[8];
      for (int i = 0; i < 8; ++i)
        c[i] = tf * btVector3((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
      std::vector<std::pair<btVector3, btVector3>> edges;
      for (int i = 0; i < 8; ++i)
        for (int b = 1; b < 8; b <<= 1)
          if (!(i & b))
            edges.push_back({c[i], c[i | b]});
      sliceEdges(edges, z, out);
      return;
    }
    case Shape::MESH:
    {
      for (const auto& t : *s.triangles)
      {
        btVector3 v[3] = {tf * t.a, tf * t.b, tf * t.c};
        std::vector<btVector3> pts;
        for (int i = 0; i < 3; ++i)
        {
          const btVector3& a = v[i];
          const btVector3& b = v[(i + 1) % 3];
          double da = a.z() - z, db = b.z() - z;
          if ((da > 0 && db > 0) || (da < 0 && db < 0) || da == db)
            continue;
          pts.push_back(a + (b - a) * (da / (da - db)));
        }
        if (pts.size() >= 2 && (pts[0] - pts[1]).length2() > 1e-12)
          out.segments.push_back({pts[0].x(), pts[0].y(), pts[1].x(), pts[1].y()});
      }
      return;
    }
  }
}

Slice2D sliceWorld(const WorldSpec& world, double z, bool include_dynamic)
{
  Slice2D out;
  for (const auto& m : world.models)
  {
    if (!m.is_static && !include_dynamic)
      continue;
    for (const auto& l : m.links)
      for (const auto& s : l.shapes)
        sliceShape(s, m.pose * l.pose * s.pose, z, out);
  }
  return out;
}

RayCaster2D::RayCaster2D(const Slice2D& slice, double cell)
    : segs_(slice.allSegments()), circles_(slice.circles), cell_(cell)
{
  double xmin = kInf, ymin = kInf, xmax = -kInf, ymax = -kInf;
  for (const auto& s : segs_)
  {
    xmin = std::min({xmin, s.x0, s.x1});
    xmax = std::max({xmax, s.x0, s.x1});
    ymin = std::min({ymin, s.y0, s.y1});
    ymax = std::max({ymax, s.y0, s.y1});
  }
  for (const auto& c : circles_)
  {
    xmin = std::min(xmin, c.cx - c.r);
    xmax = std::max(xmax, c.cx + c.r);
    ymin = std::min(ymin, c.cy - c.r);
    ymax = std::max(ymax, c.cy + c.r);
  }
  if (xmin > xmax)
    return;  // nothing to hit
  x0_ = xmin - cell_;
  y0_ = ymin - cell_;
  nx_ = static_cast<int>(std::ceil((xmax - x0_) / cell_)) + 1;
  ny_ = static_cast<int>(std::ceil((ymax - y0_) / cell_)) + 1;
  cells_.resize(static_cast<size_t>(nx_) * ny_);
  for (size_t i = 0; i < segs_.size(); ++i)
  {
    const auto& s = segs_[i];
    double dx = s.x1 - s.x0, dy = s.y1 - s.y0, len = std::hypot(dx, dy);
    if (len < 1e-12)
    {
      int cx = static_cast<int>((s.x0 - x0_) / cell_), cy = static_cast<int>((s.y0 - y0_) / cell_);
      cells_[cy * nx_ + cx].segs.push_back(static_cast<int>(i));
      continue;
    }
    walk(s.x0, s.y0, dx / len, dy / len, len,
         [&](int c, double, double)
         {
           auto& v = cells_[c].segs;
           if (v.empty() || v.back() != static_cast<int>(i))
             v.push_back(static_cast<int>(i));
           return false;
         });
  }
  for (size_t i = 0; i < circles_.size(); ++i)
  {
    const auto& c = circles_[i];
    int ax = static_cast<int>((c.cx - c.r - x0_) / cell_), bx = static_cast<int>((c.cx + c.r - x0_) / cell_);
    int ay = static_cast<int>((c.cy - c.r - y0_) / cell_), by = static_cast<int>((c.cy + c.r - y0_) / cell_);
    for (int y = std::max(ay, 0); y <= std::min(by, ny_ - 1); ++y)
      for (int x = std::max(ax, 0); x <= std::min(bx, nx_ - 1); ++x)
        cells_[y * nx_ + x].circles.push_back(static_cast<int>(i));
  }
}

// Amanatides-Woo grid traversal; visit(cell, t_enter, t_exit) returns true to stop.
template <class F>
void RayCaster2D::walk(double x, double y, double dx, double dy, double max_range, F&& visit) const
{
  if (nx_ == 0)
    return;
  const double gx1 = x0_ + nx_ * cell_, gy1 = y0_ + ny_ * cell_;
  double t0 = 0, t1 = max_range;
  // Clip the ray to the grid box.
  auto clip = [&](double o, double d, double lo, double hi)
  {
    if (std::abs(d) < 1e-15)
      return o >= lo && o <= hi;
    double a = (lo - o) / d, b = (hi - o) / d;
    if (a > b)
      std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    return t0 <= t1;
  };
  if (!clip(x, dx, x0_, gx1) || !clip(y, dy, y0_, gy1))
    return;
  double px = x + dx * t0, py = y + dy * t0;
  int cx = std::clamp(static_cast<int>((px - x0_) / cell_), 0, nx_ - 1);
  int cy = std::clamp(static_cast<int>((py - y0_) / cell_), 0, ny_ - 1);
  int sx = dx > 0 ? 1 : -1, sy = dy > 0 ? 1 : -1;
  double tdx = std::abs(dx) > 1e-15 ? cell_ / std::abs(dx) : kInf;
  double tdy = std::abs(dy) > 1e-15 ? cell_ / std::abs(dy) : kInf;
  double nxb = x0_ + (cx + (sx > 0 ? 1 : 0)) * cell_;
  double nyb = y0_ + (cy + (sy > 0 ? 1 : 0)) * cell_;
  double tmx = std::abs(dx) > 1e-15 ? (nxb - x) / dx : kInf;
  double tmy = std::abs(dy) > 1e-15 ? (nyb - y) / dy : kInf;
  double t = t0;
  while (true)
  {
    double texit = std::min({tmx, tmy, t1});
    if (visit(cy * nx_ + cx, t, texit))
      return;
    if (texit >= t1)
      return;
    t = texit;
    if (tmx < tmy)
    {
      cx += sx;
      tmx += tdx;
      if (cx < 0 || cx >= nx_)
        return;
    }
    else
    {
      cy += sy;
      tmy += tdy;
      if (cy < 0 || cy >= ny_)
        return;
    }
  }
}

double RayCaster2D::cast(double x, double y, double dx, double dy, double max_range) const
{
  double best = kInf;
  walk(x, y, dx, dy, max_range,
       [&](int c, double, double texit)
       {
         const Cell& cell = cells_[c];
         for (int i : cell.segs)
         {
           double t = raySegment(segs_[i], x, y, dx, dy);
           if (t >= 0 && t < best)
             best = t;
         }
         for (int i : cell.circles)
         {
           double t0, t1;
           if (!rayCircle(circles_[i], x, y, dx, dy, t0, t1))
             continue;
           double t = t0 >= 0 ? t0 : t1;  // inside the circle: the far wall
           if (t >= 0 && t < best)
             best = t;
         }
         return best <= texit;  // nothing in later cells can be nearer
       });
  return best <= max_range ? best : kInf;
}

void RayCaster2D::castAll(double x, double y, double dx, double dy, double max_range, std::vector<Crossing>& out) const
{
  out.clear();
  walk(x, y, dx, dy, max_range,
       [&](int c, double, double)
       {
         const Cell& cell = cells_[c];
         for (int i : cell.segs)
         {
           double t = raySegment(segs_[i], x, y, dx, dy);
           if (t >= 0 && t <= max_range)
             out.push_back({t, i, false});
         }
         for (int i : cell.circles)
         {
           double t0, t1;
           if (!rayCircle(circles_[i], x, y, dx, dy, t0, t1))
             continue;
           for (double t : {t0, t1})
             if (t >= 0 && t <= max_range)
               out.push_back({t, i, true});
         }
         return false;
       });
  // A primitive spanning several cells is met once per cell.
  std::sort(out.begin(), out.end(),
            [](const Crossing& a, const Crossing& b)
            { return std::tie(a.circle, a.index, a.t) < std::tie(b.circle, b.index, b.t); });
  out.erase(std::unique(out.begin(), out.end(),
                        [](const Crossing& a, const Crossing& b)
                        { return a.circle == b.circle && a.index == b.index && std::abs(a.t - b.t) < 1e-9; }),
            out.end());
}

void rasterizeSlice(const Slice2D& slice, double x0, double y0, double res, int w, int h, std::vector<uint8_t>& grid)
{
  grid.assign(static_cast<size_t>(w) * h, 0);
  auto mark = [&](int cx, int cy)
  {
    if (cx >= 0 && cy >= 0 && cx < w && cy < h)
      grid[static_cast<size_t>(cy) * w + cx] = 1;
  };
  auto drawSeg = [&](double ax, double ay, double bx, double by)
  {
    double len = std::hypot(bx - ax, by - ay);
    int n = std::max(1, static_cast<int>(std::ceil(len / (res * 0.25))));
    for (int i = 0; i <= n; ++i)
    {
      double t = static_cast<double>(i) / n;
      mark(static_cast<int>(std::floor((ax + (bx - ax) * t - x0) / res)),
           static_cast<int>(std::floor((ay + (by - ay) * t - y0) / res)));
    }
  };
  for (const auto& s : slice.segments)
    drawSeg(s.x0, s.y0, s.x1, s.y1);
  for (const auto& poly : slice.polygons)
  {
    double ymin = kInf, ymax = -kInf;
    for (const auto& p : poly)
    {
      ymin = std::min(ymin, p.second);
      ymax = std::max(ymax, p.second);
    }
    // Scanline fill at cell centres, plus the outline so thin walls survive.
    for (int cy = std::max(0, static_cast<int>(std::floor((ymin - y0) / res)));
         cy <= std::min(h - 1, static_cast<int>(std::floor((ymax - y0) / res))); ++cy)
    {
      double yc = y0 + (cy + 0.5) * res;
      double xa = kInf, xb = -kInf;
      for (size_t i = 0; i < poly.size(); ++i)
      {
        const auto& a = poly[i];
        const auto& b = poly[(i + 1) % poly.size()];
        if ((a.second <= yc && b.second > yc) || (b.second <= yc && a.second > yc))
        {
          double x = a.first + (yc - a.second) * (b.first - a.first) / (b.second - a.second);
          xa = std::min(xa, x);
          xb = std::max(xb, x);
        }
      }
      if (xa > xb)
        continue;
      // Cells whose centre lies inside; the outline below adds those covered in part.
      for (int cx = static_cast<int>(std::ceil((xa - x0) / res - 0.5));
           cx <= static_cast<int>(std::floor((xb - x0) / res - 0.5)); ++cx)
        mark(cx, cy);
    }
    // The outline marks the cells the solid covers however thinly, so a wall thinner than a cell
    // survives. It is drawn a micrometre inside the solid: a face lying exactly on a cell
    // boundary (a 1 m box on a 5 cm grid) then marks the cell it covers, not the free cell beyond
    // (which made every +x and +y face one cell thicker than the solid).
    double twice_area = 0.0;
    for (size_t i = 0; i < poly.size(); ++i)
    {
      const auto& a = poly[i];
      const auto& b = poly[(i + 1) % poly.size()];
      twice_area += a.first * b.second - b.first * a.second;
    }
    const double inward = twice_area >= 0.0 ? 1.0 : -1.0;  // counter-clockwise: the interior is on the left
    constexpr double kInside = 1e-6;                       // m
    for (size_t i = 0; i < poly.size(); ++i)
    {
      const auto& a = poly[i];
      const auto& b = poly[(i + 1) % poly.size()];
      const double len = std::hypot(b.first - a.first, b.second - a.second);
      if (len <= 2.0 * kInside)
        continue;
      const double tx = (b.first - a.first) / len, ty = (b.second - a.second) / len;
      const double nx = -ty * inward * kInside, ny = tx * inward * kInside;
      drawSeg(a.first + tx * kInside + nx, a.second + ty * kInside + ny, b.first - tx * kInside + nx,
              b.second - ty * kInside + ny);
    }
  }
  for (const auto& c : slice.circles)
  {
    int ax = static_cast<int>(std::floor((c.cx - c.r - x0) / res)),
        bx = static_cast<int>(std::floor((c.cx + c.r - x0) / res));
    int ay = static_cast<int>(std::floor((c.cy - c.r - y0) / res)),
        by = static_cast<int>(std::floor((c.cy + c.r - y0) / res));
    for (int cy = ay; cy <= by; ++cy)
      for (int cx = ax; cx <= bx; ++cx)
      {
        // Occupied when the circle covers part of the cell (touching its boundary is not enough).
        double nxp = std::clamp(c.cx, x0 + cx * res, x0 + (cx + 1) * res);
        double nyp = std::clamp(c.cy, y0 + cy * res, y0 + (cy + 1) * res);
        if (std::hypot(nxp - c.cx, nyp - c.cy) < c.r - 1e-9)
          mark(cx, cy);
      }
  }
}

}  // namespace mybot_gazebo_lite
