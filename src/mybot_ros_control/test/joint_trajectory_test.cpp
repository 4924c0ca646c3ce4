// The trajectory joint_trajectory_controller follows: its splines meet their knots, a spliced
// trajectory takes over without a jump, and a stop comes to rest.
#include "mybot_ros_control/joint_trajectory.h"

#include <gtest/gtest.h>

#include <cmath>

using mybot_ros_control::JointTrajectory;
using mybot_ros_control::TrajectoryPoint;

namespace
{
const std::vector<bool> kNoWrap{false, false};

// From rest at (0, 1) at t = 10 through the given points.
JointTrajectory from(const std::vector<TrajectoryPoint>& points)
{
  return JointTrajectory::hold(10.0, {0.0, 1.0}).splice(10.0, points, kNoWrap);
}
}  // namespace

TEST(JointTrajectory, PositionsOnlyMoveInStraightLinesAndRestAtTheEnd)
{
  const JointTrajectory tr = from({{11.0, {1.0, 1.0}, {}, {}}, {13.0, {3.0, -1.0}, {}, {}}});
  EXPECT_NEAR(tr.sample(10.5).positions[0], 0.5, 1e-12);
  EXPECT_NEAR(tr.sample(12.0).positions[0], 2.0, 1e-12);
  EXPECT_NEAR(tr.sample(12.0).positions[1], 0.0, 1e-12);
  EXPECT_NEAR(tr.sample(12.0).velocities[0], 1.0, 1e-12);
  EXPECT_NEAR(tr.sample(12.0).velocities[1], -1.0, 1e-12);
  EXPECT_DOUBLE_EQ(tr.endTime(), 13.0);
  for (double t : {13.0, 20.0})
  {
    EXPECT_DOUBLE_EQ(tr.sample(t).positions[0], 3.0);
    EXPECT_DOUBLE_EQ(tr.sample(t).velocities[0], 0.0);
  }
  // Before the first knot: where it starts.
  EXPECT_DOUBLE_EQ(tr.sample(5.0).positions[1], 1.0);
}

TEST(JointTrajectory, VelocitiesGiveACubicThatMeetsThemAtEveryKnot)
{
  const JointTrajectory tr = from({{11.0, {1.0, 2.0}, {0.5, 1.0}, {}}, {12.5, {2.0, 2.5}, {0.0, 0.0}, {}}});
  for (const auto& [t, p, v] : {std::tuple<double, double, double>{11.0, 1.0, 0.5}, {12.5, 2.0, 0.0}})
  {
    // Approached from inside its segment: the knot's position and velocity.
    const auto s = tr.sample(t - 1e-9);
    EXPECT_NEAR(s.positions[0], p, 1e-6);
    EXPECT_NEAR(s.velocities[0], v, 1e-6);
  }
  // The velocity is continuous across the knot at 11 s.
  EXPECT_NEAR(tr.sample(11.0 - 1e-7).velocities[1], tr.sample(11.0 + 1e-7).velocities[1], 1e-5);
}

TEST(JointTrajectory, AccelerationsGiveAQuinticThatMeetsAllThree)
{
  const JointTrajectory tr = from({{12.0, {2.0, 0.0}, {1.0, -0.5}, {0.3, 0.2}}});
  const auto s = tr.sample(12.0 - 1e-9);
  EXPECT_NEAR(s.positions[0], 2.0, 1e-6);
  EXPECT_NEAR(s.velocities[0], 1.0, 1e-6);
  EXPECT_NEAR(s.accelerations[0], 0.3, 1e-5);
  EXPECT_NEAR(s.accelerations[1], 0.2, 1e-5);
  // Starting from rest: the hold gives velocity and acceleration 0.
  EXPECT_NEAR(tr.sample(10.0).velocities[0], 0.0, 1e-12);
  EXPECT_NEAR(tr.sample(10.0).accelerations[0], 0.0, 1e-12);
}

TEST(JointTrajectory, ASplicedTrajectoryTakesOverWithoutAJumpAndDropsPastPoints)
{
  const JointTrajectory first = from({{12.0, {2.0, 3.0}, {0.0, 0.0}, {}}});
  const auto at = first.sample(11.0);
  ASSERT_GT(at.velocities[0], 0.1);
  // The new trajectory's first point lies in the past: dropped.
  const JointTrajectory second =
      first.splice(11.0, {{10.5, {9.0, 9.0}, {}, {}}, {13.0, {-1.0, 0.0}, {0.0, 0.0}, {}}}, kNoWrap);
  const auto s = second.sample(11.0);
  EXPECT_DOUBLE_EQ(s.positions[0], at.positions[0]);
  EXPECT_DOUBLE_EQ(s.velocities[0], at.velocities[0]);
  EXPECT_NEAR(second.sample(13.0).positions[0], -1.0, 1e-12);
  // Before the splice the old one still holds (its samples are the old trajectory's from t on).
  EXPECT_DOUBLE_EQ(second.endTime(), 13.0);
}

TEST(JointTrajectory, AContinuousJointTakesTheShortWayRound)
{
  const JointTrajectory at = JointTrajectory::hold(0.0, {3.0, 3.0});
  // Both to -3.0 rad: the continuous one by +0.28 rad through pi, the other by -6 rad.
  const JointTrajectory tr = at.splice(0.0, {{1.0, {-3.0, -3.0}, {}, {}}}, {true, false});
  EXPECT_NEAR(tr.sample(1.0).positions[0], 2.0 * M_PI - 3.0, 1e-12);
  EXPECT_NEAR(tr.sample(1.0).positions[1], -3.0, 1e-12);
}

TEST(JointTrajectory, AStopComesToRestOverItsDurationOrAtOnce)
{
  const JointTrajectory moving = from({{12.0, {2.0, 1.0}, {}, {}}});  // 1 rad/s on the first joint
  const JointTrajectory now = moving.stopAt(11.0, 0.0);
  EXPECT_DOUBLE_EQ(now.sample(11.5).positions[0], moving.sample(11.0).positions[0]);
  EXPECT_DOUBLE_EQ(now.sample(11.5).velocities[0], 0.0);
  const JointTrajectory soft = moving.stopAt(11.0, 0.4);
  EXPECT_NEAR(soft.sample(11.0).velocities[0], 1.0, 1e-12);      // from the speed it had
  EXPECT_NEAR(soft.sample(11.4).positions[0], 1.0 + 0.2, 1e-9);  // half its speed times 0.4 s further
  EXPECT_DOUBLE_EQ(soft.sample(12.0).velocities[0], 0.0);
  for (double t = 11.0; t < 11.4; t += 0.01)
    EXPECT_GE(soft.sample(t).velocities[0], -1e-9) << "it never turns back, at " << t;
}

TEST(JointTrajectory, ATrajectoryStartingLaterLeavesTheCurrentOneUntilThen)
{
  // Moving 0 -> 2 over 10..12 s; a new trajectory takes over at 11.5 s.
  const JointTrajectory first = from({{12.0, {2.0, 1.0}, {0.0, 0.0}, {}}});
  JointTrajectory second = first.splice(11.5, {{13.0, {0.0, 1.0}, {}, {}}}, kNoWrap);
  for (double t : {10.0, 10.7, 11.2, 11.499})
  {
    EXPECT_NEAR(second.sample(t).positions[0], first.sample(t).positions[0], 1e-12) << t;
    EXPECT_NEAR(second.sample(t).velocities[0], first.sample(t).velocities[0], 1e-12) << t;
  }
  // At 11.5 s it takes over where the first one is (the new point gives no velocity: a straight
  // line from there on, as upstream).
  EXPECT_NEAR(second.sample(11.5).positions[0], first.sample(11.5).positions[0], 1e-12);
  EXPECT_NEAR(second.sample(13.0).positions[0], 0.0, 1e-12);
  // Forgetting what lies before 11 s changes nothing from 11 s on.
  const JointTrajectory kept = second;
  second.forgetBefore(11.0);
  for (double t : {11.0, 11.3, 11.5, 12.2, 14.0})
    EXPECT_DOUBLE_EQ(second.sample(t).positions[0], kept.sample(t).positions[0]) << t;
}
