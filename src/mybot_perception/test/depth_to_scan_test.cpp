#include "mybot_perception/depth_to_scan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

using namespace mybot_perception;

namespace
{
// A D435i-like camera: 87 degrees across 640 x 480.
PinholeColumns d435(int width = 640, int height = 480)
{
  return pinholeFromFov(width, height, 1.5184);
}

// A float depth image whose every row sees the same column depths.
std::vector<float> columns(const PinholeColumns& c, const std::function<float(double xr)>& depth_of_ray)
{
  std::vector<float> img(static_cast<std::size_t>(c.width) * c.height);
  for (int v = 0; v < c.height; ++v)
    for (int u = 0; u < c.width; ++u)
      img[static_cast<std::size_t>(v) * c.width + u] = depth_of_ray((u - c.cx) / c.fx);
  return img;
}

// The scan's beams as points in the scan plane: forward, left.
template <typename F>
void forEachPoint(const PlanarScan& s, F f)
{
  for (std::size_t i = 0; i < s.ranges.size(); ++i)
    if (std::isfinite(s.ranges[i]))
    {
      const double a = s.angle_min + i * s.angle_increment;
      f(s.ranges[i] * std::cos(a), s.ranges[i] * std::sin(a));
    }
}
}  // namespace

// Straight ahead at 2 m: every beam ends on the wall (forward = 2 m), the range is along the ray
// (2 m / cos(bearing), 2.76 m at the edges), not the depth.
TEST(DepthToScan, WallAheadIsRangedAlongTheRays)
{
  const PinholeColumns c = d435();
  const auto img = columns(c, [](double) { return 2.0f; });
  const PlanarScan s = depthToScan(img.data(), c.width, c, DepthToScanParams());
  ASSERT_EQ(s.ranges.size(), 640u);
  EXPECT_NEAR(s.angle_max, 1.5184 / 2.0, 0.002);
  EXPECT_NEAR(s.angle_min, -1.5184 / 2.0, 0.002);
  int finite = 0;
  forEachPoint(s,
               [&](double fwd, double)
               {
                 EXPECT_NEAR(fwd, 2.0, 0.005);
                 ++finite;
               });
  EXPECT_GT(finite, 540);  // a few edge beams get no column (bearings are not evenly spaced)
  EXPECT_NEAR(s.ranges.front(), 2.0 / std::cos(s.angle_min), 0.01);
  EXPECT_NEAR(s.ranges[320], 2.0, 0.002);
}

// A wall turned 30 degrees: the points lie on its line (forward cos a - left sin a = 2), and the
// nearer end is on the side the wall turns towards.
TEST(DepthToScan, WallAtAnAngleKeepsItsLine)
{
  const PinholeColumns c = d435();
  const double a = 30.0 * M_PI / 180.0;
  // Optical x is to the right (= -left): plane x sin a + z cos a = 2.
  const auto img = columns(c, [&](double xr) { return static_cast<float>(2.0 / (std::sin(a) * xr + std::cos(a))); });
  const PlanarScan s = depthToScan(img.data(), c.width, c, DepthToScanParams());
  int finite = 0;
  forEachPoint(s,
               [&](double fwd, double left)
               {
                 EXPECT_NEAR(fwd * std::cos(a) - left * std::sin(a), 2.0, 0.01) << fwd << " " << left;
                 ++finite;
               });
  EXPECT_GT(finite, 500);
  EXPECT_LT(s.ranges[10], s.ranges[630]);  // right side (angle_min) nearer
}

// A pole of 10 cm radius 3 m ahead and 0.5 m to the left, a wall at 8 m behind it.
TEST(DepthToScan, PoleIsSeenAtItsBearingAndDistance)
{
  const PinholeColumns c = d435();
  const double px = -0.5, pz = 3.0, radius = 0.1;  // optical frame: x right
  const auto img = columns(c,
                           [&](double xr)
                           {
                             // Ray (xr, 1) t against the circle |(x, z) - (px, pz)| = radius.
                             const double a = xr * xr + 1, b = -2 * (xr * px + pz),
                                          cc = px * px + pz * pz - radius * radius;
                             const double disc = b * b - 4 * a * cc;
                             return disc < 0 ? 8.0f : static_cast<float>((-b - std::sqrt(disc)) / (2 * a));
                           });
  const PlanarScan s = depthToScan(img.data(), c.width, c, DepthToScanParams());
  std::size_t nearest = 0;
  for (std::size_t i = 0; i < s.ranges.size(); ++i)
    if (std::isfinite(s.ranges[i]) && (!std::isfinite(s.ranges[nearest]) || s.ranges[i] < s.ranges[nearest]))
      nearest = i;
  EXPECT_NEAR(s.ranges[nearest], std::hypot(0.5, 3.0) - radius, 0.01);
  EXPECT_NEAR(s.angle_min + nearest * s.angle_increment, std::atan2(0.5, 3.0), 0.01);
}

// 16UC1 in millimetres gives the metres of 32FC1.
TEST(DepthToScan, MillimetreImageMatchesMetres)
{
  const PinholeColumns c = d435(320, 240);
  const auto metres = columns(c, [](double xr) { return static_cast<float>(1.5 + 0.5 * xr); });
  std::vector<std::uint16_t> mm(metres.size());
  for (std::size_t i = 0; i < mm.size(); ++i)
    mm[i] = static_cast<std::uint16_t>(std::lround(metres[i] * 1000));
  const PlanarScan a = depthToScan(metres.data(), c.width, c, DepthToScanParams());
  const PlanarScan b = depthToScan(mm.data(), c.width, c, DepthToScanParams());
  for (std::size_t i = 0; i < a.ranges.size(); ++i)
  {
    if (std::isfinite(a.ranges[i]))
      EXPECT_NEAR(a.ranges[i], b.ranges[i], 0.002);
  }
}

// REP 117: no depth (NaN, or 0 in millimetres) is no return, +inf, as is a return beyond
// range_max; only too near is -inf; a valid range beats both. Only a bearing that no column
// falls on stays NaN.
TEST(DepthToScan, NoReturnsFollowRep117)
{
  const PinholeColumns c = d435(64, 48);
  const auto nan = columns(c, [](double) { return std::numeric_limits<float>::quiet_NaN(); });
  int inf = 0;
  for (float r : depthToScan(nan.data(), c.width, c, DepthToScanParams()).ranges)
  {
    EXPECT_TRUE(std::isnan(r) || r == std::numeric_limits<float>::infinity());
    inf += std::isinf(r);
  }
  EXPECT_GT(inf, 48);
  const std::vector<std::uint16_t> zeros(static_cast<std::size_t>(c.width) * c.height, 0);
  EXPECT_EQ(depthToScan(zeros.data(), c.width, c, DepthToScanParams()).ranges[32],
            std::numeric_limits<float>::infinity());
  const auto far = columns(c, [](double) { return 50.0f; });
  const auto near = columns(c, [](double) { return 0.1f; });
  const PlanarScan f = depthToScan(far.data(), c.width, c, DepthToScanParams());
  const PlanarScan n = depthToScan(near.data(), c.width, c, DepthToScanParams());
  EXPECT_EQ(f.ranges[32], std::numeric_limits<float>::infinity());
  EXPECT_EQ(n.ranges[32], -std::numeric_limits<float>::infinity());
}

// The band: the nearest valid depth among scan_height rows centred on the optical centre; rows
// outside the band do not count.
TEST(DepthToScan, BandTakesTheNearestOfItsRows)
{
  const PinholeColumns c = d435(64, 48);
  auto img = columns(c, [](double) { return 3.0f; });
  const int centre = static_cast<int>(std::lround(c.cy));
  for (int u = 0; u < c.width; ++u)
  {
    img[static_cast<std::size_t>(centre + 1) * c.width + u] = 2.0f;  // in a band of 5
    img[static_cast<std::size_t>(centre - 2) * c.width + u] = std::numeric_limits<float>::quiet_NaN();
    img[static_cast<std::size_t>(centre + 5) * c.width + u] = 1.0f;  // outside it
  }
  DepthToScanParams one, five;
  five.scan_height = 5;
  EXPECT_NEAR(depthToScan(img.data(), c.width, c, one).ranges[32], 3.0, 0.01);
  EXPECT_NEAR(depthToScan(img.data(), c.width, c, five).ranges[32], 2.0, 0.01);
}

TEST(DepthToScan, BadCameraOrParametersAreNamed)
{
  DepthToScanParams p;
  p.scan_height = 0;
  EXPECT_NE(checkDepthToScan(d435(), p).find("scan_height"), std::string::npos);
  p.scan_height = 1;
  p.range_min = 5.0;
  p.range_max = 1.0;
  EXPECT_NE(checkDepthToScan(d435(), p).find("range_min"), std::string::npos);
  PinholeColumns c = d435();
  c.fx = 0.0;
  EXPECT_NE(checkDepthToScan(c, DepthToScanParams()).find("camera_info K"), std::string::npos);
  EXPECT_EQ(checkDepthToScan(d435(), DepthToScanParams()), "");
}
