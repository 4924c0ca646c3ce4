// Swerve drive kinematics for N modules, with WPILib's semantics (SwerveDriveKinematics,
// SwerveModuleState, ChassisSpeeds): inverse kinematics about a selectable centre of
// rotation, least-squares forward kinematics (pseudo-inverse), module-state optimisation,
// cosine scaling, proportional desaturation, heading hold at zero speed, twist
// discretisation and field-relative commands. No ROS types.
#pragma once

#include <Eigen/Dense>

#include <string>
#include <vector>

#include "mybot_control/kinematics.hpp"

namespace mybot_control
{

struct Vec2
{
  double x = 0.0;
  double y = 0.0;
};

// One module's command or measurement: wheel rim speed (m/s, signed) and pivot angle (rad,
// 0 = wheel rolling along +x of the body, counter-clockwise positive).
struct SwerveModuleState
{
  double speed = 0.0;
  double angle = 0.0;
};

// One module's odometry reading: distance rolled by the wheel rim (m) and pivot angle (rad).
struct SwerveModulePosition
{
  double distance = 0.0;
  double angle = 0.0;
};

// Never turn a module more than 90 degrees: if the desired angle is more than 90 degrees from
// the current one, aim the other way and reverse the wheel. The returned angle is the one
// closest to current_angle among the equivalent ones, wrapped to (-pi, pi].
SwerveModuleState optimizeModuleState(const SwerveModuleState& desired, double current_angle);

// Scale the speed by cos(angle error): a module still turning pushes only with the component
// of its speed along the wanted direction (WPILib's cosineScale). Never reverses the wheel
// (errors are within 90 degrees after optimisation; beyond that the speed is 0).
SwerveModuleState cosineScale(const SwerveModuleState& desired, double current_angle);

// Scale all module speeds by one factor so that none exceeds max_speed (direction of travel
// and the ratio of translation to rotation kept). Returns the factor; max_speed <= 0 disables.
double desaturateModuleSpeeds(std::vector<SwerveModuleState>& states, double max_speed);

// The twist that, held for dt, moves the robot by the pose a *straight* (vx dt, vy dt) step
// combined with a (wz dt) turn would give: commanding it instead of the raw twist removes the
// skew of translating while rotating (WPILib ChassisSpeeds::Discretize). dt <= 0: unchanged.
Twist2D discretize(const Twist2D& twist, double dt);

// Field-relative (vx, vy in the odometry/world frame) -> body twist, given the robot yaw.
Twist2D fromFieldRelative(const Twist2D& field, double yaw);

class SwerveKinematics
{
public:
  // Throws std::invalid_argument with validate()'s message when the offsets are unusable.
  explicit SwerveKinematics(const std::vector<Vec2>& offsets);

  // Empty when the module offsets (m, body frame) admit forward kinematics: at least two
  // modules, all finite, no two at the same place (min_separation m).
  static std::string validate(const std::vector<Vec2>& offsets, double min_separation = 1e-3);

  std::size_t size() const { return offsets_.size(); }
  const std::vector<Vec2>& offsets() const { return offsets_; }

  // Body twist -> module states, rotating about `center` (body frame). A module with no speed
  // keeps its last heading (so a stopped robot does not snap its wheels to 0 rad).
  std::vector<SwerveModuleState> toModuleStates(const Twist2D& twist, const Vec2& center = Vec2{});
  // Headings a zero command holds (e.g. the measured angles at start-up).
  void resetHeadings(const std::vector<double>& angles);
  const std::vector<double>& headings() const { return headings_; }

  // Least-squares body twist from module states (size() of them).
  Twist2D toTwist(const std::vector<SwerveModuleState>& states) const;
  // Least-squares body displacement (vx, vy, wz = dx, dy, dtheta) from module distance deltas.
  Twist2D toTwist(const std::vector<SwerveModulePosition>& deltas) const;

private:
  std::vector<Vec2> offsets_;
  std::vector<double> headings_;
  Eigen::Matrix<double, 3, Eigen::Dynamic> forward_;  // pseudo-inverse of the 2N x 3 matrix
};

}  // namespace mybot_control
