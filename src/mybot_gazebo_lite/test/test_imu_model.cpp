// The IMU model on its own: what a sensor at rest, turning, or off the rotation axis measures.
#include "mybot_gazebo_lite/imu_model.h"

#include <gtest/gtest.h>

#include <cmath>

using mybot_gazebo_lite::ImuModel;
using mybot_gazebo_lite::Pose;

namespace
{
const btVector3 kGravity(0, 0, -9.8);
constexpr double kDt = 0.001;

// A body turning at w about the world z axis through the origin, at time t.
Pose turning(double w, double t)
{
  Pose p;
  p.tf = btTransform(btQuaternion(btVector3(0, 0, 1), w * t), btVector3(0, 0, 0));
  p.angular = btVector3(0, 0, w);
  return p;
}
}  // namespace

TEST(ImuModel, AtRestItFeelsTheGroundPushingUp)
{
  ImuModel imu;
  Pose p;
  for (int k = 0; k < 3; ++k)
    imu.step(p, kDt);
  const auto r = imu.read(p, kGravity);
  EXPECT_NEAR(r.linear_acceleration.z(), 9.8, 1e-9);
  EXPECT_NEAR(r.linear_acceleration.x(), 0.0, 1e-9);
  EXPECT_NEAR(r.angular_velocity.length(), 0.0, 1e-12);
}

TEST(ImuModel, TiltedOnItsSideGravityMovesToAnotherAxis)
{
  ImuModel imu;
  Pose p;
  p.tf.setRotation(btQuaternion(btVector3(1, 0, 0), M_PI / 2));  // rolled 90 degrees
  imu.step(p, kDt);
  imu.step(p, kDt);
  const auto r = imu.read(p, kGravity);
  EXPECT_NEAR(r.linear_acceleration.y(), 9.8, 1e-9);  // up is +y of the rolled sensor
  EXPECT_NEAR(r.linear_acceleration.z(), 0.0, 1e-9);
}

TEST(ImuModel, OffTheAxisATurningMountFeelsTheCentripetalPull)
{
  const double w = 2.0, radius = 0.5;
  ImuModel imu(btTransform(btQuaternion::getIdentity(), btVector3(radius, 0, 0)));
  for (int k = 0; k <= 100; ++k)
    imu.step(turning(w, k * kDt), kDt);
  const Pose p = turning(w, 100 * kDt);
  const auto r = imu.read(p, kGravity);
  EXPECT_NEAR(r.angular_velocity.z(), w, 1e-9);
  // Towards the axis: -x in the sensor frame, w^2 r (finite differences over 1 ms: 1e-3 relative).
  EXPECT_NEAR(r.linear_acceleration.x(), -w * w * radius, 2e-3);
  EXPECT_NEAR(r.linear_acceleration.y(), 0.0, 2e-2);
  EXPECT_NEAR(r.linear_acceleration.z(), 9.8, 1e-9);
}

TEST(ImuModel, ResetForgetsThePreviousVelocity)
{
  ImuModel imu;
  Pose moving;
  moving.linear = btVector3(1, 0, 0);
  imu.step(Pose(), kDt);
  imu.step(moving, kDt);  // 1 m/s in 1 ms: 1000 m/s^2
  EXPECT_NEAR(imu.read(moving, kGravity).linear_acceleration.x(), 1000.0, 1e-6);
  imu.reset();
  imu.step(moving, kDt);  // a first sample again: no acceleration from before the reset
  EXPECT_NEAR(imu.read(moving, kGravity).linear_acceleration.x(), 0.0, 1e-9);
}
