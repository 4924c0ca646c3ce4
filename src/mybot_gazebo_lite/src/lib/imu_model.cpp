#include "mybot_gazebo_lite/imu_model.h"

namespace mybot_gazebo_lite
{

btVector3 ImuModel::pointVelocity(const Pose& body) const
{
  const btTransform tf = body.tf * sensor_;
  return body.linear + body.angular.cross(tf.getOrigin() - body.tf.getOrigin());
}

void ImuModel::step(const Pose& body, double dt)
{
  const btVector3 v = pointVelocity(body);
  if (have_previous_ && dt > 0)
    acceleration_ = (v - previous_) / dt;
  previous_ = v;
  have_previous_ = true;
}

ImuModel::Reading ImuModel::read(const Pose& body, const btVector3& gravity) const
{
  const btTransform tf = body.tf * sensor_;
  const btMatrix3x3& R = tf.getBasis();
  return {tf.getRotation(), R.transpose() * body.angular, R.transpose() * (acceleration_ - gravity)};
}

}  // namespace mybot_gazebo_lite
