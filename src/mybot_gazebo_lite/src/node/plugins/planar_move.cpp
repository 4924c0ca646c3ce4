// libgazebo_ros_planar_move.so: a holonomic base. The commanded twist (body frame) becomes the
// root link's velocity in the plane at every step, as upstream sets the model's velocity; the
// vertical velocity is left to gravity. The robot's contacts are made frictionless so that the
// ground does not brake what the plugin commands (in Gazebo the same friction makes planar_move
// robots fall short of their command unless the URDF sets mu to 0, which tutorials do).
#include "builtin.h"

#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>

#include <cmath>

namespace mybot_gazebo_lite
{

namespace
{
class PlanarMove : public SimPlugin
{
public:
  explicit PlanarMove(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    ros::NodeHandle nh(c.ns);
    odom_rate_ = Rate(p.num("odometryRate", 20.0));
    timeout_ = p.num("cmdTimeout", -1.0);  // upstream default: never
    publish_tf_ = p.boolean("publishOdometryTf", true);
    cov_[0] = p.num("covariance_x", 0.0001);
    cov_[1] = p.num("covariance_y", 0.0001);
    cov_[2] = p.num("covariance_yaw", 0.01);
    odom_frame_ = resolveFrame(c, p.str("odometryFrame", "odom"));
    base_frame_ = resolveFrame(c, p.str("robotBaseFrame", "base_footprint"));
    cmd_ = std::make_unique<TwistCommand>(c_, nh, p.topic("commandTopic", "cmd_vel"), timeout_);
    odom_pub_ = p.advertise<nav_msgs::Odometry>(nh, "odometryTopic", p.str("odometryTopic", "odom"), 1);
    c.robot->setContactFriction(0.0);
  }
  void reset() override { cmd_->reset(); }
  void preStep(double t) override
  {
    const geometry_msgs::Twist& cmd = cmd_->at(t);
    const double vx = cmd.linear.x, vy = cmd.linear.y, wz = cmd.angular.z;
    const Pose s = c_.robot->linkState(c_.robot->spec().root);
    btScalar yaw, pitch, roll;
    s.tf.getBasis().getEulerZYX(yaw, pitch, roll);
    const double cy = std::cos(yaw), sy = std::sin(yaw);
    c_.world->setRobotVelocity(*c_.robot, btVector3(vx * cy - vy * sy, vx * sy + vy * cy, s.linear.z()),
                               btVector3(0, 0, wz));
  }
  void update(double t) override
  {
    if (!odom_rate_.due(t))
      return;
    const nav_msgs::Odometry o = worldPoseOdometry(c_, t, odom_frame_, base_frame_, cov_);
    odom_pub_.publish(o);
    if (publish_tf_)
      c_.tf->sendTransform(toTf(c_.robot->linkState(c_.robot->spec().root).tf, t, odom_frame_, base_frame_));
  }

private:
  PluginContext c_;
  Rate odom_rate_;
  double timeout_, cov_[3];
  bool publish_tf_;
  std::string odom_frame_, base_frame_;
  std::unique_ptr<TwistCommand> cmd_;
  ros::Publisher odom_pub_;
};
}  // namespace

std::unique_ptr<SimPlugin> makePlanarMove(const PluginContext& c)
{
  return std::make_unique<PlanarMove>(c);
}

}  // namespace mybot_gazebo_lite
