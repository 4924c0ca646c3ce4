// The robot of ros_controllers' four_wheel_steering_controller: four wheels, each steered about its
// own vertical axis (its pivot). The front and the rear pivots are wheel_base apart along x, the
// left and the right ones steering_track apart along y, and each wheel touches the ground
// steering_y_offset outside its pivot (a kingpin offset). The body frame is midway between the
// four pivots, x forward, y to the left. No ROS types.
//
// The rigid body's twist (vx, vy, wz) moves a point p of the body at (vx - wz p.y, vy + wz p.x).
// A wheel rolls without slipping along its heading h: its pivot moves along h, so the steering
// angle is that velocity's direction and the pivot's speed is its length. The contact point c is
// offset from the pivot perpendicularly to h, and c's velocity along h is the pivot's minus
// wz times the offset (outwards, so minus for the left wheels, plus for the right ones): that is
// the rim speed the wheel must turn at. The odometry inverts the same relation: each wheel's roll
// is one linear equation in the step's (dx, dy, dtheta), solved in least squares over the four.
#pragma once

#include <array>
#include <string>

#include "mybot_control/kinematics.hpp"
#include "mybot_control/odometry.hpp"

namespace mybot_control
{

struct FourWheelSteeringGeometry
{
  double wheel_base = 0.5;         // front to rear pivots, m
  double steering_track = 0.5;     // left to right pivots, m
  double wheel_radius = 0.1;       // m
  double steering_y_offset = 0.0;  // pivot to the wheel's contact, outwards, m
  // Empty when usable; else what is wrong, naming the field.
  std::string validate() const;
};

// The wheels in the order of the controller's joint lists: front left, front right, rear left,
// rear right.
enum FourWheel
{
  kFrontLeft = 0,
  kFrontRight = 1,
  kRearLeft = 2,
  kRearRight = 3
};

struct SteeredWheelCommand
{
  double spin = 0.0;      // the wheel joint's velocity, rad/s
  double steering = 0.0;  // the steering joint's angle, rad, within [-pi/2, pi/2]
};

// The wheels' commands for a body twist. A wheel whose pivot would move backwards is steered the
// other way, within [-pi/2, pi/2], and spins backwards. A zero twist centres the steering, as
// upstream brakes.
std::array<SteeredWheelCommand, 4> fourWheelSteeringCommands(const FourWheelSteeringGeometry& g, const Twist2D& twist);

// The body twist that four_wheel_steering_msgs/FourWheelSteering asks for: the front and the rear
// axle's virtual (bicycle) wheel steered to `front` and `rear` (rad, clamped to [-pi/2, pi/2] as
// upstream), the body's centre moving at `speed` (m/s, negative backwards). With equal angles the
// robot crabs along them without turning; with opposite ones it turns about a point on its
// lateral axis, at speed * (tan(front) - tan(rear)) / wheel_base, as upstream's controller.
Twist2D fourWheelSteeringTwist(const FourWheelSteeringGeometry& g, double speed, double front, double rear);

// The equivalent steering angle of an axle's virtual wheel from its two wheels' angles
// (upstream's odometry: atan(2 tan(l) tan(r) / (tan(l) + tan(r))), 0 when both are straight).
double equivalentSteering(double left, double right);

// Dead reckoning from the four wheel joints' positions and the four steering angles, as wpimath's
// odometries under their kinematics: each step's least-squares displacement, integrated by
// PoseIntegrator.
class FourWheelSteeringOdometry : public IntegratedOdometry
{
public:
  struct Params
  {
    FourWheelSteeringGeometry geometry;
    double encoder_period = 0.0;       // rad after which a wheel's position wraps; 0 = never
    std::size_t velocity_window = 10;  // samples of the twist rolling mean
  };

  FourWheelSteeringOdometry() : FourWheelSteeringOdometry(Params{}) {}
  explicit FourWheelSteeringOdometry(const Params& params);

  // Wheel joint positions (rad) and steering angles (rad), in FourWheel order, at time t (s). As
  // the other odometries: the first valid reading sets the reference; NaN/inf readings and
  // non-increasing stamps are rejected (false).
  bool update(const std::array<double, 4>& wheel_positions, const std::array<double, 4>& steering, double t);

  void resetEncoders();
  void reset()
  {
    setPose(Pose2D{});
    resetEncoders();
  }

private:
  Params params_;
  EncoderReadings<8> readings_;  // the four wheels, then the four steering angles
};

}  // namespace mybot_control
