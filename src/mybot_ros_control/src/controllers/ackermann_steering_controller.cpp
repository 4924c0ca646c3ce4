// ackermann_steering_controller/AckermannSteeringController with ros_controllers' parameters and
// topics: a car-like robot's driven rear wheel (`rear_wheel`, VelocityJointInterface) and steered
// front wheel (`front_steer`, PositionJointInterface). As upstream, cmd_vel's linear.x is the rear
// wheel's rim speed and **angular.z is the steering angle** (rad), not a turn rate, limited by the
// angular/z block. The odometry is the bicycle model's (mybot_control::AckermannOdometry): the
// rear wheel's roll, turned by tan(steer) / wheel_separation_h.
#include "twist_drive.h"

#include <mybot_control/odometry.hpp>

#include <cmath>

namespace mybot_ros_control
{

namespace
{
class AckermannSteeringController : public TwistDrive
{
public:
  explicit AckermannSteeringController(const ControllerContext& c) : TwistDrive(c)
  {
    const std::string wheel = c.string("rear_wheel", "rear_wheel_joint");
    const std::string steer = c.string("front_steer", "front_steer_joint");
    wheel_ = &c.joint("rear_wheel", wheel, Interface::VELOCITY);
    steer_ = &c.joint("front_steer", steer, Interface::POSITION);
    claimed_[interfaceName(Interface::VELOCITY)] = {wheel};
    claimed_[interfaceName(Interface::POSITION)] = {steer};

    const double wheelbase_mult = c.positive("wheel_separation_h_multiplier", 1.0);
    const double radius_mult = c.positive("wheel_radius_multiplier", 1.0);
    steer_mult_ = c.positive("steer_pos_multiplier", 1.0);
    // As upstream: the two joints' origins apart along x in their parent frames.
    const mybot_gazebo_lite::RobotSpec& spec = c.plugin->robot->spec();
    const double wheelbase =
        c.nh.hasParam("wheel_separation_h")
            ? c.number("wheel_separation_h", 0.0)
            : std::fabs(spec.joint(wheel)->origin.getOrigin().x() - spec.joint(steer)->origin.getOrigin().x());
    radius_ = radius_mult *
              (c.nh.hasParam("wheel_radius") ? c.number("wheel_radius", 0.0) : radiusFromUrdf("wheel_radius", wheel));
    if (!(wheelbase > 0))
      c.fail("wheel_separation_h", "must be positive (the rear wheel to the front steer along x)");
    if (!(radius_ > 0))
      c.fail("wheel_radius", "must be positive");
    mybot_control::AckermannOdometry::Params op;
    wheelbase_ = wheelbase_mult * wheelbase;
    op.wheelbase = wheelbase_;
    op.wheel_radius = radius_;
    op.velocity_window = velocity_window_;
    odometry_ = mybot_control::AckermannOdometry(op);
    ROS_INFO("%s: wheel separation h %.4f m, wheel radius %.4f m", c.name.c_str(), op.wheelbase, op.wheel_radius);
  }

  void starting(double t) override
  {
    hw_->claim(*wheel_, Interface::VELOCITY);
    hw_->claim(*steer_, Interface::POSITION);
    brake();
    odometry_.reset();
    restart(t);
  }
  void stopping(double) override { brake(); }

  void update(double t, double dt) override
  {
    mybot_control::Twist2D twist;
    if (open_loop_)
    {
      // The command's angular.z is a steering angle: its turn rate is v tan(angle) / L.
      const mybot_control::Twist2D& c = lastCommand();
      twist = {c.vx, 0.0, c.vx * std::tan(c.wz) / wheelbase_};
      odometry_.setPose(mybot_control::poseExp(odometry_.pose(), twist * dt));
    }
    else
    {
      odometry_.update(wheel_->position, steer_->position * steer_mult_, t);
      twist = odometry_.twist();
    }
    publish(t, odometry_.pose(), twist);
    const mybot_control::Twist2D cmd = command(t, dt);
    wheel_->command = cmd.vx / radius_;
    steer_->command = cmd.wz;
  }

private:
  void brake()
  {
    wheel_->command = 0;
    steer_->command = 0;
  }

  SimJoint *wheel_ = nullptr, *steer_ = nullptr;
  double radius_ = 0.1, steer_mult_ = 1.0, wheelbase_ = 0.5;
  mybot_control::AckermannOdometry odometry_;
};
}  // namespace

std::unique_ptr<Controller> makeAckermannSteeringController(const ControllerContext& c)
{
  return std::make_unique<AckermannSteeringController>(c);
}

}  // namespace mybot_ros_control
