// libhector_gazebo_ros_force_based_move.so: a holonomic base driven through the physics (not by
// setting its velocity, as planar_move does): at every step a force on <robotBaseFrame>'s body, in
// its own axes, of x_velocity_p_gain / y_velocity_p_gain times the error of its velocity in x / y,
// and a torque about the vertical of yaw_velocity_p_gain times the error of its yaw rate (upstream's
// P controllers and gains, 10000 N/(m/s) and 100 N m/(rad/s)). Whatever friction its contacts have
// acts against the push, as in Gazebo (such bases set mu 0). Odometry at odometryRate (20 Hz): the
// world pose (upstream's), odom -> robotBaseFrame on tf with publishOdometryTf. Unlike upstream:
// the twist also carries linear.y (upstream leaves a holonomic base's sideways speed out), and
// odom_disturbed (upstream's, white noise of 5 units on the speeds, from a wall-clock seed) is not
// published. NaN or inf commands are ignored with a warning.
#include "builtin.h"

#include <nav_msgs/Odometry.h>

#include <cmath>

namespace mybot_gazebo_lite
{

namespace
{
class ForceBasedMove : public SimPlugin
{
public:
  explicit ForceBasedMove(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    ros::NodeHandle nh(c.ns);
    kx_ = p.num("x_velocity_p_gain", 10000.0);
    ky_ = p.num("y_velocity_p_gain", 10000.0);
    kyaw_ = p.num("yaw_velocity_p_gain", 100.0);
    for (const char* tag : {"x_velocity_p_gain", "y_velocity_p_gain", "yaw_velocity_p_gain"})
      if (p.num(tag, 0.0) < 0)
        p.fail(tag, "must be >= 0");
    const std::string base = p.str("robotBaseFrame", "base_footprint");
    link_ = p.link("robotBaseFrame", base);
    odom_rate_ = Rate(p.num("odometryRate", 20.0));
    publish_tf_ = p.boolean("publishOdometryTf", true);
    odom_frame_ = resolveFrame(c, p.str("odometryFrame", "odom"));
    base_frame_ = resolveFrame(c, base);
    cmd_ = std::make_unique<TwistCommand>(c_, nh, p.topic("commandTopic", "cmd_vel"), 0.0);  // upstream: no timeout
    odom_pub_ = p.advertise<nav_msgs::Odometry>(nh, "odometryTopic", p.str("odometryTopic", "odom"), kEveryStepQueue);
  }
  void reset() override { cmd_->reset(); }
  void preStep(double t) override
  {
    const geometry_msgs::Twist& cmd = cmd_->at(t);
    const Pose s = c_.robot->linkState(link_);
    const btMatrix3x3& R = s.tf.getBasis();
    const btVector3 v = R.transpose() * s.linear;  // in the link's axes
    const btVector3 force = R * btVector3((cmd.linear.x - v.x()) * kx_, (cmd.linear.y - v.y()) * ky_, 0.0);
    const btVector3 torque(0, 0, -(s.angular.z() - cmd.angular.z) * kyaw_);
    c_.robot->addWrench(link_, force, torque);
  }
  void update(double t) override
  {
    if (!odom_rate_.due(t))
      return;
    nav_msgs::Odometry o = worldPoseOdometry(c_, t, odom_frame_, base_frame_, kCovariance);
    // Upstream's pose covariance: the heading's is 0.01 at rest and 100 while turning.
    o.pose.covariance[35] = std::abs(o.twist.twist.angular.z) < 1e-4 ? 0.01 : 100.0;
    odom_pub_.publish(o);
    if (publish_tf_)
      c_.tf->sendTransform(toTf(c_.robot->linkState(c_.robot->spec().root).tf, t, odom_frame_, base_frame_));
  }

private:
  static constexpr double kCovariance[3] = {0.001, 0.001, 0.01};
  PluginContext c_;
  double kx_, ky_, kyaw_;
  std::string link_, odom_frame_, base_frame_;
  Rate odom_rate_;
  bool publish_tf_;
  std::unique_ptr<TwistCommand> cmd_;
  ros::Publisher odom_pub_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeHectorForceBasedMove(const PluginContext& c)
{
  return std::make_unique<ForceBasedMove>(c);
}

}  // namespace mybot_gazebo_lite
