// four_wheel_steering_controller/FourWheelSteeringController with ros_controllers' parameters and
// topics: four wheels (front_wheel, rear_wheel: left then right, VelocityJointInterface), each
// steered (front_steering, rear_steering: PositionJointInterface). cmd_vel (geometry_msgs/Twist,
// linear.y too) and cmd_four_wheel_steering (four_wheel_steering_msgs/FourWheelSteering) in, the
// later one obeyed, as upstream; odom, odom_steer and /tf out. The kinematics and the odometry are
// mybot_control's four_wheel_steering.hpp (the rigid body's, where upstream has closed forms for
// two cases of it; they agree where upstream's apply, see the README).
#include "twist_drive.h"

#include <mybot_control/four_wheel_steering.hpp>

#include <four_wheel_steering_msgs/FourWheelSteering.h>
#include <four_wheel_steering_msgs/FourWheelSteeringStamped.h>

#include <array>
#include <cmath>
#include <limits>

namespace mybot_ros_control
{

namespace
{
class FourWheelSteeringController : public TwistDrive
{
public:
  explicit FourWheelSteeringController(const ControllerContext& c) : TwistDrive(c)
  {
    holonomic_ = true;
    const char* params[] = {"front_wheel", "rear_wheel", "front_steering", "rear_steering"};
    std::array<std::vector<std::string>, 4> names;
    for (int k = 0; k < 4; ++k)
    {
      names[k] = c.stringList(params[k], true);
      if (names[k].size() != 2)
        c.fail(params[k],
               "must name two joints, the left one then the right one (got " + std::to_string(names[k].size()) + ")");
    }
    for (int side = 0; side < 2; ++side)
    {
      wheels_[side] = &c.joint("front_wheel", names[0][side], Interface::VELOCITY);
      wheels_[2 + side] = &c.joint("rear_wheel", names[1][side], Interface::VELOCITY);
      steers_[side] = &c.joint("front_steering", names[2][side], Interface::POSITION);
      steers_[2 + side] = &c.joint("rear_steering", names[3][side], Interface::POSITION);
    }
    claimed_[interfaceName(Interface::VELOCITY)] = {names[0][0], names[0][1], names[1][0], names[1][1]};
    claimed_[interfaceName(Interface::POSITION)] = {names[2][0], names[2][1], names[3][0], names[3][1]};

    // As upstream: each figure from the parameter of its name, else from the URDF (the front
    // wheels apart, the front left wheel's radius, the front left and rear left wheels apart, the
    // front left steering joint to its wheel).
    mybot_control::FourWheelSteeringGeometry& g = odom_params_.geometry;
    const double track = c.nh.hasParam("track") ? c.number("track", 0.0) : jointDistance(names[0][0], names[0][1]);
    g.wheel_radius =
        c.nh.hasParam("wheel_radius") ? c.number("wheel_radius", 0.0) : radiusFromUrdf("wheel_radius", names[0][0]);
    g.wheel_base = c.nh.hasParam("wheel_base") ? c.number("wheel_base", 0.0) : jointDistance(names[0][0], names[1][0]);
    g.steering_y_offset = jointDistance(names[2][0], names[0][0]);
    g.steering_track = track - 2.0 * g.steering_y_offset;
    if (!(track > 0) || !std::isfinite(track))
      c.fail("track", "must be positive (the front wheels apart)");
    if (!(g.wheel_radius > 0) || !std::isfinite(g.wheel_radius))
      c.fail("wheel_radius", "must be positive");
    if (!(g.wheel_base > 0) || !std::isfinite(g.wheel_base))
      c.fail("wheel_base", "must be positive (the front and rear wheels apart)");
    if (!(g.steering_track > 0))
      c.fail("track", "must be more than twice the steering joints' offset from their wheels (" +
                          std::to_string(g.steering_y_offset) + " m)");
    odom_params_.velocity_window = velocity_window_;
    odometry_ = mybot_control::FourWheelSteeringOdometry(odom_params_);

    ros::NodeHandle nh = c.nh;
    sub_4ws_ = mybot_gazebo_lite::subscribeCommand<four_wheel_steering_msgs::FourWheelSteering>(
        *c.plugin, nh, "cmd_four_wheel_steering",
        [this](const four_wheel_steering_msgs::FourWheelSteering::ConstPtr& m) { on4ws(*m); });
    steer_pub_ = nh.advertise<four_wheel_steering_msgs::FourWheelSteeringStamped>("odom_steer", 100);
    ROS_INFO("%s: track %.4f m, wheel radius %.4f m, wheel base %.4f m, wheel steering offset %.4f m", c.name.c_str(),
             track, g.wheel_radius, g.wheel_base, g.steering_y_offset);
  }

  void starting(double t) override
  {
    for (SimJoint* w : wheels_)
      hw_->claim(*w, Interface::VELOCITY);
    for (SimJoint* s : steers_)
      hw_->claim(*s, Interface::POSITION);
    brake();
    odometry_.reset();
    four_ws_ = FourWs{};
    last_steer_ = SteerState{};
    restart(t);
  }
  void stopping(double) override { brake(); }

  void update(double t, double dt) override
  {
    std::array<double, 4> wheel{}, steer{};
    for (std::size_t i = 0; i < 4; ++i)
      wheel[i] = wheels_[i]->position, steer[i] = steers_[i]->position;
    odometry_.update(wheel, steer, t);
    const mybot_control::Twist2D twist = odometry_.twist();
    if (publish(t, odometry_.pose(), twist))
      publishSteer(t, twist, steer);

    const mybot_control::FourWheelSteeringGeometry& g = odom_params_.geometry;
    mybot_control::Twist2D cmd;
    if (four_ws_.stamp >= commandStamp())
    {
      // As upstream: the speed through the linear/x limits; the angles as they are (clamped).
      const bool fresh = t - four_ws_.stamp <= commandTimeout();
      const double speed = limited({fresh ? four_ws_.speed : 0.0, 0.0, 0.0}, dt, false).vx;
      cmd = mybot_control::fourWheelSteeringTwist(g, speed, fresh ? four_ws_.front : 0.0, fresh ? four_ws_.rear : 0.0);
    }
    else
      cmd = command(t, dt);
    const auto wheels = mybot_control::fourWheelSteeringCommands(g, cmd);
    for (std::size_t i = 0; i < 4; ++i)
    {
      wheels_[i]->command = wheels[i].spin;
      steers_[i]->command = wheels[i].steering;
    }
  }

private:
  struct FourWs
  {
    double speed = 0, front = 0, rear = 0, stamp = -std::numeric_limits<double>::infinity();
  };
  struct SteerState
  {
    double t = std::numeric_limits<double>::quiet_NaN(), speed = 0, accel = 0, front = 0, rear = 0;
  };

  void on4ws(const four_wheel_steering_msgs::FourWheelSteering& m)
  {
    if (!std::isfinite(m.speed) || !std::isfinite(m.front_steering_angle) || !std::isfinite(m.rear_steering_angle))
    {
      ROS_WARN_THROTTLE(1.0, "%s: ignoring a cmd_four_wheel_steering with a non-finite speed or angle",
                        c_.name.c_str());
      return;
    }
    four_ws_ = {m.speed, m.front_steering_angle, m.rear_steering_angle, c_.plugin->world->time()};
  }

  // odom_steer: what the wheels say of the virtual front and rear wheel (upstream's equivalent
  // angles) and of the speed, with the rates of change since the last publication.
  void publishSteer(double t, const mybot_control::Twist2D& twist, const std::array<double, 4>& steer)
  {
    using mybot_control::equivalentSteering;
    SteerState now;
    now.t = t;
    now.speed = std::copysign(std::hypot(twist.vx, twist.vy), twist.vx != 0.0 ? twist.vx : twist.vy);
    now.front = equivalentSteering(steer[mybot_control::kFrontLeft], steer[mybot_control::kFrontRight]);
    now.rear = equivalentSteering(steer[mybot_control::kRearLeft], steer[mybot_control::kRearRight]);
    const double dt = t - last_steer_.t;  // NaN at the first: rates 0
    const bool step = dt > 0.0;
    now.accel = step ? (now.speed - last_steer_.speed) / dt : 0.0;
    four_wheel_steering_msgs::FourWheelSteeringStamped m;
    m.header.stamp = ros::Time(t);
    m.header.frame_id = "odom";
    m.data.speed = now.speed;
    m.data.acceleration = now.accel;
    m.data.jerk = step ? (now.accel - last_steer_.accel) / dt : 0.0;
    m.data.front_steering_angle = now.front;
    m.data.rear_steering_angle = now.rear;
    m.data.front_steering_angle_velocity = step ? (now.front - last_steer_.front) / dt : 0.0;
    m.data.rear_steering_angle_velocity = step ? (now.rear - last_steer_.rear) / dt : 0.0;
    steer_pub_.publish(m);
    last_steer_ = now;
  }

  void brake()
  {
    for (std::size_t i = 0; i < 4; ++i)
      wheels_[i]->command = 0, steers_[i]->command = 0;
  }

  std::array<SimJoint*, 4> wheels_{}, steers_{};  // mybot_control::FourWheel order
  mybot_control::FourWheelSteeringOdometry::Params odom_params_;
  mybot_control::FourWheelSteeringOdometry odometry_;
  FourWs four_ws_;
  SteerState last_steer_;
  ros::Subscriber sub_4ws_;
  ros::Publisher steer_pub_;
};
}  // namespace

std::unique_ptr<Controller> makeFourWheelSteeringController(const ControllerContext& c)
{
  return std::make_unique<FourWheelSteeringController>(c);
}

}  // namespace mybot_ros_control
