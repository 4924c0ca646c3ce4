// four_wheel_steering.hpp: the wheels' commands for a body twist, the twist a FourWheelSteering
// command asks for, and the odometry that turns the wheels' motion back into the body's.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "mybot_control/four_wheel_steering.hpp"

using namespace mybot_control;

namespace
{
FourWheelSteeringGeometry geometry(double offset = 0.0)
{
  FourWheelSteeringGeometry g;
  g.wheel_base = 0.6;
  g.steering_track = 0.4;
  g.wheel_radius = 0.1;
  g.steering_y_offset = offset;
  return g;
}
}  // namespace

TEST(FourWheelSteering, GeometryIsValidatedNamingTheField)
{
  EXPECT_EQ(geometry().validate(), "");
  FourWheelSteeringGeometry g = geometry();
  g.wheel_base = 0.0;
  EXPECT_NE(g.validate().find("wheel_base"), std::string::npos);
  g = geometry();
  g.wheel_radius = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(g.validate().find("wheel_radius"), std::string::npos);
  g = geometry();
  g.steering_track = -0.1;
  EXPECT_NE(g.validate().find("track"), std::string::npos);
}

TEST(FourWheelSteering, StraightAheadAndBackAllWheelsStraight)
{
  for (const double v : {0.5, -0.5})
    for (const SteeredWheelCommand& w : fourWheelSteeringCommands(geometry(0.05), {v, 0.0, 0.0}))
    {
      EXPECT_DOUBLE_EQ(w.steering, 0.0);  // backwards is the wheel reversed, not turned round
      EXPECT_DOUBLE_EQ(w.spin, v / 0.1);
    }
}

TEST(FourWheelSteering, AZeroTwistCentresTheSteering)
{
  for (const SteeredWheelCommand& w : fourWheelSteeringCommands(geometry(), {0.0, 0.0, 0.0}))
  {
    EXPECT_EQ(w.steering, 0.0);
    EXPECT_EQ(w.spin, 0.0);
  }
}

// Upstream's twist mode (linear.y = 0): the front wheels at atan(w L / (2 v -+ w T)), the rear ones
// mirrored, each rim at hypot(v -+ w T / 2, w L / 2), less w times the offset outwards.
TEST(FourWheelSteering, ATurnSteersAsUpstreamsTwistMode)
{
  const double v = 0.5, w = 0.8, L = 0.6, T = 0.4, o = 0.05, r = 0.1;
  const auto c = fourWheelSteeringCommands(geometry(o), {v, 0.0, w});
  EXPECT_NEAR(c[kFrontLeft].steering, std::atan(w * L / (2 * v - w * T)), 1e-12);
  EXPECT_NEAR(c[kFrontRight].steering, std::atan(w * L / (2 * v + w * T)), 1e-12);
  EXPECT_NEAR(c[kRearLeft].steering, -c[kFrontLeft].steering, 1e-12);
  EXPECT_NEAR(c[kRearRight].steering, -c[kFrontRight].steering, 1e-12);
  EXPECT_NEAR(c[kFrontLeft].spin, std::hypot(v - w * T / 2, w * L / 2) / r - w * o / r, 1e-12);
  EXPECT_NEAR(c[kFrontRight].spin, std::hypot(v + w * T / 2, w * L / 2) / r + w * o / r, 1e-12);
  EXPECT_NEAR(c[kRearLeft].spin, c[kFrontLeft].spin, 1e-12);
  EXPECT_NEAR(c[kRearRight].spin, c[kFrontRight].spin, 1e-12);
}

TEST(FourWheelSteering, ASidewaysTwistCrabsWithEveryWheelAtItsAngle)
{
  const double speed = 0.4, angle = 0.5;
  for (const SteeredWheelCommand& w :
       fourWheelSteeringCommands(geometry(0.05), {speed * std::cos(angle), speed * std::sin(angle), 0.0}))
  {
    EXPECT_NEAR(w.steering, angle, 1e-12);
    EXPECT_NEAR(w.spin, speed / 0.1, 1e-12);
  }
}

TEST(FourWheelSteering, ATurnOnTheSpotSteersEveryWheelAcrossItsRadius)
{
  const auto c = fourWheelSteeringCommands(geometry(), {0.0, 0.0, 1.0});
  const double across = std::atan2(0.3, 0.2);  // the pivot (0.3, 0.2) moves along (-0.2, 0.3)
  EXPECT_NEAR(c[kFrontLeft].steering, -across, 1e-12);
  EXPECT_NEAR(c[kFrontLeft].spin, -std::hypot(0.3, 0.2) / 0.1, 1e-12);  // backwards along it
  EXPECT_NEAR(c[kRearRight].steering, -across, 1e-12);
  EXPECT_NEAR(c[kRearRight].spin, std::hypot(0.3, 0.2) / 0.1, 1e-12);
  for (const SteeredWheelCommand& w : c)
    EXPECT_LE(std::abs(w.steering), M_PI_2);
}

TEST(FourWheelSteering, TheCommandsTwistIsUpstreamsBicycleModel)
{
  const FourWheelSteeringGeometry g = geometry();
  // Opposite angles: straight on at `speed`, turning at speed (tan f - tan r) / L.
  Twist2D t = fourWheelSteeringTwist(g, 0.5, 0.3, -0.3);
  EXPECT_NEAR(t.vx, 0.5, 1e-12);
  EXPECT_NEAR(t.vy, 0.0, 1e-12);
  EXPECT_NEAR(t.wz, 0.5 * 2 * std::tan(0.3) / 0.6, 1e-12);
  // Equal angles: a crab along them, at `speed`, as upstream's wheels roll.
  t = fourWheelSteeringTwist(g, 0.5, 0.4, 0.4);
  EXPECT_NEAR(t.vx, 0.5 * std::cos(0.4), 1e-12);
  EXPECT_NEAR(t.vy, 0.5 * std::sin(0.4), 1e-12);
  EXPECT_NEAR(t.wz, 0.0, 1e-12);
  // Sideways, and beyond (clamped to pi/2): finite, straight to the left.
  t = fourWheelSteeringTwist(g, 0.5, 2.0, M_PI_2);
  EXPECT_NEAR(t.vx, 0.0, 1e-12);
  EXPECT_NEAR(t.vy, 0.5, 1e-12);
  EXPECT_NEAR(t.wz, 0.0, 1e-12);
  // The front axle sideways, the rear one straight: a turn about the rear axle's centre.
  t = fourWheelSteeringTwist(g, 0.5, M_PI_2, 0.0);
  EXPECT_NEAR(t.vx, 0.0, 1e-9);
  EXPECT_NEAR(t.vy - t.wz * 0.3, 0.0, 1e-9);  // the rear axle's centre stands
  EXPECT_TRUE(std::isfinite(t.wz));
  // The axles sideways, opposite ways: a turn on the spot, each axle's centre at `speed`.
  t = fourWheelSteeringTwist(g, 0.5, M_PI_2, -M_PI_2);
  EXPECT_NEAR(t.wz * 0.3, 0.5, 1e-12);
}

// The two wheels of an axle steered for a FourWheelSteering command give back its virtual angle
// through upstream's equivalent-steering formula (what odom_steer reports).
TEST(FourWheelSteering, EachAxlesWheelsAverageToItsVirtualAngle)
{
  const FourWheelSteeringGeometry g = geometry();
  const auto c = fourWheelSteeringCommands(g, fourWheelSteeringTwist(g, 0.5, 0.3, -0.1));
  EXPECT_NEAR(equivalentSteering(c[kFrontLeft].steering, c[kFrontRight].steering), 0.3, 1e-12);
  EXPECT_NEAR(equivalentSteering(c[kRearLeft].steering, c[kRearRight].steering), -0.1, 1e-12);
  EXPECT_EQ(equivalentSteering(0.0, 0.0), 0.0);
}

// The odometry inverts the commands: wheels turned and steered as commanded for a constant twist
// give back the pose that twist reaches, with an offset pivot too.
TEST(FourWheelSteeringOdometry, RecoversTheCommandedMotion)
{
  for (const Twist2D& twist : {Twist2D{0.5, 0.0, 0.0}, Twist2D{0.4, 0.0, 0.7}, Twist2D{0.3, 0.2, 0.0},
                               Twist2D{0.2, -0.1, 0.4}, Twist2D{0.0, 0.0, 1.0}, Twist2D{-0.3, 0.0, -0.5}})
  {
    FourWheelSteeringOdometry::Params p;
    p.geometry = geometry(0.05);
    p.velocity_window = 1;
    FourWheelSteeringOdometry odom(p);
    const auto c = fourWheelSteeringCommands(p.geometry, twist);
    std::array<double, 4> wheels{}, steering{};
    for (std::size_t i = 0; i < 4; ++i)
      steering[i] = c[i].steering;
    const double dt = 0.01;
    ASSERT_TRUE(odom.update(wheels, steering, 0.0));
    for (int k = 1; k <= 200; ++k)
    {
      for (std::size_t i = 0; i < 4; ++i)
        wheels[i] += c[i].spin * dt;
      ASSERT_TRUE(odom.update(wheels, steering, k * dt));
    }
    const Pose2D expected = poseExp(Pose2D{}, Twist2D{twist.vx * 2.0, twist.vy * 2.0, twist.wz * 2.0});
    EXPECT_NEAR(odom.pose().x, expected.x, 1e-9) << twist.vx << " " << twist.vy << " " << twist.wz;
    EXPECT_NEAR(odom.pose().y, expected.y, 1e-9);
    EXPECT_NEAR(odom.pose().theta, expected.theta, 1e-9);
    EXPECT_NEAR(odom.twist().vx, twist.vx, 1e-9);
    EXPECT_NEAR(odom.twist().vy, twist.vy, 1e-9);
    EXPECT_NEAR(odom.twist().wz, twist.wz, 1e-9);
  }
}

TEST(FourWheelSteeringOdometry, BadReadingsAreRejectedAndTheFirstIsTheReference)
{
  FourWheelSteeringOdometry odom;
  EXPECT_TRUE(odom.update({5.0, 6.0, 7.0, 8.0}, {0.1, 0.1, 0.0, 0.0}, 1.0));
  EXPECT_EQ(odom.pose().x, 0.0);
  EXPECT_FALSE(odom.update({std::nan(""), 6.0, 7.0, 8.0}, {0.1, 0.1, 0.0, 0.0}, 1.01));
  EXPECT_FALSE(odom.update({5.0, 6.0, 7.0, 8.0}, {0.1, 0.1, 0.0, 0.0}, 1.0));  // not later
  EXPECT_EQ(odom.pose().x, 0.0);
}
