#include "mybot_common/pose2d.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace mybot_common;

TEST(Pose2D, WrapAngleIsHalfOpen)
{
  EXPECT_DOUBLE_EQ(wrapAngle(M_PI), M_PI);
  EXPECT_DOUBLE_EQ(wrapAngle(-M_PI), M_PI);  // (-pi, pi]: one heading, one value
  EXPECT_NEAR(wrapAngle(3 * M_PI / 2), -M_PI / 2, 1e-12);
  EXPECT_NEAR(wrapAngle(-7.0), -7.0 + 2 * M_PI, 1e-12);
  EXPECT_NEAR(wrapAngle(1e3), std::remainder(1e3, 2 * M_PI), 1e-9);
  EXPECT_TRUE(std::isnan(wrapAngle(std::numeric_limits<double>::quiet_NaN())));
}

TEST(Pose2D, ComposeInverseRoundTrip)
{
  const Pose2D a{1.0, -2.0, 2.5}, b{0.3, 0.7, 1.2};
  const Pose2D c = compose(a, b);
  const Pose2D back = between(a, c);
  EXPECT_NEAR(back.x, b.x, 1e-12);
  EXPECT_NEAR(back.y, b.y, 1e-12);
  EXPECT_NEAR(back.theta, b.theta, 1e-12);
  EXPECT_NEAR(c.theta, wrapAngle(3.7), 1e-12);
  EXPECT_LE(std::abs(c.theta), M_PI);
  const Pose2D identity = compose(a, inverse(a));
  EXPECT_NEAR(identity.x, 0.0, 1e-12);
  EXPECT_NEAR(identity.y, 0.0, 1e-12);
  EXPECT_NEAR(identity.theta, 0.0, 1e-12);
}

TEST(Pose2D, TransformPointRotatesThenTranslates)
{
  // A point 1 m ahead of a robot at (2, 3) facing +y is at (2, 4).
  const Point2D p = transformPoint(Pose2D{2.0, 3.0, M_PI / 2}, Point2D{1.0, 0.0});
  EXPECT_NEAR(p.x, 2.0, 1e-12);
  EXPECT_NEAR(p.y, 4.0, 1e-12);
  EXPECT_DOUBLE_EQ(translationNorm(Pose2D{3.0, 4.0, 1.0}), 5.0);
}
