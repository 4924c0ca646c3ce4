// Dead-reckoning odometry for a differential drive from wheel joint positions.
#pragma once

#include <array>
#include <cmath>
#include <deque>

#include "mybot_control/kinematics.hpp"

namespace mybot_control
{

// Unwraps a joint position that wraps with period `period` (0 = does not wrap): returns the
// smallest signed step from `previous` to `current` modulo the period.
double unwrappedDelta(double previous, double current, double period);

// Rolling mean of the last N samples.
class RollingMean
{
public:
  explicit RollingMean(std::size_t window = 1);
  void setWindow(std::size_t window);
  void push(double v);
  void reset();
  double mean() const;

private:
  std::size_t window_;
  std::deque<double> values_;
};

// Stamped joint readings as the encoder and the odometries take them: one with a NaN or inf, or stamped no later
// than the last, is rejected; the first after a reset only sets the reference, so the pose does
// not jump by where the encoders happened to start. A step keeps the readings before it.
template <std::size_t N>
class EncoderReadings
{
public:
  enum Result
  {
    REJECTED,
    REFERENCE,
    STEP
  };
  Result take(const std::array<double, N>& values, double t)
  {
    if (!std::isfinite(t))
      return REJECTED;
    for (const double v : values)
      if (!std::isfinite(v))
        return REJECTED;
    if (!have_reference_)
    {
      have_reference_ = true;
      last_ = values;
      t_last_ = t;
      return REFERENCE;
    }
    if (!(t > t_last_))
      return REJECTED;
    before_ = last_;
    dt_ = t - t_last_;
    last_ = values;
    t_last_ = t;
    return STEP;
  }
  void reset() { have_reference_ = false; }
  // Of the last STEP: the readings it started from, and its duration (s).
  const std::array<double, N>& before() const { return before_; }
  double dt() const { return dt_; }

private:
  bool have_reference_ = false;
  std::array<double, N> last_{}, before_{};
  double t_last_ = 0.0, dt_ = 0.0;
};

// Angular velocity of one wheel from stamped joint positions: the slope over the last
// `window` position steps. Readings are taken by EncoderReadings' rules, as the odometries take them.
class WheelEncoder
{
public:
  explicit WheelEncoder(std::size_t window = 1, double period = 0.0);
  bool update(double position, double t);
  void reset();
  bool valid() const { return samples_.size() >= 2; }
  double velocity() const { return velocity_; }  // rad/s
  double lastStamp() const { return samples_.empty() ? 0.0 : samples_.back().t; }

private:
  struct Sample
  {
    double t, position;  // position unwrapped
  };
  std::size_t window_;
  double period_;
  EncoderReadings<1> readings_;
  std::deque<Sample> samples_;
  double velocity_ = 0.0;
};

// What every wheeled odometry shares under its own kinematics, as wpimath's Odometry does under
// DifferentialDriveOdometry and SwerveDriveOdometry: the kinematics turns a step's wheel motion
// into a body displacement (dx, dy, dtheta); this integrates it along the constant-twist path
// (poseExp: exact for a constant twist over the step, where adding it in the start heading
// drifts outwards on every turn), adds it to the path length and, divided by the step's
// duration, to a rolling mean of the body twist.
class PoseIntegrator
{
public:
  explicit PoseIntegrator(std::size_t velocity_window)
      : vx_(velocity_window), vy_(velocity_window), wz_(velocity_window)
  {
  }
  // One step's body displacement over dt > 0 seconds.
  void integrate(const Twist2D& delta, double dt)
  {
    pose_ = poseExp(pose_, delta);
    distance_ += std::hypot(delta.vx, delta.vy);
    vx_.push(delta.vx / dt);
    vy_.push(delta.vy / dt);
    wz_.push(delta.wz / dt);
  }
  void setPose(const Pose2D& pose) { pose_ = {pose.x, pose.y, wrapAngle(pose.theta)}; }
  void resetTwist()
  {
    vx_.reset();
    vy_.reset();
    wz_.reset();
  }
  void resetDistance() { distance_ = 0.0; }

  const Pose2D& pose() const { return pose_; }
  Twist2D twist() const { return {vx_.mean(), vy_.mean(), wz_.mean()}; }
  double distance() const { return distance_; }

private:
  Pose2D pose_;
  RollingMean vx_, vy_, wz_;
  double distance_ = 0.0;
};

// What every odometry shows of its PoseIntegrator, the one home of these accessors: the pose (it
// can be set: set_pose, open-loop odometry), the rolling mean of the body twist over the last
// velocity_window updates, and the path length.
class IntegratedOdometry
{
public:
  void setPose(const Pose2D& pose) { integrator_.setPose(pose); }
  const Pose2D& pose() const { return integrator_.pose(); }
  Twist2D twist() const { return integrator_.twist(); }
  double distance() const { return integrator_.distance(); }  // total |path| length, m

protected:
  explicit IntegratedOdometry(std::size_t velocity_window) : integrator_(velocity_window) {}
  PoseIntegrator integrator_;
};

class DiffDriveOdometry : public IntegratedOdometry
{
public:
  struct Params
  {
    double wheel_separation = 0.3;
    double left_radius = 0.1;
    double right_radius = 0.1;
    double encoder_period = 0.0;       // rad after which joint positions wrap; 0 = never
    std::size_t velocity_window = 10;  // samples of the twist rolling mean (diff_drive_controller)
  };

  DiffDriveOdometry() : DiffDriveOdometry(Params{}) {}
  explicit DiffDriveOdometry(const Params& params);

  // Feed wheel joint positions (rad) stamped at time t (s). The first valid reading only sets
  // the reference (no jump); NaN/inf readings and non-increasing stamps are rejected (false).
  bool update(double left_position, double right_position, double t);

  // Forget the encoder reference (the next reading is a first reading again).
  void resetEncoders();
  void reset()
  {
    setPose(Pose2D{});
    resetEncoders();
  }

  // Most recent per-update wheel rim speeds (m/s) and the angular ones (rad/s).
  const WheelVelocities& wheelTangent() const { return wheel_tangent_; }
  const DiffDriveKinematics& kinematics() const { return kin_; }

private:
  Params params_;
  DiffDriveKinematics kin_;
  EncoderReadings<2> readings_;  // left, right
  WheelVelocities wheel_tangent_;
};

// A car-like robot's odometry (ros_controllers' ackermann_steering_controller): a driven rear axle
// and a steered front wheel, in the bicycle model. Over a step the rear axle's centre rolls
// s = r dphi along its heading (r the wheel's radius, dphi its turn) and, with the front wheel
// steered by delta, turns about the point where the rear axle's line meets the front wheel's: a
// circle of radius L / tan(delta) (L the wheelbase), so dtheta = s tan(delta) / L. The step's
// delta is the mean of its two readings (the steering moves while the wheel rolls; upstream takes
// the last one). The pose is the rear axle's centre.
class AckermannOdometry : public IntegratedOdometry
{
public:
  struct Params
  {
    double wheelbase = 0.5;            // rear axle to front wheel, m
    double wheel_radius = 0.1;         // the rear wheel's, m
    double encoder_period = 0.0;       // rad after which the wheel's position wraps; 0 = never
    std::size_t velocity_window = 10;  // samples of the twist rolling mean
  };

  AckermannOdometry() : AckermannOdometry(Params{}) {}
  explicit AckermannOdometry(const Params& params);

  // The rear wheel's joint position (rad) and the steering angle (rad) at time t (s). As
  // DiffDriveOdometry: the first valid reading sets the reference; NaN/inf readings and
  // non-increasing stamps are rejected (false).
  bool update(double wheel_position, double steering_angle, double t);

  void resetEncoders();
  void reset()
  {
    setPose(Pose2D{});
    resetEncoders();
  }

private:
  Params params_;
  EncoderReadings<2> readings_;  // the wheel, the steering
};

}  // namespace mybot_control
