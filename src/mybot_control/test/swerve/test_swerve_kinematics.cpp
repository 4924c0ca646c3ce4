// Swerve kinematics, module states and chassis speeds (WPILib's test cases where they exist).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "mybot_control/swerve_kinematics.hpp"
#include "mybot_control/swerve_module.hpp"
#include "swerve_test_util.h"

using namespace mybot_control;
using namespace swerve_test;

TEST(SwerveKinematics, StraightAndStrafe)
{
  SwerveKinematics kin(robotOffsets());
  for (const auto& s : kin.toModuleStates({5.0, 0.0, 0.0}))
  {
    EXPECT_NEAR(5.0, s.speed, kEps);
    EXPECT_NEAR(0.0, s.angle, kEps);
  }
  for (const auto& s : kin.toModuleStates({0.0, 0.3, 0.0}))
  {
    EXPECT_NEAR(0.3, s.speed, kEps);
    EXPECT_NEAR(M_PI / 2, s.angle, kEps);
  }
}

TEST(SwerveKinematics, TurnInPlace)
{
  SwerveKinematics kin(robotOffsets());
  const double w = 2.0, r = std::hypot(0.25, 0.2);
  const auto states = kin.toModuleStates({0.0, 0.0, w});
  for (std::size_t i = 0; i < states.size(); ++i)
  {
    EXPECT_NEAR(w * r, states[i].speed, kEps);
    // Tangent to the circle: perpendicular to the offset, counter-clockwise.
    const Vec2 o = robotOffsets()[i];
    EXPECT_NEAR(wrapAngle(std::atan2(o.y, o.x) + M_PI / 2), states[i].angle, kEps);
  }
}

TEST(SwerveKinematics, CenterOfRotationAtAModule)
{
  SwerveKinematics kin(robotOffsets());
  kin.resetHeadings({0.3, 0.0, 0.0, 0.0});
  const auto states = kin.toModuleStates({0.0, 0.0, 1.0}, {0.25, 0.2});
  EXPECT_NEAR(0.0, states[0].speed, kEps);
  EXPECT_NEAR(0.3, states[0].angle, kEps);  // heading held: no speed, no direction
  EXPECT_NEAR(0.4, states[1].speed, kEps);  // b is 0.4 m to the right of a
  EXPECT_NEAR(0.0, states[1].angle, kEps);  // so it moves along +x
  EXPECT_NEAR(0.5, states[2].speed, kEps);  // c is 0.5 m behind a
  EXPECT_NEAR(-M_PI / 2, states[2].angle, kEps);
  EXPECT_NEAR(std::hypot(0.4, 0.5), states[3].speed, kEps);
  EXPECT_NEAR(std::atan2(-0.5, 0.4), states[3].angle, kEps);
}

TEST(SwerveKinematics, HeadingHoldAtZero)
{
  SwerveKinematics kin(robotOffsets());
  kin.toModuleStates({0.0, 0.3, 0.0});
  for (const auto& s : kin.toModuleStates({0.0, 0.0, 0.0}))
  {
    EXPECT_EQ(0.0, s.speed);
    EXPECT_NEAR(M_PI / 2, s.angle, kEps);
  }
}

TEST(SwerveKinematics, InverseThenForwardReturnsTheTwist)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  // Also an irregular three-module layout: least squares does not need symmetry.
  for (const auto& offsets : {robotOffsets(), std::vector<Vec2>{{0.3, 0.0}, {-0.1, 0.25}, {-0.2, -0.3}}})
  {
    SwerveKinematics kin(offsets);
    for (int k = 0; k < 100; ++k)
    {
      const Twist2D t{u(rng), u(rng), u(rng)};
      expectTwist(t, kin.toTwist(kin.toModuleStates(t)));
      const Vec2 c{u(rng), u(rng)};
      // About another centre the same body twist has extra translation w x c.
      const Twist2D about = kin.toTwist(kin.toModuleStates(t, c));
      expectTwist({t.vx + t.wz * c.y, t.vy - t.wz * c.x, t.wz}, about, 1e-8);
    }
  }
}

TEST(SwerveKinematics, ForwardIsTheLeastSquaresFit)
{
  SwerveKinematics kin(robotOffsets());
  // Three modules say "forward at 1 m/s", one disagrees (slipping sideways): the fit is the
  // mean translation plus the rotation the disagreement implies.
  std::vector<SwerveModuleState> states{{1.0, 0.0}, {1.0, 0.0}, {1.0, 0.0}, {1.0, M_PI / 2}};
  const Twist2D t = kin.toTwist(states);
  // Normal equations by hand for this layout: vx = mean(vxi) = 0.75, vy = mean(vyi) = 0.25,
  // wz = sum(-yi vxi + xi vyi) / sum(xi^2 + yi^2).
  EXPECT_NEAR(0.75, t.vx, kEps);
  EXPECT_NEAR(0.25, t.vy, kEps);
  const double num = -0.2 * 1 + 0.2 * 1 - 0.2 * 1 + (-0.25) * 1;
  EXPECT_NEAR(num / (4 * (0.25 * 0.25 + 0.2 * 0.2)), t.wz, kEps);
}

TEST(SwerveKinematics, RejectsBadLayouts)
{
  EXPECT_NE("", SwerveKinematics::validate({{0.1, 0.1}}));
  EXPECT_NE("", SwerveKinematics::validate({{0.1, 0.1}, {0.1, 0.1}, {-0.1, 0.0}}));
  EXPECT_NE("", SwerveKinematics::validate({{0.1, std::nan("")}, {0.0, 0.0}}));
  EXPECT_EQ("", SwerveKinematics::validate(robotOffsets()));
  EXPECT_THROW(SwerveKinematics({{0.2, 0.2}, {0.2, 0.2}}), std::invalid_argument);
  const std::string msg = SwerveKinematics::validate({{0.2, 0.2}, {0.0, 0.0}, {0.2, 0.2}});
  EXPECT_NE(std::string::npos, msg.find("same offset")) << msg;
}

TEST(SwerveModuleState, OptimizeLikeWpilib)
{
  // WPILib SwerveModuleStateTest.Optimize.
  auto a = optimizeModuleState({-2.0, M_PI}, 45 * kDeg);
  EXPECT_NEAR(2.0, a.speed, kEps);
  EXPECT_NEAR(0.0, a.angle, kEps);
  auto b = optimizeModuleState({4.7, 41 * kDeg}, -50 * kDeg);
  EXPECT_NEAR(-4.7, b.speed, kEps);
  EXPECT_NEAR(-139 * kDeg, b.angle, kEps);
  // No optimisation needed.
  auto c = optimizeModuleState({2.0, 89 * kDeg}, 0.0);
  EXPECT_NEAR(2.0, c.speed, kEps);
  EXPECT_NEAR(89 * kDeg, c.angle, kEps);
  // Across the +/-pi seam: 179 deg from -179 deg is a 2 degree turn.
  auto d = optimizeModuleState({1.0, 179 * kDeg}, -179 * kDeg);
  EXPECT_NEAR(1.0, d.speed, kEps);
  EXPECT_NEAR(179 * kDeg, d.angle, kEps);
}

TEST(SwerveModuleState, OptimizeNeverTurnsMoreThan90Degrees)
{
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  for (int k = 0; k < 10000; ++k)
  {
    const double current = u(rng);
    const SwerveModuleState want{u(rng), u(rng)};
    const auto got = optimizeModuleState(want, current);
    EXPECT_LE(std::abs(wrapAngle(got.angle - current)), M_PI / 2 + 1e-12);
    // Same wheel velocity vector.
    EXPECT_NEAR(want.speed * std::cos(want.angle), got.speed * std::cos(got.angle), 1e-9);
    EXPECT_NEAR(want.speed * std::sin(want.angle), got.speed * std::sin(got.angle), 1e-9);
  }
}

TEST(SwerveModuleState, CosineScale)
{
  EXPECT_NEAR(2.0 * std::cos(45 * kDeg), cosineScale({2.0, 45 * kDeg}, 0.0).speed, kEps);
  EXPECT_NEAR(-2.0 * std::cos(30 * kDeg), cosineScale({-2.0, -30 * kDeg}, 0.0).speed, kEps);
  EXPECT_NEAR(2.0, cosineScale({2.0, 3.0}, 3.0 - 2 * M_PI).speed, kEps);
  EXPECT_EQ(0.0, cosineScale({2.0, M_PI}, 0.0).speed);  // never reversed
}

TEST(SwerveModuleState, DesaturateLikeWpilib)
{
  // WPILib SwerveDriveKinematicsTest.Desaturate: speeds 5, 6, 4, 7 to 5.5 m/s.
  std::vector<SwerveModuleState> s{{5, 0}, {6, 0}, {4, 0}, {7, 0}};
  const double k = desaturateModuleSpeeds(s, 5.5);
  EXPECT_NEAR(5.5 / 7.0, k, kEps);
  EXPECT_NEAR(5.0 * k, s[0].speed, kEps);
  EXPECT_NEAR(6.0 * k, s[1].speed, kEps);
  EXPECT_NEAR(4.0 * k, s[2].speed, kEps);
  EXPECT_NEAR(5.5, s[3].speed, kEps);
  // Negative speeds count by magnitude; below the limit nothing changes.
  std::vector<SwerveModuleState> n{{-1.0, 0}, {0.5, 0}};
  EXPECT_EQ(1.0, desaturateModuleSpeeds(n, 2.0));
  EXPECT_NEAR(-2.0, (desaturateModuleSpeeds(n = {{-4.0, 0}, {1.0, 0}}, 2.0), n[0].speed), kEps);
  EXPECT_NEAR(0.5, n[1].speed, kEps);
}

TEST(SwerveKinematics, DesaturationKeepsTheDirectionOfTravel)
{
  SwerveKinematics kin(robotOffsets());
  const Twist2D t{3.0, 1.0, 4.0};
  auto states = kin.toModuleStates(t);
  const double k = desaturateModuleSpeeds(states, 1.0);
  ASSERT_LT(k, 1.0);
  expectTwist(t * k, kin.toTwist(states));
}

TEST(ChassisSpeeds, DiscretizeLikeWpilib)
{
  // WPILib ChassisSpeedsTest.Discretize: applying the discretized speeds for `duration` in
  // steps of dt lands where the continuous command (straight + turn) would.
  const Twist2D target{1.0, 0.0, 0.5};
  const double duration = 1.0, dt = 0.01;
  const Twist2D speeds = discretize(target, duration);
  Pose2D pose;
  for (double t = 0.0; t < duration - 1e-9; t += dt)
    pose = poseExp(pose, speeds * dt);
  EXPECT_NEAR(target.vx * duration, pose.x, 1e-9);
  EXPECT_NEAR(target.vy * duration, pose.y, 1e-9);
  EXPECT_NEAR(target.wz * duration, pose.theta, 1e-9);
  // Zero rotation or dt: unchanged.
  expectTwist({1.0, 2.0, 0.0}, discretize({1.0, 2.0, 0.0}, 0.02));
  expectTwist({1.0, 2.0, 3.0}, discretize({1.0, 2.0, 3.0}, 0.0));
}

TEST(ChassisSpeeds, DiscretizedTwistHoldsTheFieldDirectionOverAControlPeriod)
{
  // Translating along field +x while rotating: without discretisation each 20 ms step drifts
  // sideways by vx * wz * dt / 2 per metre; with it the end of each step lies on the line.
  const double dt = 0.02, wz = 2.0;
  Pose2D raw, fixed;
  for (int k = 0; k < 50; ++k)
  {
    const Twist2D want = fromFieldRelative({1.0, 0.0, wz}, raw.theta);
    raw = poseExp(raw, want * dt);
    const Twist2D want2 = fromFieldRelative({1.0, 0.0, wz}, fixed.theta);
    fixed = poseExp(fixed, discretize(want2, dt) * dt);
  }
  EXPECT_NEAR(0.0, fixed.y, 1e-9);
  EXPECT_GT(std::abs(raw.y), 0.01);
}

TEST(ChassisSpeeds, FieldRelative)
{
  // Facing +y (yaw 90 deg): field +x is the robot's right (-y body).
  expectTwist({0.0, -1.0, 0.5}, fromFieldRelative({1.0, 0.0, 0.5}, M_PI / 2));
  expectTwist({1.0, 0.0, 0.0}, fromFieldRelative({0.0, 1.0, 0.0}, M_PI / 2));
  expectTwist({-1.0, -2.0, 0.0}, fromFieldRelative({1.0, 2.0, 0.0}, M_PI));
}
