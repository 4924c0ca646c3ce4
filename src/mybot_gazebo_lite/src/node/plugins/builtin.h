// The plugins built into gazebo_lite, one a file in this folder; registry.cpp maps file names to them.
#pragma once

#include "mybot_gazebo_lite/kinematics.h"
#include "mybot_gazebo_lite/ros/sim_plugin.h"
#include "mybot_gazebo_lite/sensor_error_model.h"

#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/Imu.h>

namespace mybot_gazebo_lite
{

// The publisher queue of a plugin that may publish at every step (updateRate 0): under lockstep a
// participant handles every message of a period, and a period holds 10 steps at the default step
// (a queue of 1 lost 8 of 520 messages of libgazebo_ros_f3d.so to a Python subscriber).
constexpr uint32_t kEveryStepQueue = 100;

// The cmd_vel input of the drive plugins (counted under lockstep): a twist with a NaN or inf in
// vx, vy or wz is ignored with a warning, and the command falls back to zero once `timeout` s of
// sim time pass without one (<= 0: never).
class TwistCommand
{
public:
  TwistCommand(const PluginContext& c, ros::NodeHandle& nh, const std::string& topic, double timeout);
  // The command in force at sim time t.
  const geometry_msgs::Twist& at(double t);
  void reset();

private:
  const PluginContext& c_;
  double timeout_, stamp_ = 0;
  bool have_ = false;
  geometry_msgs::Twist cmd_;
  ros::Subscriber sub_;
};

// Odometry that is the root link's world pose and body-frame twist (the drive plugins that report
// ground truth as odometry, as upstream), with a diagonal covariance {x, y, yaw} on pose and twist.
nav_msgs::Odometry worldPoseOdometry(const PluginContext& c, double t, const std::string& odom_frame,
                                     const std::string& base_frame, const double cov[3]);

// What gazebo_ros's wheeled drives (diff drive, tricycle) publish alike at each update: odometry,
// from the root link's world pose or from encoder dead reckoning, with upstream's pose covariance;
// its tf (odom -> base) unless `odom_tf` is cleared; and on request (<publishWheelTF>,
// <publishWheelJointState>) each wheel's tf (parent link -> child link) and joint_states.
// Reads <odometryTopic> (odom), <odometryFrame> (odom), <robotBaseFrame> (`base_default`).
struct WheelDriveOutputs
{
  WheelDriveOutputs() = default;
  WheelDriveOutputs(const PluginContext& c, const PluginParams& p, ros::NodeHandle& nh, const std::string& base_default,
                    std::vector<std::string> joints);
  // `encoder`: the dead reckoning to publish, or null for the world pose.
  void publish(double t, const EncoderOdometry* encoder) const;
  bool odom_tf = true, odom_msg = true;

private:
  const PluginContext* c_ = nullptr;
  std::string odom_frame_, base_frame_;
  std::vector<std::string> joints_;
  bool wheel_tf_ = false, wheel_js_ = false;
  ros::Publisher odom_pub_, js_pub_;
};

// A <sensor type="ray">'s <ray>: ray/scan/{horizontal,vertical}/{samples,min_angle,max_angle} and
// ray/range/{min,max}, each checked naming its tag (samples are whole numbers, 1 to 100000 rays in
// all, as an unsigned count would not take 1e308; the angles' span is finite; 0 <= min < max).
struct RayScan
{
  int horizontal = 1, vertical = 1;  // samples
  double hmin = 0, hmax = 0, vmin = 0, vmax = 0;
  double range_min = 0, range_max = 0;
  // `horizontal_samples`: the default (SDF's is 640; the emulations of one-ray sensors take 1).
  static RayScan read(const PluginParams& s, int horizontal_samples);
};

// The rays of a <sensor type="ray"> (horizontal x vertical samples, Gazebo's convention: positive
// vertical angles look up) cast through Bullet, for the range and block-laser plugins.
struct SensorRays
{
  std::vector<btVector3> dirs;  // unit directions in the sensor frame, vertical-major
  double min = 0, max = 0;      // range limits (m)
  // Reads ray/scan/{horizontal,vertical}/{samples,min_angle,max_angle} and ray/range/{min,max}.
  static SensorRays fromSensor(const PluginParams& s);
  // Range along each ray from `sensor` (world frame), `max` where nothing is hit.
  std::vector<double> cast(const PhysicsWorld& world, const btTransform& sensor, const Robot* self) const;
  // The nearest of them (a sonar's reading), `max` where nothing is hit.
  double nearest(const PhysicsWorld& world, const btTransform& sensor, const Robot* self) const;
};

// An IMU message's orientation, angular velocity and linear acceleration (imu.cpp).
void setImu(sensor_msgs::Imu& m, const btQuaternion& q, const btVector3& w, const btVector3& a);

// What hector_gazebo_plugins' sensors read alike (hector_support.cpp).
// The error model's tags: <offset>, <drift>, <driftFrequency>, <gaussianNoise>, <scaleError>, or with
// a prefix <accelOffset>, <accelDrift>, ...; three axes ("x y z") or one. Negative spreads refused.
std::set<std::string> hectorErrorTags(const std::string& prefix);
SensorErrorParams hectorError(const PluginParams& p, const std::string& prefix);
std::array<SensorErrorParams, 3> hectorError3(const PluginParams& p, const std::string& prefix);
// hector's UpdateTimer: <updateRate> (Hz) or <updatePeriod> (s), 0 = every step.
Rate hectorUpdateRate(const PluginParams& p, double default_hz);
// <bodyName>, the model's first link without it; must be a link of the robot.
std::string hectorBody(const PluginContext& c, const PluginParams& p);
// <frameId> (default `def`) without leading slashes.
std::string hectorFrame(const PluginParams& p, const std::string& def);
// hector's UpdateTimer: fires at hectorUpdateRate's period and gives the sim time since it last
// fired (the error models' dt): 0 at the first firing, after a reset, and after time went back.
class HectorTimer
{
public:
  HectorTimer() = default;
  HectorTimer(const PluginParams& p, double default_hz) : rate_(hectorUpdateRate(p, default_hz)) {}
  bool due(double t, double& dt);
  void reset() { last_ = -1; }
  const uint64_t* fired() const { return &rate_.fired; }  // for sensorUpdates()

private:
  Rate rate_;
  double last_ = -1;
};

std::unique_ptr<SimPlugin> makeDiffDrive(const PluginContext& c);
std::unique_ptr<SimPlugin> makeSkidSteerDrive(const PluginContext& c);
std::unique_ptr<SimPlugin> makeHectorMultiWheelDrive(const PluginContext& c);
std::unique_ptr<SimPlugin> makePlanarMove(const PluginContext& c);
std::unique_ptr<SimPlugin> makeP3D(const PluginContext& c);
std::unique_ptr<SimPlugin> makeForce(const PluginContext& c);
std::unique_ptr<SimPlugin> makeF3D(const PluginContext& c);
std::unique_ptr<SimPlugin> makeFTSensor(const PluginContext& c);
std::unique_ptr<SimPlugin> makeTricycleDrive(const PluginContext& c);
std::unique_ptr<SimPlugin> makeVacuumGripper(const PluginContext& c);
std::unique_ptr<SimPlugin> makeMimicJoint(const PluginContext& c);
std::unique_ptr<SimPlugin> makeJointPoseTrajectory(const PluginContext& c);
std::unique_ptr<SimPlugin> makeJointStatePublisher(const PluginContext& c);
std::unique_ptr<SimPlugin> makeJointCommand(const PluginContext& c);
std::unique_ptr<SimPlugin> makeLaser(const PluginContext& c);
std::unique_ptr<SimPlugin> makeRange(const PluginContext& c);
std::unique_ptr<SimPlugin> makeBlockLaser(const PluginContext& c);
std::unique_ptr<SimPlugin> makeBumper(const PluginContext& c);
std::unique_ptr<SimPlugin> makeImuSensor(const PluginContext& c);
std::unique_ptr<SimPlugin> makeImu(const PluginContext& c);
std::unique_ptr<SimPlugin> makeCamera(const PluginContext& c);
std::unique_ptr<SimPlugin> makeDepthCamera(const PluginContext& c);     // gazebo_ros_openni_kinect
std::unique_ptr<SimPlugin> makeRosDepthCamera(const PluginContext& c);  // gazebo_ros_depth_camera
std::unique_ptr<SimPlugin> makeMultiCamera(const PluginContext& c);
std::unique_ptr<SimPlugin> makeTriggeredCamera(const PluginContext& c);
std::unique_ptr<SimPlugin> makeTriggeredMultiCamera(const PluginContext& c);  // a stereo pair
std::unique_ptr<SimPlugin> makeHectorGps(const PluginContext& c);
std::unique_ptr<SimPlugin> makeHectorImu(const PluginContext& c);
std::unique_ptr<SimPlugin> makeHectorMagnetic(const PluginContext& c);
std::unique_ptr<SimPlugin> makeHectorSonar(const PluginContext& c);
std::unique_ptr<SimPlugin> makeHectorForceBasedMove(const PluginContext& c);

}  // namespace mybot_gazebo_lite
