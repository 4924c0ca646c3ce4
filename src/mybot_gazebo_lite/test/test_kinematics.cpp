// The drive plugins' kinematics: wheel speeds, legacy mode, encoder odometry.
#include "mybot_gazebo_lite/kinematics.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace mybot_gazebo_lite;

TEST(DiffDrive, WheelSpeedsAndLegacyMode)
{
  DiffDriveGeometry g;
  g.separation = 0.3;
  g.legacy = false;
  auto [l, r] = diffDriveWheelSpeeds(0.5, 1.0, g);
  EXPECT_DOUBLE_EQ(l, 0.35);
  EXPECT_DOUBLE_EQ(r, 0.65);
  g.legacy = true;
  std::tie(l, r) = diffDriveWheelSpeeds(0.5, 1.0, g);
  EXPECT_DOUBLE_EQ(l, 0.65);
  EXPECT_DOUBLE_EQ(r, 0.35);
}

TEST(DiffDrive, EncoderOdometryCircle)
{
  DiffDriveGeometry g;
  g.separation = 0.3;
  g.diameter = 0.2;
  g.legacy = false;
  EncoderOdometry o;
  // Wheels 4 and 6 rad/s: v = 0.5 m/s, w = 0.2/0.3 rad/s; a full circle returns home.
  double w = (0.6 - 0.4) / 0.3, T = 2 * M_PI / w;
  int n = 100000;
  for (int i = 0; i < n; ++i)
    o.update(4.0, 6.0, T / n, g);
  EXPECT_NEAR(o.x, 0, 1e-4);
  EXPECT_NEAR(o.y, 0, 1e-4);
  EXPECT_NEAR(o.v, 0.5, 1e-9);
}
