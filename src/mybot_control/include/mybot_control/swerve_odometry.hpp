// Dead-reckoning odometry for a swerve drive: per-module wheel distance deltas and pivot
// angles -> least-squares body displacement -> pose exponential. Optional yaw fusion from
// an IMU. No ROS types.
#pragma once

#include <optional>
#include <vector>

#include "mybot_control/odometry.hpp"
#include "mybot_control/swerve_kinematics.hpp"

namespace mybot_control
{

class SwerveOdometry : public IntegratedOdometry
{
public:
  struct Params
  {
    std::vector<Vec2> offsets;         // module positions in the body frame (m)
    double wheel_radius = 0.05;        // m
    double encoder_period = 0.0;       // rad after which wheel joint positions wrap; 0 = never
    std::size_t velocity_window = 10;  // samples of the twist rolling mean
    // Weight of the IMU's yaw change against the wheels' one: 1 = the IMU alone gives the
    // heading change (WPILib's gyro odometry), 0 = wheels only.
    double imu_weight = 1.0;
  };

  // Throws std::invalid_argument naming the field when the parameters are unusable.
  explicit SwerveOdometry(const Params& params);

  // Wheel joint positions (rad) and pivot angles (rad), one per module, stamped at t (s);
  // imu_yaw (rad, any offset: only its changes are used) when fused. The first valid reading
  // only sets the reference; NaN/inf readings and non-increasing stamps are rejected (false).
  bool update(const std::vector<double>& wheel_positions, const std::vector<double>& pivot_angles, double t,
              std::optional<double> imu_yaw = std::nullopt);

  void resetEncoders();
  // Back to the origin with a fresh encoder reference and zero distance.
  void reset();

  const SwerveKinematics& kinematics() const { return kin_; }

private:
  Params params_;
  SwerveKinematics kin_;
  bool have_reference_ = false;
  std::vector<double> wheel_prev_, pivot_prev_;
  std::optional<double> imu_prev_;
  double t_prev_ = 0.0;
  std::vector<SwerveModulePosition> deltas_;  // scratch, avoids allocating per update
};

}  // namespace mybot_control
