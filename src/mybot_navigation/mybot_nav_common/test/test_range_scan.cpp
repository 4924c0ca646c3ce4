// LaserScan ranges to hits and free-space beams (REP 117).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "mybot_nav_common/range_scan.h"

using namespace mybot_navigation;

TEST(RangeScan, InvalidReadingsAreClassified)
{
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const std::vector<float> ranges{1.0f, nan, inf, -inf, 0.01f, 35.0f, 12.0f};
  ScanGeometry g;
  g.sensor_in_base = {0.1, 0.0, 0.0};
  ScanConversionStats st;
  const RangeScan s = convertRanges(ranges, 0.0, 0.1, 0.1, 30.0, 10.0, g, &st);
  EXPECT_EQ(st.hits, 1);
  EXPECT_EQ(st.invalid, 3);    // NaN, -inf, below range_min
  EXPECT_EQ(st.no_return, 2);  // +inf, >= range_max
  EXPECT_EQ(st.clipped, 1);    // 12 m > max usable 10 m
  ASSERT_EQ(s.hits.size(), 1u);
  EXPECT_NEAR(s.hits[0].x, 1.1, 1e-9);
  EXPECT_EQ(s.misses.size(), 3u);
  for (const Point2D& m : s.misses)
    EXPECT_NEAR(std::hypot(m.x - 0.1, m.y), 10.0, 1e-6);
  EXPECT_DOUBLE_EQ(s.usable_range, 10.0);  // no hit beyond it: a map from this scan ends there
  EXPECT_DOUBLE_EQ(convertRanges(ranges, 0.0, 0.1, 0.1, 8.0, 10.0, g).usable_range, 8.0);
}

TEST(RangeScan, UpsideDownSensorMirrorsAngles)
{
  ScanGeometry g;
  g.upside_down = true;
  const RangeScan s = convertRanges({1.0f}, M_PI / 2, 0.0, 0.1, 30.0, 30.0, g);
  ASSERT_EQ(s.hits.size(), 1u);
  EXPECT_NEAR(s.hits[0].y, -1.0, 1e-9);
}
