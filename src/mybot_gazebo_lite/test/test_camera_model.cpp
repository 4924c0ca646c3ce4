// Column renderer: geometry of walls, pillars and tops against closed-form
// projections, gazebo_ros intrinsics, and the image noise statistics.
#include "mybot_gazebo_lite/camera_model.h"
#include "mybot_gazebo_lite/parsing.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>

using namespace mybot_gazebo_lite;

namespace
{
constexpr double kInf = std::numeric_limits<double>::infinity();

WorldModel box(const std::string& name, double x, double y, double z, double sx, double sy, double sz,
               std::array<float, 3> color = {0.7f, 0.7f, 0.7f})
{
  WorldModel m;
  m.name = name;
  m.pose = makeTransform(btVector3(x, y, z), btVector3(0, 0, 0));
  WorldLink l;
  Shape s;
  s.type = Shape::BOX;
  s.size = btVector3(sx, sy, sz);
  l.shapes.push_back(s);
  l.has_color = true;
  std::copy(color.begin(), color.end(), l.color);
  m.links.push_back(l);
  return m;
}

// A 1 m high red wall whose face is at x = 5, on a ground plane.
WorldSpec wallWorld()
{
  WorldSpec w;
  w.ground_plane = true;
  w.models.push_back(box("wall", 5.1, 0, 0.5, 0.2, 20, 1.0, {1.0f, 0.0f, 0.0f}));
  return w;
}

struct Frame
{
  CameraIntrinsics k;
  std::vector<uint8_t> rgb;
  std::vector<float> depth;
  float d(int u, int v) const { return depth[static_cast<size_t>(v) * k.width + u]; }
  const uint8_t* px(int u, int v) const { return &rgb[(static_cast<size_t>(v) * k.width + u) * 3]; }
};

Frame render(const WorldSpec& w, const CameraPose& pose, int width = 160, int height = 120, double hfov = 1.3962634)
{
  PrismScene scene(w);
  Frame f;
  f.k = gazeboIntrinsics(width, height, hfov);
  f.rgb.resize(width * height * 3);
  f.depth.resize(width * height);
  RenderSettings s;
  s.near = 0.02;
  s.far = 300;
  renderCamera(scene, f.k, pose, s, f.rgb.data(), f.depth.data());
  return f;
}
}  // namespace

TEST(CameraIntrinsics, GazeboRosFormulas)
{
  // mybot's camera: 800x800, 80 degrees.
  CameraIntrinsics k = gazeboIntrinsics(800, 800, 1.3962634);
  EXPECT_NEAR(k.fx, 800 / (2 * std::tan(1.3962634 / 2)), 1e-9);
  EXPECT_NEAR(k.fx, 476.7014, 1e-3);
  EXPECT_DOUBLE_EQ(k.fy, k.fx);
  EXPECT_DOUBLE_EQ(k.cx, 400.5);
  EXPECT_DOUBLE_EQ(k.cy, 400.5);
  // The swerve robot's 640x480, and explicit <focalLength>/<Cx>/<Cy> win.
  k = gazeboIntrinsics(640, 480, 1.3962634);
  EXPECT_DOUBLE_EQ(k.cx, 320.5);
  EXPECT_DOUBLE_EQ(k.cy, 240.5);
  k = gazeboIntrinsics(640, 480, 1.0, 525, 320, 240);
  EXPECT_DOUBLE_EQ(k.fx, 525);
  EXPECT_DOUBLE_EQ(k.cx, 320);
  EXPECT_DOUBLE_EQ(k.cy, 240);
}

TEST(CameraIntrinsics, DepthPixelsBecomeOpticalPoints)
{
  const CameraIntrinsics k = gazeboIntrinsics(640, 480, 1.047);
  const OpticalPoint centre = depthToPoint(k, static_cast<int>(k.cx), static_cast<int>(k.cy), 2.0f);
  EXPECT_NEAR(centre.x, (static_cast<int>(k.cx) - k.cx) * 2.0 / k.fx, 1e-6);
  EXPECT_FLOAT_EQ(centre.z, 2.0f);
  // One focal length right of and below the principal point: 45 degrees off the axis on both.
  const OpticalPoint corner = depthToPoint(CameraIntrinsics{640, 480, 100, 100, 300, 200}, 400, 300, 3.0f);
  EXPECT_FLOAT_EQ(corner.x, 3.0f);
  EXPECT_FLOAT_EQ(corner.y, 3.0f);
  EXPECT_FLOAT_EQ(corner.z, 3.0f);
  EXPECT_TRUE(std::isnan(depthToPoint(k, 10, 10, std::nanf("")).x));
}

TEST(CameraRender, WallRowsAndDepth)
{
  CameraPose pose{0, 0, 0.3, 0};
  Frame f = render(wallWorld(), pose);
  const auto& k = f.k;
  // At depth 5 the wall spans z in [0, 1]: rows cy - (1 - 0.3) fy / 5 .. cy + 0.3 fy / 5.
  const double v_top = k.cy - 0.7 * k.fy / 5, v_bottom = k.cy + 0.3 * k.fy / 5;
  int wall_rows = 0;
  for (int u = 0; u < k.width; ++u)
    for (int v = 0; v < k.height; ++v)
    {
      const double d = f.d(u, v);
      if (v < v_top - 0.5)
      {
        EXPECT_EQ(d, kInf) << u << "," << v;  // sky
      }
      else if (v > v_top + 0.5 && v < v_bottom - 0.5)
      {
        ASSERT_NEAR(d, 5.0, 1e-6) << u << "," << v;  // the wall, depth along the optical axis
        const uint8_t* p = f.px(u, v);
        EXPECT_GT(p[0], 70);  // red, shaded by the angle of incidence
        EXPECT_EQ(p[1], 0);
        EXPECT_EQ(p[2], 0);
        ++wall_rows;
      }
      else if (v > v_bottom + 0.5)
      {
        // Floor: depth where the pixel ray meets z = 0.
        EXPECT_NEAR(d, 0.3 * k.fy / (v - k.cy), 1e-6) << u << "," << v;
        const uint8_t* p = f.px(u, v);
        EXPECT_TRUE(p[0] == p[1] && p[1] == p[2]);  // grey
      }
    }
  EXPECT_GT(wall_rows, k.width * 10);
  // Centre column faces the wall head-on: brightest; the edges are darker.
  EXPECT_GT(f.px(k.width / 2, static_cast<int>(k.cy))[0], f.px(0, static_cast<int>(k.cy))[0]);
  // Sky is bluish.
  const uint8_t* sky = f.px(k.width / 2, 0);
  EXPECT_GT(sky[2], sky[0]);
}

TEST(CameraRender, PillarColumnsAndYaw)
{
  WorldSpec w = wallWorld();
  // A 0.2 x 0.2 pillar, 2 m high, front face at x = 2.9, spanning y in [0.9, 1.1].
  w.models.push_back(box("pillar", 3.0, 1.0, 1.0, 0.2, 0.2, 2.0, {0.0f, 0.0f, 1.0f}));
  CameraPose pose{0, 0, 0.3, 0};
  Frame f = render(w, pose);
  const auto& k = f.k;
  const int v = static_cast<int>(k.cy);
  // +y is left in the image: u = cx - fx * y / x.
  const double u_left = k.cx - k.fx * 1.1 / 2.9, u_right = k.cx - k.fx * 0.9 / 2.9;
  for (int u = 0; u < k.width; ++u)
  {
    if (u > u_left + 0.5 && u < u_right - 0.5)
    {
      EXPECT_NEAR(f.d(u, v), 2.9, 1e-6) << u;
      EXPECT_GT(f.px(u, v)[2], 70);
    }
    else if (u < u_left - 3 || u > u_right + 3)
    {
      EXPECT_NEAR(f.d(u, v), 5.0, 1e-6) << u;  // the wall behind (the pillar's side faces show just outside)
    }
  }
  // The pillar (2 m) stands above the wall (1 m): its column still has it above the wall's top.
  const int u_mid = static_cast<int>(0.5 * (u_left + u_right));
  const int v_above_wall = static_cast<int>(k.cy - 0.9 * k.fy / 2.9);  // z = 1.2 at depth 2.9
  EXPECT_NEAR(f.d(u_mid, v_above_wall), 2.9, 1e-6);

  // Turned 90 degrees left the camera sees no pillar at the centre: nothing in +y within the scene.
  Frame g = render(w, CameraPose{0, 0, 0.3, M_PI / 2});
  EXPECT_EQ(g.d(k.width / 2, static_cast<int>(k.cy) - 5), kInf);
  // Turned towards the pillar's centre the centre pixel sees its face at the right distance.
  const double yaw = std::atan2(1.0, 2.9);
  Frame h = render(w, CameraPose{0, 0, 0.3, yaw});
  EXPECT_NEAR(h.d(static_cast<int>(k.cx), static_cast<int>(k.cy)), 2.9 / std::cos(yaw), 0.02);
}

TEST(CameraRender, TopFaceOfLowBoxAndCylinder)
{
  WorldSpec w;
  w.ground_plane = true;
  // 0.5 m high box from x = 2 to 3; camera at 1 m looks down on its top.
  w.models.push_back(box("low", 2.5, 0, 0.25, 1.0, 4.0, 0.5));
  Frame f = render(w, CameraPose{0, 0, 1.0, 0});
  const auto& k = f.k;
  const int u = static_cast<int>(k.cx);
  // Top face: z = 0.5 between depths 2 and 3 -> rows cy + 0.5 fy / 3 .. cy + 0.5 fy / 2.
  for (int v = static_cast<int>(k.cy + 0.5 * k.fy / 3) + 1; v < k.cy + 0.5 * k.fy / 2; ++v)
    EXPECT_NEAR(f.d(u, v), 0.5 * k.fy / (v - k.cy), 1e-6) << v;
  // Side face below it at depth 2.
  for (int v = static_cast<int>(k.cy + 0.5 * k.fy / 2) + 1; v < k.cy + 1.0 * k.fy / 2; ++v)
    EXPECT_NEAR(f.d(u, v), 2.0, 1e-6);
  // Far beyond the box, above its top edge: the floor behind it.
  const int v_far = static_cast<int>(k.cy + 1.0 * k.fy / 8);
  EXPECT_NEAR(f.d(u, v_far), 1.0 * k.fy / (v_far - k.cy), 1e-6);

  // Upright cylinder r = 0.5 at x = 4: the nearest point at depth 3.5 on the axis.
  WorldSpec c;
  WorldModel m;
  m.pose = makeTransform(btVector3(4, 0, 1), btVector3(0, 0, 0));
  WorldLink l;
  Shape s;
  s.type = Shape::CYLINDER;
  s.radius = 0.5;
  s.length = 2;
  l.shapes.push_back(s);
  m.links.push_back(l);
  c.models.push_back(m);
  Frame g = render(c, CameraPose{0, 0, 0.3, 0}, 161, 121);
  EXPECT_NEAR(g.d(80, 60), 3.5, 3e-3);  // cx = 81 (1-based), so column 80 is 1/fx off axis
}

TEST(CameraRender, NearAndFarClip)
{
  PrismScene scene(wallWorld());
  CameraIntrinsics k = gazeboIntrinsics(40, 30, 1.0);
  std::vector<float> depth(40 * 30);
  RenderSettings s;
  s.near = 0.02;
  s.far = 4.0;  // the wall at 5 m is beyond far
  renderCamera(scene, k, CameraPose{0, 0, 0.3, 0}, s, nullptr, depth.data());
  EXPECT_EQ(depth[15 * 40 + 20], kInf);
  EXPECT_LE(depth[29 * 40 + 20], 4.0);  // the floor close by is still there
}

TEST(CameraNoise, TableStatistics)
{
  NoiseTable n(3);
  std::vector<float> v(200000, 1.0f);
  n.addToFloats(v.data(), v.size(), 0.0, 0.01);
  double sum = 0, sq = 0;
  for (float x : v)
  {
    sum += x - 1.0;
    sq += (x - 1.0) * (x - 1.0);
  }
  const double mean = sum / v.size(), sd = std::sqrt(sq / v.size() - mean * mean);
  EXPECT_NEAR(mean, 0.0, 5e-4);
  EXPECT_NEAR(sd, 0.01, 5e-4);
  // Infinite depths (sky) stay infinite.
  std::vector<float> inf(10, std::numeric_limits<float>::infinity());
  n.addToFloats(inf.data(), inf.size(), 0.0, 0.5);
  for (float x : inf)
    EXPECT_TRUE(std::isinf(x));
  // Bytes: stddev and mean in units of 255 (a mid grey gets 0.02 * 255 = 5.1 levels of offset
  // and 2.55 of spread, plus the rounding to whole levels: sqrt(2.55^2 + 1/12) = 2.57).
  std::vector<uint8_t> grey(200000, 128);
  n.addToBytes(grey.data(), grey.size(), 0.02, 0.01);
  sum = sq = 0;
  for (uint8_t x : grey)
  {
    sum += x - 128.0;
    sq += (x - 128.0) * (x - 128.0);
  }
  const double grey_mean = sum / grey.size(), grey_sd = std::sqrt(sq / grey.size() - grey_mean * grey_mean);
  EXPECT_NEAR(grey_mean, 5.1, 0.05);
  EXPECT_NEAR(grey_sd, 2.57, 0.05);
  // Bytes saturate instead of wrapping.
  std::vector<uint8_t> b(1000, 255);
  n.addToBytes(b.data(), b.size(), 0.0, 0.5);
  int low = 0;
  for (uint8_t x : b)
    low += x < 128;
  EXPECT_GT(low, 100);
  EXPECT_LT(low, 400);
}

TEST(RayCaster2D, CastAllFirstCrossingIsCast)
{
  WorldSpec w = wallWorld();
  w.models.push_back(box("pillar", 3.0, 1.0, 1.0, 0.2, 0.2, 2.0));
  Slice2D sl = sliceWorld(w, 0.3);
  RayCaster2D rc(sl, 0.25);
  std::mt19937 gen(1);
  std::uniform_real_distribution<double> ang(-M_PI, M_PI);
  std::vector<RayCaster2D::Crossing> all;
  for (int i = 0; i < 500; ++i)
  {
    double a = ang(gen), dx = std::cos(a), dy = std::sin(a);
    double first = rc.cast(0, 0, dx, dy, 30);
    rc.castAll(0, 0, dx, dy, 30, all);
    double mn = kInf;
    for (const auto& c : all)
      mn = std::min(mn, c.t);
    EXPECT_EQ(first, mn);
    // A closed polygon is crossed an even number of times by a ray from outside.
    if (std::isfinite(first))
    {
      EXPECT_EQ(all.size() % 2, 0u);
    }
  }
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}

// gazebo_ros_camera_utils' formats, and the bytes each encoding gives a 2 x 2 image.
TEST(CameraEncoding, GazeboFormatsAndTheirBytes)
{
  EXPECT_EQ(gazeboImageEncoding("R8G8B8"), "rgb8");
  EXPECT_EQ(gazeboImageEncoding("BGR_INT8"), "bgr8");
  EXPECT_EQ(gazeboImageEncoding("L_INT16"), "mono16");
  EXPECT_EQ(gazeboImageEncoding("R16G16B16"), "rgb16");
  EXPECT_EQ(gazeboImageEncoding("BAYER_GRBG8"), "bayer_grbg8");
  EXPECT_EQ(gazeboImageEncoding("R_FLOAT32"), "");
  // Red, green / blue, white.
  const std::vector<uint8_t> rgb = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
  uint32_t step = 0;
  EXPECT_EQ(encodeImage(rgb, 2, 2, "rgb8", step), rgb);
  EXPECT_EQ(step, 6u);
  EXPECT_EQ(encodeImage(rgb, 2, 2, "bgr8", step),
            (std::vector<uint8_t>{0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255}));
  // Luma 0.299 R + 0.587 G + 0.114 B.
  EXPECT_EQ(encodeImage(rgb, 2, 2, "mono8", step), (std::vector<uint8_t>{76, 149, 29, 255}));
  EXPECT_EQ(step, 2u);
  // 16 bits: 257 times the 8-bit value, little-endian.
  EXPECT_EQ(encodeImage(rgb, 2, 2, "mono16", step), (std::vector<uint8_t>{76, 76, 149, 149, 29, 29, 255, 255}));
  EXPECT_EQ(step, 4u);
  const std::vector<uint8_t> rgb16 = encodeImage(rgb, 2, 2, "rgb16", step);
  EXPECT_EQ(step, 12u);
  EXPECT_EQ(std::vector<uint8_t>(rgb16.begin(), rgb16.begin() + 6), (std::vector<uint8_t>{255, 255, 0, 0, 0, 0}));
  // Bayer: the pixel's own colour in its place of the pattern. RGGB reads R at (0, 0), G at
  // (1, 0) and (0, 1), B at (1, 1): red's R, green's G, blue's G, white's B.
  EXPECT_EQ(encodeImage(rgb, 2, 2, "bayer_rggb8", step), (std::vector<uint8_t>{255, 255, 0, 255}));
  EXPECT_EQ(step, 2u);
  EXPECT_EQ(encodeImage(rgb, 2, 2, "bayer_bggr8", step), (std::vector<uint8_t>{0, 255, 0, 255}));
  EXPECT_EQ(encodeImage(rgb, 2, 2, "bayer_gbrg8", step), (std::vector<uint8_t>{0, 0, 0, 255}));
  EXPECT_EQ(encodeImage(rgb, 2, 2, "bayer_grbg8", step), (std::vector<uint8_t>{0, 0, 255, 255}));
}
