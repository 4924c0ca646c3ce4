#include "mybot_gazebo_lite/camera_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>

namespace mybot_gazebo_lite
{

namespace
{
constexpr double kInf = std::numeric_limits<double>::infinity();

// World z-extent of a shape (the prism's height range).
bool zExtent(const Shape& s, const btTransform& tf, double& zmin, double& zmax)
{
  zmin = kInf;
  zmax = -kInf;
  auto add = [&](double z)
  {
    zmin = std::min(zmin, z);
    zmax = std::max(zmax, z);
  };
  const double cz = tf.getOrigin().z();
  switch (s.type)
  {
    case Shape::PLANE:
      return false;
    case Shape::SPHERE:
      add(cz - s.radius);
      add(cz + s.radius);
      return true;
    case Shape::CYLINDER:
    {
      double az = std::abs(tf.getBasis().getColumn(2).z());
      double h = az * s.length / 2 + s.radius * std::sqrt(std::max(0.0, 1 - az * az));
      add(cz - h);
      add(cz + h);
      return true;
    }
    case Shape::BOX:
    {
      btVector3 h = s.size * 0.5;
      for (int i = 0; i < 8; ++i)
        add((tf * btVector3((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z())).z());
      return true;
    }
    case Shape::MESH:
      for (const auto& t : *s.triangles)
      {
        add((tf * t.a).z());
        add((tf * t.b).z());
        add((tf * t.c).z());
      }
      return zmin <= zmax;
  }
  return false;
}

// A column's prisms in the order its ray enters them.
bool nearestFirst(const PrismScene::ColumnHit& a, const PrismScene::ColumnHit& b)
{
  return a.t_in < b.t_in;
}

inline uint8_t toByte(double v)
{
  return static_cast<uint8_t>(std::clamp(v, 0.0, 1.0) * 255.0 + 0.5);
}
}  // namespace

CameraIntrinsics gazeboIntrinsics(int width, int height, double hfov, double focal, double cx, double cy)
{
  CameraIntrinsics k;
  k.width = width;
  k.height = height;
  k.fx = k.fy = focal != 0 ? focal : width / (2.0 * std::tan(hfov / 2.0));
  k.cx = cx != 0 ? cx : (width + 1.0) / 2.0;
  k.cy = cy != 0 ? cy : (height + 1.0) / 2.0;
  return k;
}

PrismScene::PrismScene(const WorldSpec& world, double cell) : ground_(world.ground_plane)
{
  for (const auto& m : world.models)
  {
    if (!m.is_static)
      continue;  // dynamic bodies move: each frame places them anew (the other constructor)
    for (const auto& l : m.links)
      for (const auto& s : l.shapes)
        addShape(s, m.pose * l.pose * s.pose, l.color);
  }
  index(cell);
}

PrismScene::PrismScene(const std::vector<PlacedShape>& shapes, double cell)
{
  for (const auto& p : shapes)
    addShape(*p.shape, p.tf, p.color);
  index(cell);
}

void PrismScene::addShape(const Shape& s, const btTransform& tf, const float color[3])
{
  Prism p;
  if (!zExtent(s, tf, p.zmin, p.zmax) || p.zmax - p.zmin < 1e-9)
    return;
  Slice2D cut;
  sliceShape(s, tf, 0.5 * (p.zmin + p.zmax), cut);
  if (cut.empty())
    return;
  std::copy(color, color + 3, p.color);
  const int id = static_cast<int>(prisms_.size());
  prisms_.push_back(p);
  for (const auto& seg : cut.allSegments())
  {
    segments_.push_back(seg);
    seg_prism_.push_back(id);
  }
  for (const auto& c : cut.circles)
  {
    circles_.push_back(c);
    circle_prism_.push_back(id);
  }
}

void PrismScene::index(double cell)
{
  Slice2D all;
  all.segments = segments_;  // no polygons: allSegments() keeps this order
  all.circles = circles_;
  caster_ = std::make_unique<RayCaster2D>(all, cell);
}

void PrismScene::column(double x, double y, double dx, double dy, double max_range, std::vector<ColumnHit>& out) const
{
  out.clear();
  appendColumn(x, y, dx, dy, max_range, out);
  std::sort(out.begin(), out.end(), nearestFirst);
}

void PrismScene::appendColumn(double x, double y, double dx, double dy, double max_range,
                              std::vector<ColumnHit>& out) const
{
  const size_t first = out.size();  // this scene's hits start here
  caster_->castAll(x, y, dx, dy, max_range, crossings_);
  for (const auto& c : crossings_)
  {
    const Prism* prism = &prisms_[c.circle ? circle_prism_[c.index] : seg_prism_[c.index]];
    double nx, ny;
    if (c.circle)
    {
      const Circle2& ci = circles_[c.index];
      nx = (x + dx * c.t - ci.cx) / ci.r;
      ny = (y + dy * c.t - ci.cy) / ci.r;
    }
    else
    {
      const Segment2& s = segments_[c.index];
      double ex = s.x1 - s.x0, ey = s.y1 - s.y0, len = std::hypot(ex, ey);
      nx = len > 0 ? -ey / len : 0;
      ny = len > 0 ? ex / len : 0;
    }
    auto it = std::find_if(out.begin() + static_cast<long>(first), out.end(),
                           [&](const ColumnHit& h) { return h.prism == prism; });
    if (it == out.end())
    {
      out.push_back({prism, c.t, c.t, nx, ny});
      continue;
    }
    if (c.t < it->t_in)
    {
      it->t_in = c.t;
      it->nx = nx;
      it->ny = ny;
    }
    it->t_out = std::max(it->t_out, c.t);
  }
}

void renderCamera(const PrismScene& scene, const PrismScene* moving, const CameraIntrinsics& k, const CameraPose& pose,
                  const RenderSettings& s, uint8_t* rgb, float* depth)
{
  if (moving && moving->empty())
    moving = nullptr;
  const int w = k.width, h = k.height;
  const double fwx = std::cos(pose.yaw), fwy = std::sin(pose.yaw);
  const double rx = fwy, ry = -fwx;  // image x (right) in the world
  const double zc = pose.z;
  // Per-row vertical slope of the pixel ray: z = zc + m * depth.
  // Floor depth, haze and sky colour depend on the row only; so do the floor's two checker
  // greys, hazed. Colours are turned into bytes once a row (and once a face a column below).
  std::vector<double> slope(h), floor_d(h);
  std::vector<uint8_t> sky(3 * h), checker(2 * h);
  for (int v = 0; v < h; ++v)
  {
    const double m = slope[v] = -(v - k.cy) / k.fy;
    floor_d[v] = (scene.ground() && m < 0 && zc > 0) ? zc / -m : kInf;
    const double fog = 1 - std::exp(-floor_d[v] / 30.0);  // checker fades into haze: no aliasing at the horizon
    checker[2 * v] = toByte(0.42 * (1 - fog) + 0.7 * fog);
    checker[2 * v + 1] = toByte(0.55 * (1 - fog) + 0.7 * fog);
    const double e = std::clamp(m * 2, 0.0, 1.0);  // sky: pale at the horizon, blue above
    sky[3 * v] = toByte(0.75 - 0.3 * e);
    sky[3 * v + 1] = toByte(0.85 - 0.2 * e);
    sky[3 * v + 2] = toByte(0.95 - 0.05 * e);
  }
  // Columns are drawn in blocks, row by row across a block: the images are row-major, and a
  // column at a time wrote each pixel a row apart (2.4 kB for 800 colour pixels), a cache miss
  // a pixel.
  constexpr int kBlock = 16;
  struct Column
  {
    double dx = 0, dy = 0, kn = 0;  // the 2D ray, and its length per unit of depth
    std::vector<PrismScene::ColumnHit> hits;
    std::vector<double> din, dout;  // each hit's entry and exit as depth along the optical axis
    // The prisms' faces in bytes: side (lit by the angle between ray and normal), top, underside.
    std::vector<uint8_t> faces;
  };
  constexpr double kTopShade = 0.95, kUndersideShade = 0.25;
  Column block[kBlock];
  for (int u0 = 0; u0 < w; u0 += kBlock)
  {
    const int u1 = std::min(w, u0 + kBlock);
    for (int u = u0; u < u1; ++u)
    {
      Column& col = block[u - u0];
      const double a = (u - k.cx) / k.fx;
      col.kn = std::sqrt(1 + a * a);
      col.dx = (fwx + a * rx) / col.kn;
      col.dy = (fwy + a * ry) / col.kn;
      scene.column(pose.x, pose.y, col.dx, col.dy, s.far * col.kn, col.hits);
      if (moving)
      {
        moving->appendColumn(pose.x, pose.y, col.dx, col.dy, s.far * col.kn, col.hits);
        std::sort(col.hits.begin(), col.hits.end(), nearestFirst);
      }
      col.din.resize(col.hits.size());
      col.dout.resize(col.hits.size());
      for (size_t i = 0; i < col.hits.size(); ++i)
      {
        col.din[i] = col.hits[i].t_in / col.kn;
        col.dout[i] = col.hits[i].t_out / col.kn;
      }
      if (!rgb)
        continue;
      col.faces.resize(9 * col.hits.size());
      for (size_t i = 0; i < col.hits.size(); ++i)
      {
        const double side = 0.3 + 0.7 * std::abs(col.dx * col.hits[i].nx + col.dy * col.hits[i].ny);
        for (int ch = 0; ch < 3; ++ch)
        {
          col.faces[9 * i + ch] = toByte(col.hits[i].prism->color[ch] * side);
          col.faces[9 * i + 3 + ch] = toByte(col.hits[i].prism->color[ch] * kTopShade);
          col.faces[9 * i + 6 + ch] = toByte(col.hits[i].prism->color[ch] * kUndersideShade);
        }
      }
    }
    for (int v = 0; v < h; ++v)
      for (int u = u0; u < u1; ++u)
      {
        const Column& col = block[u - u0];
        const std::vector<PrismScene::ColumnHit>& hits = col.hits;
        const double kn = col.kn, dx = col.dx, dy = col.dy;
        const double m = slope[v];
        const double d_floor = floor_d[v];
        double d = kInf;
        bool hit = false;
        const uint8_t* face = nullptr;  // the bytes of the face hit, with rgb
        for (size_t i = 0; i < hits.size(); ++i)
        {
          const double din = col.din[i], dout = col.dout[i];
          if (din >= d_floor || din > s.far)
            break;
          const PrismScene::Prism& p = *hits[i].prism;
          const double zin = zc + m * din;
          double dh = kInf;
          int which = 0;
          if (zin >= p.zmin && zin <= p.zmax)
          {
            dh = din;  // side face
          }
          else if (zin > p.zmax && m < 0)
          {
            dh = (p.zmax - zc) / m;
            which = 1;  // top face
          }
          else if (zin < p.zmin && m > 0)
          {
            dh = (p.zmin - zc) / m;
            which = 2;  // underside
          }
          if (dh <= dout + 1e-9 && dh >= s.near && dh <= s.far)
          {
            d = dh;
            hit = true;
            if (rgb)
              face = &col.faces[9 * i + 3 * static_cast<size_t>(which)];
            break;
          }
        }
        const bool floor = !hit && d_floor >= s.near && d_floor <= s.far;
        if (floor)
          d = d_floor;
        const size_t idx = static_cast<size_t>(v) * w + u;
        if (depth)
          depth[idx] = static_cast<float>(d);
        if (!rgb)
          continue;
        uint8_t* px = &rgb[idx * 3];
        if (hit)
        {
          px[0] = face[0];
          px[1] = face[1];
          px[2] = face[2];
        }
        else if (floor)
        {
          const double fx = pose.x + dx * d * kn, fy = pose.y + dy * d * kn;
          const uint8_t g =
              checker[2 * v + ((static_cast<long>(std::floor(fx)) + static_cast<long>(std::floor(fy))) & 1)];
          px[0] = px[1] = px[2] = g;
        }
        else
        {
          px[0] = sky[3 * v];
          px[1] = sky[3 * v + 1];
          px[2] = sky[3 * v + 2];
        }
      }
  }
}

NoiseTable::NoiseTable(uint32_t seed, size_t size) : state_(seed * 2654435761ull + 1)
{
  size_t len = 2;
  while (len < std::max(size, kBytesA + kBytesB))
    len <<= 1;  // power of two, so an odd stride visits every entry
  table_.resize(len);
  std::mt19937 gen(seed);
  std::normal_distribution<float> n(0, 1);
  for (auto& x : table_)
    x = n(gen);
}

size_t NoiseTable::start(size_t* stride)
{
  auto next = [&]() {  // xorshift64
    state_ ^= state_ << 13;
    state_ ^= state_ >> 7;
    state_ ^= state_ << 17;
    return state_;
  };
  *stride = (next() % (table_.size() / 2)) * 2 + 1;  // odd: visits every entry of the power-of-two table
  return next() % table_.size();
}

void NoiseTable::addToBytes(uint8_t* data, size_t n, double mean, double stddev)
{
  if (mean != bytes_mean_ || stddev != bytes_stddev_)
  {
    // 1/256 of a grey level a unit; the mean goes in the first table.
    const double scale = 255.0 * 256.0 * stddev / std::sqrt(2.0);
    bytes_a_.resize(kBytesA);
    bytes_b_.resize(kBytesB);
    for (size_t k = 0; k < kBytesA; ++k)
      bytes_a_[k] = static_cast<int32_t>(std::lround(255.0 * 256.0 * mean + scale * table_[k]));
    for (size_t k = 0; k < kBytesB; ++k)
      bytes_b_[k] = static_cast<int32_t>(std::lround(scale * table_[kBytesA + k]));
    bytes_mean_ = mean;
    bytes_stddev_ = stddev;
  }
  // Both walked in order from random starts: a frame reads a stretch of one long noise tape.
  size_t stride_unused;
  size_t a = start(&stride_unused) % kBytesA, b = start(&stride_unused) % kBytesB;
  const int32_t* ta = bytes_a_.data();
  const int32_t* tb = bytes_b_.data();
  for (size_t j = 0; j < n;)
  {
    // Up to where either table wraps, a plain loop the compiler vectorises.
    const size_t run = std::min({n - j, kBytesA - a, kBytesB - b});
    for (size_t r = 0; r < run; ++r)
    {
      // round(level + noise), in 1/256 of a level; >> floors (arithmetic on a negative sum).
      const int32_t v = (static_cast<int32_t>(data[j + r]) << 8) + ta[a + r] + tb[b + r] + 128;
      data[j + r] = static_cast<uint8_t>(std::clamp(v >> 8, 0, 255));
    }
    j += run;
    a = (a + run) % kBytesA;
    b = (b + run) % kBytesB;
  }
}

void NoiseTable::addToFloats(float* data, size_t n, double mean, double stddev)
{
  size_t stride, i = start(&stride);
  const size_t mask = table_.size() - 1;
  for (size_t j = 0; j < n; ++j, i = (i + stride) & mask)
    if (std::isfinite(data[j]))
      data[j] = static_cast<float>(data[j] + mean + stddev * table_[i]);
}

std::string gazeboImageEncoding(const std::string& format)
{
  static const std::map<std::string, std::string> kEncodings = {{"R8G8B8", "rgb8"},
                                                                {"RGB_INT8", "rgb8"},
                                                                {"B8G8R8", "bgr8"},
                                                                {"BGR_INT8", "bgr8"},
                                                                {"L8", "mono8"},
                                                                {"L_INT8", "mono8"},
                                                                {"L16", "mono16"},
                                                                {"L_INT16", "mono16"},
                                                                {"R16G16B16", "rgb16"},
                                                                {"RGB_INT16", "rgb16"},
                                                                {"BAYER_RGGB8", "bayer_rggb8"},
                                                                {"BAYER_BGGR8", "bayer_bggr8"},
                                                                {"BAYER_GBRG8", "bayer_gbrg8"},
                                                                {"BAYER_GRBG8", "bayer_grbg8"}};
  const auto e = kEncodings.find(format);
  return e == kEncodings.end() ? "" : e->second;
}

std::vector<uint8_t> encodeImage(const std::vector<uint8_t>& rgb, int width, int height, const std::string& encoding,
                                 uint32_t& step)
{
  const size_t n = static_cast<size_t>(width) * height;
  const auto luma = [&](size_t i)
  { return static_cast<uint8_t>((299 * rgb[3 * i] + 587 * rgb[3 * i + 1] + 114 * rgb[3 * i + 2]) / 1000); };
  std::vector<uint8_t> out;
  if (encoding == "mono8" || encoding == "mono16")
  {
    const size_t bytes = encoding == "mono8" ? 1 : 2;
    step = static_cast<uint32_t>(width * bytes);
    out.resize(n * bytes);
    for (size_t i = 0; i < n; ++i)
      for (size_t b = 0; b < bytes; ++b)
        out[i * bytes + b] = luma(i);  // v * 257: the 8-bit value in both bytes
  }
  else if (encoding == "rgb16")
  {
    step = static_cast<uint32_t>(width * 6);
    out.resize(n * 6);
    for (size_t i = 0; i < 3 * n; ++i)
      out[2 * i] = out[2 * i + 1] = rgb[i];
  }
  else if (encoding.compare(0, 6, "bayer_") == 0)
  {
    const std::string pattern = encoding.substr(6);
    step = static_cast<uint32_t>(width);
    out.resize(n);
    for (int v = 0; v < height; ++v)
      for (int u = 0; u < width; ++u)
      {
        const size_t i = static_cast<size_t>(v) * width + u;
        const char c = pattern[2 * (v % 2) + (u % 2)];
        out[i] = rgb[3 * i + (c == 'r' ? 0 : c == 'g' ? 1 : 2)];
      }
  }
  else
  {
    step = static_cast<uint32_t>(width * 3);
    out = rgb;
    if (encoding == "bgr8")
      for (size_t i = 0; i < n; ++i)
        std::swap(out[3 * i], out[3 * i + 2]);
  }
  return out;
}

}  // namespace mybot_gazebo_lite
