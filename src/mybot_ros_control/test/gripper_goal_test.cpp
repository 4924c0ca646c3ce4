// GripperGoalMonitor: when a gripper goal is reached, and when it has stalled.
#include "mybot_ros_control/gripper_goal.h"

#include <gtest/gtest.h>

using mybot_ros_control::GripperGoalMonitor;
using mybot_ros_control::GripperGoalParams;
using mybot_ros_control::GripperGoalState;

namespace
{
GripperGoalParams params()
{
  GripperGoalParams p;
  p.goal_tolerance = 0.01;
  p.stall_velocity_threshold = 0.001;
  p.stall_timeout = 1.0;
  return p;
}
}  // namespace

TEST(GripperGoal, ReachedInsideTheToleranceOnEitherSide)
{
  GripperGoalMonitor m(params());
  m.start(0.0);
  EXPECT_EQ(m.update(0.1, 0.04, 0.02, 0.05), GripperGoalState::MOVING);
  EXPECT_EQ(m.update(0.2, 0.04, 0.0301, 0.05), GripperGoalState::REACHED);
  EXPECT_EQ(m.update(0.3, 0.04, 0.0499, -0.05), GripperGoalState::REACHED);
  // Exactly the tolerance away is not inside it (upstream's strict comparison).
  EXPECT_EQ(m.update(0.4, 0.04, 0.05, 0.0), GripperGoalState::MOVING);
}

TEST(GripperGoal, AJointAtRestShortOfItsTargetStallsAfterTheTimeout)
{
  GripperGoalMonitor m(params());
  m.start(2.0);
  // Closed on an object at 0.02 m, short of the 0.0 commanded: at rest from the start.
  EXPECT_EQ(m.update(2.5, 0.0, 0.02, 0.0), GripperGoalState::MOVING);
  EXPECT_EQ(m.update(3.0, 0.0, 0.02, 0.0), GripperGoalState::MOVING);  // 1.0 s: not longer than the timeout
  EXPECT_EQ(m.update(3.01, 0.0, 0.02, 0.0), GripperGoalState::STALLED);
}

TEST(GripperGoal, MovingRestartsTheStallClock)
{
  GripperGoalMonitor m(params());
  m.start(0.0);
  EXPECT_EQ(m.update(0.9, 0.0, 0.03, 0.0005), GripperGoalState::MOVING);  // creeping below the threshold
  EXPECT_EQ(m.update(1.0, 0.0, 0.03, -0.002), GripperGoalState::MOVING);  // moving: the clock restarts
  EXPECT_EQ(m.update(1.9, 0.0, 0.03, 0.0), GripperGoalState::MOVING);
  EXPECT_EQ(m.update(2.0, 0.0, 0.03, 0.0), GripperGoalState::MOVING);
  EXPECT_EQ(m.update(2.1, 0.0, 0.03, 0.0), GripperGoalState::STALLED);
}

TEST(GripperGoal, ANewGoalStartsItsOwnClock)
{
  GripperGoalMonitor m(params());
  m.start(0.0);
  EXPECT_EQ(m.update(5.0, 0.0, 0.03, 0.0), GripperGoalState::STALLED);
  m.start(5.0);
  EXPECT_EQ(m.update(5.5, 0.04, 0.03, 0.0), GripperGoalState::MOVING);
}

TEST(GripperGoal, TimeGoingBackRestartsTheClockThere)
{
  GripperGoalMonitor m(params());
  m.start(10.0);
  // A simulation reset: time is 0.2 s now. Not stalled for -9.8 s, nor at once.
  EXPECT_EQ(m.update(0.2, 0.0, 0.03, 0.0), GripperGoalState::MOVING);
  EXPECT_EQ(m.update(1.1, 0.0, 0.03, 0.0), GripperGoalState::MOVING);
  EXPECT_EQ(m.update(1.3, 0.0, 0.03, 0.0), GripperGoalState::STALLED);
}
