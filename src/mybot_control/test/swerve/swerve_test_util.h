// Helpers of the swerve library's tests: the robot's module layout and twist comparison.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mybot_control/swerve_kinematics.hpp"

namespace swerve_test
{
using namespace mybot_control;

constexpr double kEps = 1e-9;
const double kDeg = M_PI / 180.0;

// The swerve robot of mybot_description (a front-left, b front-right, c rear-left, d rear-right).
inline std::vector<Vec2> robotOffsets()
{
  return {{0.25, 0.2}, {0.25, -0.2}, {-0.25, 0.2}, {-0.25, -0.2}};
}

inline void expectTwist(const Twist2D& expected, const Twist2D& actual, double tol = 1e-9)
{
  EXPECT_NEAR(expected.vx, actual.vx, tol);
  EXPECT_NEAR(expected.vy, actual.vy, tol);
  EXPECT_NEAR(expected.wz, actual.wz, tol);
}
}  // namespace swerve_test
