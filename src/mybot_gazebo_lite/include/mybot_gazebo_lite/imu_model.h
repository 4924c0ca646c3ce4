// What an IMU fixed to a rigid body measures, without noise: its orientation, its angular
// velocity and its specific force (acceleration minus gravity: +9.8 up at rest), the last two in
// the sensor frame. No ROS.
#pragma once

#include "mybot_gazebo_lite/physics.h"

namespace mybot_gazebo_lite
{

class ImuModel
{
public:
  struct Reading
  {
    btQuaternion orientation;       // sensor frame in the world
    btVector3 angular_velocity;     // rad/s, sensor frame
    btVector3 linear_acceleration;  // m/s^2, sensor frame, gravity's reaction included
  };

  // sensor_in_body: the sensor's pose in the link it is fixed to.
  explicit ImuModel(const btTransform& sensor_in_body = btTransform::getIdentity()) : sensor_(sensor_in_body) {}

  // After every physics step of dt seconds: the sensor point's acceleration is the change of its
  // velocity over the step (the body's own velocity plus w x r for an offset sensor), which
  // includes the centripetal part a rotating mount feels.
  void step(const Pose& body, double dt);
  Reading read(const Pose& body, const btVector3& gravity) const;
  void reset()
  {
    have_previous_ = false;
    acceleration_ = btVector3(0, 0, 0);
  }

private:
  btVector3 pointVelocity(const Pose& body) const;

  btTransform sensor_;
  btVector3 previous_{0, 0, 0}, acceleration_{0, 0, 0};
  bool have_previous_ = false;
};

}  // namespace mybot_gazebo_lite
