// A multi-joint trajectory as joint_trajectory_controller follows it: knots (absolute times) joined
// per joint by the spline their given derivatives allow, as ros_controllers' QuinticSplineSegment
// does. No ROS.
//
// Between two knots a joint moves by
//   - a straight line where either knot gives only positions,
//   - a cubic where both give velocities (position and velocity match at both ends),
//   - a quintic where both also give accelerations (position, velocity and acceleration match).
// A new trajectory is spliced onto the current one at the moment it takes over: it starts from
// the current desired state (position, velocity, acceleration), so the setpoint never jumps.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

namespace mybot_ros_control
{

struct TrajectoryPoint
{
  double time = 0.0;  // s, absolute
  std::vector<double> positions;
  std::vector<double> velocities;     // empty: not given
  std::vector<double> accelerations;  // empty: not given
};

struct TrajectorySample
{
  std::vector<double> positions, velocities, accelerations;
};

class JointTrajectory
{
public:
  JointTrajectory() = default;
  // Standing at `positions` from time `t` on.
  static JointTrajectory hold(double t, const std::vector<double>& positions);

  // The desired state at t: before the first knot the first knot's; after the last knot its
  // positions at rest (velocity and acceleration 0: nothing moves past the end).
  TrajectorySample sample(double t) const;
  // Time of the last knot (where it comes to rest).
  double endTime() const { return knots_.empty() ? 0.0 : knots_.back().time; }
  size_t joints() const { return knots_.empty() ? 0 : knots_.front().positions.size(); }

  // Drops what lies wholly before `t`: samples at `t` and later stay the same.
  void forgetBefore(double t);
  // This trajectory until `t`, then from its state at `t` through the points after `t` (points
  // at or before `t` are dropped). For a joint with wrap[j] (continuous) every new position is
  // shifted by the whole turns that bring the first new point within half a turn of the state at
  // `t`, as upstream's wraparound offset. Points must have one position per joint and times
  // that increase (the controller checks both before).
  JointTrajectory splice(double t, const std::vector<TrajectoryPoint>& points, const std::vector<bool>& wrap) const;
  // From its state at `t` to rest over `duration` s (0: at once, where the setpoint is): what a
  // cancelled goal or an empty trajectory does (stop_trajectory_duration).
  JointTrajectory stopAt(double t, double duration) const;
  // From `state` (a joint's position, velocity and acceleration) at `t` to rest over `duration`
  // s: where the joints are when a goal aborts, rather than where they were meant to be.
  static JointTrajectory stopFrom(double t, const TrajectorySample& state, double duration);

private:
  struct Knot
  {
    double time = 0.0;
    std::vector<double> positions, velocities, accelerations;  // velocities/accelerations may be empty
  };
  using Poly = std::array<double, 6>;  // c0 + c1 tau + ... + c5 tau^5, tau = t - start knot's time
  void addKnot(const Knot& k);
  static TrajectorySample evaluate(const std::vector<Poly>& polys, double tau);

  std::vector<Knot> knots_;
  std::vector<std::vector<Poly>> segments_;  // segments_[i]: knots_[i] to knots_[i+1], one Poly a joint
};

}  // namespace mybot_ros_control
