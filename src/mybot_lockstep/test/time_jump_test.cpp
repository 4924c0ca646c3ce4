#include "mybot_lockstep/time_jump.h"

#include <gtest/gtest.h>

using mybot_lockstep::TimeJump;

TEST(TimeJump, TimeGoingForwardIsNoJumpAndNothingIsStale)
{
  TimeJump j;
  EXPECT_FALSE(j.wentBack(0.0));
  EXPECT_FALSE(j.wentBack(5.0));
  EXPECT_FALSE(j.wentBack(5.0));      // the same clock twice (several messages in one period)
  EXPECT_FALSE(j.stale(100.0, 5.0));  // a stamp far ahead is no jump's business
}

TEST(TimeJump, ASimulationResetIsOneJump)
{
  TimeJump j;
  j.wentBack(19.96);
  EXPECT_TRUE(j.wentBack(0.02));
  EXPECT_FALSE(j.wentBack(0.02));
  EXPECT_FALSE(j.wentBack(0.04));
  EXPECT_DOUBLE_EQ(j.guardUntil(), 9.99);
}

// The case of nav_reset: amcl's map -> odom, stamped at its last scan before the reset plus its
// transform_tolerance, reaches move_base after the clock went back to 0.02 s.
TEST(TimeJump, TransformsStampedBeforeTheResetAreStale)
{
  TimeJump j;
  j.wentBack(19.96);
  j.wentBack(0.02);
  EXPECT_TRUE(j.stale(19.96 + 0.1, 0.02));
  EXPECT_TRUE(j.stale(19.5, 0.04));
}

TEST(TimeJump, TransformsOfTheNewTimelineAreNot)
{
  TimeJump j;
  j.wentBack(19.96);
  j.wentBack(0.02);
  EXPECT_FALSE(j.stale(0.02, 0.02));
  EXPECT_FALSE(j.stale(0.02 + 0.5, 0.02));  // future-dated by a transform tolerance
  EXPECT_FALSE(j.stale(0.0, 0.02));         // a static transform's zero stamp
}

// nav_reset again, 6 s after the reset: amcl's map -> odom is stamped 0.19 s ahead of the clock
// (transform_tolerance), past the midpoint of the jump, and is no late arrival.
TEST(TimeJump, AFutureDatedTransformNearTheMidpointIsNot)
{
  TimeJump j;
  j.wentBack(12.04);
  j.wentBack(0.02);
  EXPECT_FALSE(j.stale(6.051, 5.86));
  EXPECT_TRUE(j.stale(12.225, 0.02));
}

TEST(TimeJump, OnceTheClockPassesTheMidpointNothingIsStale)
{
  TimeJump j;
  j.wentBack(19.96);
  j.wentBack(0.02);
  EXPECT_FALSE(j.stale(19.96, 9.99));
  EXPECT_FALSE(j.stale(12.0, 11.9));
}

TEST(TimeJump, ASecondJumpMovesTheMidpoint)
{
  TimeJump j;
  j.wentBack(20.0);
  j.wentBack(0.0);
  j.wentBack(4.0);
  EXPECT_TRUE(j.wentBack(2.0));  // a bag of 2 s played in a loop
  EXPECT_DOUBLE_EQ(j.guardUntil(), 3.0);
  EXPECT_TRUE(j.stale(3.9, 2.0));
  EXPECT_FALSE(j.stale(2.1, 2.0));
}
