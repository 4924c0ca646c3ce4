// Swerve library: kinematics (WPILib's test cases where they exist), odometry, module loops.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "mybot_control/swerve_kinematics.hpp"
#include "mybot_control/swerve_limiter.hpp"
#include "mybot_control/swerve_module.hpp"
#include "mybot_control/swerve_odometry.hpp"

using namespace mybot_control;

namespace
{
constexpr double kEps = 1e-9;
const double kDeg = M_PI / 180.0;

// The swerve robot of mybot_description (a front-left, b front-right, c rear-left, d rear-right).
std::vector<Vec2> robotOffsets()
{
  return {{0.25, 0.2}, {0.25, -0.2}, {-0.25, 0.2}, {-0.25, -0.2}};
}

void expectTwist(const Twist2D& expected, const Twist2D& actual, double tol = 1e-9)
{
  EXPECT_NEAR(expected.vx, actual.vx, tol);
  EXPECT_NEAR(expected.vy, actual.vy, tol);
  EXPECT_NEAR(expected.wz, actual.wz, tol);
}
}  // namespace

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

namespace
{
// Simulated encoders of a rigid robot following a body twist exactly.
struct EncoderSim
{
  std::vector<Vec2> offsets = robotOffsets();
  double radius = 0.05;
  std::vector<double> wheels = std::vector<double>(4, 0.0), pivots = std::vector<double>(4, 0.0);
  void step(const Twist2D& t, double dt)
  {
    for (std::size_t i = 0; i < offsets.size(); ++i)
    {
      const double vx = t.vx - t.wz * offsets[i].y, vy = t.vy + t.wz * offsets[i].x;
      const double v = std::hypot(vx, vy);
      if (v > 1e-12)
        pivots[i] = std::atan2(vy, vx);
      wheels[i] += v * dt / radius;
    }
  }
};

SwerveOdometry::Params odomParams()
{
  SwerveOdometry::Params p;
  p.offsets = robotOffsets();
  p.wheel_radius = 0.05;
  return p;
}
}  // namespace

TEST(SwerveOdometry, FirstReadingDoesNotJump)
{
  SwerveOdometry odom(odomParams());
  EXPECT_TRUE(odom.update({100, -3, 7, 12}, {1, 2, 3, 0.5}, 5.0));
  EXPECT_EQ(0.0, odom.pose().x);
  EXPECT_EQ(0.0, odom.pose().y);
  EXPECT_EQ(0.0, odom.pose().theta);
}

TEST(SwerveOdometry, StrafeAndFullCircle)
{
  SwerveOdometry odom(odomParams());
  EncoderSim sim;
  sim.step({0.0, 1.0, 0.0}, 1e-9);  // set pivots for a strafe before the reference
  double t = 0.0;
  odom.update(sim.wheels, sim.pivots, t);
  for (int k = 0; k < 100; ++k)
  {
    sim.step({0.0, 0.3, 0.0}, 0.02);
    ASSERT_TRUE(odom.update(sim.wheels, sim.pivots, t += 0.02));
  }
  EXPECT_NEAR(0.0, odom.pose().x, 1e-9);
  EXPECT_NEAR(0.6, odom.pose().y, 1e-9);
  EXPECT_NEAR(0.3, odom.twist().vy, 1e-9);

  // A full circle translating while rotating with constant module angles relative to the
  // body is a circle in the world: back to the start.
  odom.reset();
  SwerveOdometry::Params p = odomParams();
  const Twist2D arc{0.5, 0.2, 0.5};
  EncoderSim s2;
  s2.step(arc, 1e-12);
  odom.update(s2.wheels, s2.pivots, t = 0.0);
  const int n = 1000;
  const double dt = 2 * M_PI / arc.wz / n;
  for (int k = 0; k < n; ++k)
  {
    s2.step(arc, dt);
    ASSERT_TRUE(odom.update(s2.wheels, s2.pivots, t += dt));
  }
  EXPECT_NEAR(0.0, odom.pose().x, 1e-9);
  EXPECT_NEAR(0.0, odom.pose().y, 1e-9);
  EXPECT_NEAR(0.0, odom.pose().theta, 1e-9);
  EXPECT_NEAR(2 * M_PI * std::hypot(arc.vx, arc.vy) / arc.wz, odom.distance(), 1e-9);
}

TEST(SwerveOdometry, RejectsNanAndStaleStamps)
{
  SwerveOdometry odom(odomParams());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ASSERT_TRUE(odom.update({0, 0, 0, 0}, {0, 0, 0, 0}, 1.0));
  EXPECT_FALSE(odom.update({nan, 0, 0, 0}, {0, 0, 0, 0}, 1.1));
  EXPECT_FALSE(odom.update({1, 1, 1, 1}, {0, 0, 0, 0}, 1.0));
  EXPECT_FALSE(odom.update({1, 1, 1}, {0, 0, 0}, 1.2));
  EXPECT_TRUE(odom.update({1, 1, 1, 1}, {0, 0, 0, 0}, 1.2));
  EXPECT_NEAR(0.05, odom.pose().x, 1e-12);
  EXPECT_TRUE(std::isfinite(odom.pose().theta));
}

TEST(SwerveOdometry, EncoderWrapAround)
{
  SwerveOdometry::Params p = odomParams();
  p.encoder_period = 2 * M_PI;
  SwerveOdometry odom(p);
  odom.update({3.1, 3.1, 3.1, 3.1}, {0, 0, 0, 0}, 0.0);
  const double w = 3.1 + 0.2 - 2 * M_PI;  // rolled 0.2 rad forward through the wrap
  odom.update({w, w, w, w}, {0, 0, 0, 0}, 0.02);
  EXPECT_NEAR(0.2 * 0.05, odom.pose().x, 1e-12);
}

TEST(SwerveOdometry, ImuYawReplacesTheWheelsHeading)
{
  SwerveOdometry odom(odomParams());
  EncoderSim sim;
  double t = 0.0, yaw = 1.0;  // IMU yaw has an arbitrary offset
  odom.update(sim.wheels, sim.pivots, t, yaw);
  for (int k = 0; k < 50; ++k)
  {
    sim.step({0.4, 0.0, 0.0}, 0.02);  // wheels say straight
    yaw += 0.01;                      // the IMU says the body turned (wheels slipping)
    odom.update(sim.wheels, sim.pivots, t += 0.02, yaw);
  }
  EXPECT_NEAR(0.5, odom.pose().theta, 1e-9);
  // A NaN IMU sample falls back to the wheels for that step.
  sim.step({0.4, 0.0, 0.0}, 0.02);
  EXPECT_TRUE(odom.update(sim.wheels, sim.pivots, t += 0.02, std::nan("")));
  EXPECT_NEAR(0.5, odom.pose().theta, 1e-9);
  EXPECT_THROW(SwerveOdometry(
                   []
                   {
                     auto p = odomParams();
                     p.wheel_radius = 0.0;
                     return p;
                   }()),
               std::invalid_argument);
}

TEST(SwerveOdometry, MidStepPivotAngle)
{
  // A module turning during a step rolled along its mean direction: with a 0.2 rad change per
  // step, the end angle alone (WPILib) would be off by 0.1 rad per step.
  SwerveOdometry odom(odomParams());
  odom.update({0, 0, 0, 0}, {0, 0, 0, 0}, 0.0);
  odom.update({1, 1, 1, 1}, {0.2, 0.2, 0.2, 0.2}, 0.02);
  EXPECT_NEAR(0.05 * std::cos(0.1), odom.pose().x, 1e-12);
  EXPECT_NEAR(0.05 * std::sin(0.1), odom.pose().y, 1e-12);
}

namespace
{
SwerveModuleConfig moduleConfig()
{
  SwerveModuleConfig c;
  c.pivot.p = 8.0;
  c.pivot.d = 0.0;
  c.pivot.output_min = -10.0;
  c.pivot.output_max = 10.0;
  c.drive.p = 0.5;
  c.drive.i = 2.0;
  c.drive.f = 1.0;
  c.wheel_radius = 0.05;
  return c;
}
}  // namespace

TEST(SwerveModuleController, NinetyDegreeStepConvergesWithoutOscillation)
{
  SwerveModuleController ctl(moduleConfig());
  MockModuleActuator act(0.03);
  const double dt = 0.02, goal = M_PI / 2;
  double settle = -1.0, worst_overshoot = 0.0;
  for (int k = 0; k < 100; ++k)
  {
    const auto out = ctl.update({0.0, goal}, act.pivotPosition(), act.wheelVelocity(), dt);
    act.step(out.pivot_command, out.wheel_command, dt);
    const double err = wrapAngle(act.pivotPosition() - goal);
    worst_overshoot = std::max(worst_overshoot, err);
    if (std::abs(err) > 0.02)
      settle = -1.0;
    else if (settle < 0.0)
      settle = (k + 1) * dt;
  }
  EXPECT_GT(settle, 0.0);
  EXPECT_LT(settle, 1.0);
  EXPECT_LT(worst_overshoot, 0.1);
}

TEST(SwerveModuleController, NeverTurnsMoreThan90Degrees)
{
  SwerveModuleController ctl(moduleConfig());
  MockModuleActuator act(0.03);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-M_PI, M_PI);
  const double dt = 0.02;
  for (int cmd = 0; cmd < 200; ++cmd)
  {
    const SwerveModuleState want{1.0, u(rng)};
    const double start = act.pivotPosition();
    double travelled = 0.0;
    for (int k = 0; k < 25; ++k)
    {
      const auto out = ctl.update(want, act.pivotPosition(), act.wheelVelocity(), dt);
      EXPECT_LE(std::abs(out.pivot_error), M_PI / 2 + 1e-12);
      act.step(out.pivot_command, out.wheel_command, dt);
      travelled = std::max(travelled, std::abs(act.pivotPosition() - start));
    }
    EXPECT_LE(travelled, M_PI / 2 + 0.1) << "command " << cmd;
  }
}

TEST(SwerveModuleController, DriveTracksSpeedWithCosineScaling)
{
  SwerveModuleController ctl(moduleConfig());
  MockModuleActuator act(0.05);
  const double dt = 0.02;
  SwerveModuleController::Output out;
  for (int k = 0; k < 150; ++k)
  {
    out = ctl.update({0.3, 0.0}, act.pivotPosition(), act.wheelVelocity(), dt);
    act.step(out.pivot_command, out.wheel_command, dt);
  }
  EXPECT_NEAR(0.3 / 0.05, act.wheelVelocity(), 0.01);
  EXPECT_NEAR(0.0, out.speed_error, 0.001);
  // Request 60 degrees off: the first step drives at cos(60) of the speed.
  SwerveModuleController fresh(moduleConfig());
  const auto o = fresh.update({0.3, M_PI / 3}, 0.0, 0.0, dt);
  EXPECT_NEAR(0.15, o.target.speed, 1e-12);
  EXPECT_NEAR(M_PI / 3, o.pivot_error, 1e-12);
}

TEST(SwerveModuleController, RateFeedForwardTracksARotatingRequest)
{
  SwerveModuleController ctl(moduleConfig());
  MockModuleActuator act(0.01);
  const double dt = 0.02, rate = 1.0;
  double worst = 0.0;
  for (int k = 0; k < 200; ++k)
  {
    const double want = wrapAngle(rate * k * dt);
    const auto out = ctl.update({0.0, want}, act.pivotPosition(), 0.0, dt);
    act.step(out.pivot_command, out.wheel_command, dt);
    if (k > 25)
      worst = std::max(worst, std::abs(out.pivot_error));
  }
  EXPECT_LT(worst, 0.05);
}

TEST(SwerveModuleConfig, Validates)
{
  SwerveModuleConfig c = moduleConfig();
  EXPECT_EQ("", c.validate());
  c.wheel_radius = 0.0;
  EXPECT_NE(std::string::npos, c.validate("m/").find("m/wheel_radius"));
  c = moduleConfig();
  c.drive.output_min = 5.0;
  c.drive.output_max = 1.0;
  EXPECT_NE(std::string::npos, c.validate().find("drive_pid/"));
}

TEST(SwerveTwistLimiter, KeepsTheCurvatureWhileAccelerating)
{
  SwerveTwistLimiter lim(SpeedLimits::symmetric(0.8, 1.0), SpeedLimits::symmetric(0.8, 1.0),
                         SpeedLimits::symmetric(2.0, 4.0));
  const Twist2D cmd{0.5, 0.0, 0.5};
  const double dt = 0.02;
  Twist2D prev;
  int steps = 0;
  for (; steps < 100; ++steps)
  {
    const Twist2D out = lim.limit(cmd, dt);
    EXPECT_NEAR(out.vx, out.wz, 1e-12);  // v / w stays the commanded 1 m radius
    EXPECT_EQ(0.0, out.vy);
    EXPECT_LE(std::abs(out.vx - prev.vx), 1.0 * dt + 1e-12);
    EXPECT_LE(std::abs(out.wz - prev.wz), 4.0 * dt + 1e-12);
    prev = out;
    if (std::abs(out.vx - cmd.vx) < 1e-12)
      break;
  }
  EXPECT_EQ(24, steps);  // limited by vx: 0.5 m/s at 1 m/s^2 in 25 steps of 20 ms
}

TEST(SwerveTwistLimiter, VelocityLimitScalesAllAxes)
{
  SwerveTwistLimiter lim(SpeedLimits::symmetric(0.5), SpeedLimits::symmetric(0.5), SpeedLimits::symmetric(1.0));
  const Twist2D out = lim.limit({1.0, 0.25, 0.5}, 0.02);
  EXPECT_NEAR(0.5, out.vx, 1e-12);
  EXPECT_NEAR(0.125, out.vy, 1e-12);
  EXPECT_NEAR(0.25, out.wz, 1e-12);
}

TEST(SwerveTwistLimiter, ChangeOfDirectionRespectsEveryAxis)
{
  SwerveTwistLimiter lim(SpeedLimits::symmetric(1.0, 1.0), SpeedLimits::symmetric(1.0, 2.0),
                         SpeedLimits::symmetric(1.0, 1.0));
  lim.reset({1.0, 0.0, 0.0});
  Twist2D prev = lim.last();
  for (int k = 0; k < 100; ++k)
  {
    const Twist2D out = lim.limit({0.0, 1.0, 0.0}, 0.02);
    EXPECT_LE(std::abs(out.vx - prev.vx), 1.0 * 0.02 + 1e-12);
    EXPECT_LE(std::abs(out.vy - prev.vy), 2.0 * 0.02 + 1e-12);
    prev = out;
  }
  EXPECT_NEAR(1.0, prev.vy, 1e-12);
  EXPECT_NEAR(0.0, prev.vx, 1e-12);
  // dt <= 0 or a NaN command: the last output, unchanged.
  EXPECT_EQ(prev.vy, lim.limit({5.0, 5.0, 5.0}, 0.0).vy);
  EXPECT_EQ(prev.vy, lim.limit({std::nan(""), 0.0, 0.0}, 0.02).vy);
}
