// diff_drive_controller/DiffDriveController with ros_controllers' parameters and topics:
// cmd_vel in, odom and tf out, wheels through VelocityJointInterface. The odometry and the
// speed limits are this workspace's diff-drive library (mybot_control), the same as the
// real robot's controller.
#include "twist_drive.h"

#include <mybot_control/odometry.hpp>

#include <geometry_msgs/TwistStamped.h>

namespace mybot_ros_control
{

namespace
{
class DiffDriveController : public TwistDrive
{
public:
  explicit DiffDriveController(const ControllerContext& c) : TwistDrive(c)
  {
    const std::vector<std::string> left = c.stringList("left_wheel", true), right = c.stringList("right_wheel", true);
    for (const auto& n : left)
      left_.push_back(&c.joint("left_wheel", n, Interface::VELOCITY));
    for (const auto& n : right)
      right_.push_back(&c.joint("right_wheel", n, Interface::VELOCITY));
    auto& claim = claimed_[interfaceName(Interface::VELOCITY)];
    claim.insert(claim.end(), left.begin(), left.end());
    claim.insert(claim.end(), right.begin(), right.end());

    const double sep_mult = c.positive("wheel_separation_multiplier", 1.0);
    const double radius_mult = c.positive("wheel_radius_multiplier", 1.0);
    const double left_mult = c.positive("left_wheel_radius_multiplier", radius_mult);
    const double right_mult = c.positive("right_wheel_radius_multiplier", radius_mult);
    publish_cmd_ = c.boolean("publish_cmd", false);

    // As upstream: the distance between the two wheel joints' origins in their parent frames.
    const mybot_gazebo_lite::RobotSpec& spec = c.plugin->robot->spec();
    const double separation =
        c.nh.hasParam("wheel_separation")
            ? c.number("wheel_separation", 0.0)
            : (spec.joint(left.front())->origin.getOrigin() - spec.joint(right.front())->origin.getOrigin()).length();
    const double radius =
        c.nh.hasParam("wheel_radius") ? c.number("wheel_radius", 0.0) : radiusFromUrdf("wheel_radius", left.front());
    if (!(separation > 0))
      c.fail("wheel_separation", "must be positive");
    if (!(radius > 0))
      c.fail("wheel_radius", "must be positive");
    mybot_control::DiffDriveOdometry::Params op;
    op.wheel_separation = sep_mult * separation;
    op.left_radius = left_mult * radius;
    op.right_radius = right_mult * radius;
    op.velocity_window = velocity_window_;
    odometry_ = mybot_control::DiffDriveOdometry(op);
    kin_ = mybot_control::DiffDriveKinematics(op.wheel_separation, op.left_radius, op.right_radius);

    if (publish_cmd_)
      cmd_out_pub_ = ros::NodeHandle(c.nh).advertise<geometry_msgs::TwistStamped>("cmd_vel_out", 100);
    ROS_INFO("%s: wheel separation %.4f m, radius left %.4f m right %.4f m", c.name.c_str(), op.wheel_separation,
             op.left_radius, op.right_radius);
  }

  void starting(double t) override
  {
    for (SimJoint* j : left_)
      hw_->claim(*j, Interface::VELOCITY);
    for (SimJoint* j : right_)
      hw_->claim(*j, Interface::VELOCITY);
    odometry_.reset();
    restart(t);
  }
  void stopping(double) override { brake(); }

  void update(double t, double dt) override
  {
    // Odometry from the mean wheel angle of each side (the encoders), or the commands (open_loop).
    mybot_control::Twist2D twist;
    if (open_loop_)
    {
      twist = lastCommand();
      odometry_.setPose(mybot_control::poseExp(odometry_.pose(), twist * dt));
    }
    else
    {
      odometry_.update(mean(left_), mean(right_), t);
      twist = odometry_.twist();
    }
    publish(t, odometry_.pose(), twist);
    const mybot_control::Twist2D cmd = command(t, dt);
    if (publish_cmd_)
    {
      geometry_msgs::TwistStamped m;
      m.header.stamp = ros::Time(t);
      m.twist.linear.x = cmd.vx;
      m.twist.angular.z = cmd.wz;
      cmd_out_pub_.publish(m);
    }
    const mybot_control::WheelVelocities w = kin_.toWheelAngular(cmd);
    for (SimJoint* j : left_)
      j->command = w.left;
    for (SimJoint* j : right_)
      j->command = w.right;
  }

private:
  static double mean(const std::vector<SimJoint*>& js)
  {
    double s = 0;
    for (const SimJoint* j : js)
      s += j->position;
    return s / js.size();
  }
  void brake()
  {
    for (SimJoint* j : left_)
      j->command = 0;
    for (SimJoint* j : right_)
      j->command = 0;
  }

  std::vector<SimJoint*> left_, right_;
  bool publish_cmd_ = false;
  mybot_control::DiffDriveOdometry odometry_;
  mybot_control::DiffDriveKinematics kin_;
  ros::Publisher cmd_out_pub_;
};
}  // namespace

std::unique_ptr<Controller> makeDiffDriveController(const ControllerContext& c)
{
  return std::make_unique<DiffDriveController>(c);
}

}  // namespace mybot_ros_control
