#include <gtest/gtest.h>

#include "mybot_control/twist_mux.hpp"

using namespace mybot_control;

namespace
{
// twist_mux's example configuration.
TwistMux exampleMux()
{
  TwistMux mux;
  mux.addTopic({"navigation", "nav_vel", 0.5, 10});
  mux.addTopic({"joystick", "joy_vel", 0.5, 100});
  mux.addTopic({"keyboard", "key_vel", 0.5, 90});
  mux.addLock({"pause", "pause_navigation", 0.0, 100});
  mux.addLock({"loop_closure", "stop_closing_loop", 0.0, 200});
  mux.addLock({"joystick", "joy_priority", 0.0, 100});
  return mux;
}
enum
{
  NAV,
  JOY,
  KEY
};
enum
{
  PAUSE,
  LOOP,
  JOYLOCK
};
}  // namespace

TEST(TwistMux, ExampleConfigIsValid)
{
  EXPECT_EQ(exampleMux().validate(), "");
}

TEST(TwistMux, PriorityOverride)
{
  TwistMux mux = exampleMux();
  mux.topicReceived(NAV, 0.0);
  EXPECT_TRUE(mux.shouldForward(NAV, 0.0));
  mux.topicReceived(JOY, 0.1);
  EXPECT_TRUE(mux.shouldForward(JOY, 0.1));
  mux.topicReceived(NAV, 0.2);
  EXPECT_FALSE(mux.shouldForward(NAV, 0.2));  // joystick still alive and higher
  mux.topicReceived(KEY, 0.3);
  EXPECT_FALSE(mux.shouldForward(KEY, 0.3));
  EXPECT_EQ(mux.active(0.3), JOY);
}

TEST(TwistMux, TimeoutFallBackAndZeroOnce)
{
  TwistMux mux = exampleMux();
  mux.topicReceived(JOY, 0.0);
  EXPECT_TRUE(mux.shouldForward(JOY, 0.0));
  EXPECT_FALSE(mux.checkStop(0.4));
  EXPECT_TRUE(mux.checkStop(0.6));   // joystick silent > 0.5 s: stop once
  EXPECT_FALSE(mux.checkStop(0.7));  // ...and only once
  mux.topicReceived(NAV, 0.8);       // lower priority takes over
  EXPECT_TRUE(mux.shouldForward(NAV, 0.8));
  EXPECT_EQ(mux.active(0.8), NAV);
}

// reset_simulation sends the clock back: a source last heard "in the future" is not alive,
// so the mux neither keeps it active nor lets it block a lower priority.
TEST(TwistMux, TimeGoingBackwardsLeavesNoSourceAlive)
{
  TwistMux mux = exampleMux();
  mux.topicReceived(JOY, 100.0);
  EXPECT_EQ(mux.active(100.2), JOY);
  EXPECT_EQ(mux.active(0.1), -1);  // clock reset to 0.1 s
  mux.topicReceived(NAV, 0.2);
  EXPECT_TRUE(mux.shouldForward(NAV, 0.2));  // the joystick's stale stamp does not outrank it
}

// Navigation forwarded from 0, the joystick's one message at 0.1 outranks it; navigation is
// heard again at 0.5 (not forwarded: the joystick is alive until 0.6).
TwistMux navOverriddenByJoystick()
{
  TwistMux mux = exampleMux();
  mux.topicReceived(NAV, 0.0);
  mux.shouldForward(NAV, 0.0);
  mux.topicReceived(JOY, 0.1);
  mux.shouldForward(JOY, 0.1);
  mux.topicReceived(NAV, 0.5);
  EXPECT_FALSE(mux.checkStop(0.5));  // overridden, still alive: no stop
  EXPECT_FALSE(mux.shouldForward(NAV, 0.5));
  return mux;
}

TEST(TwistMux, ZeroWhenOverriddenSourceFallsBack)
{
  TwistMux mux = navOverriddenByJoystick();
  // Joystick times out at 0.6 while navigation is alive: stop, then navigation resumes.
  EXPECT_TRUE(mux.checkStop(0.65));
  mux.topicReceived(NAV, 0.7);
  EXPECT_TRUE(mux.shouldForward(NAV, 0.7));
}

// The joystick times out while navigation is alive, and navigation's next message comes before
// the check timer's tick (a busy machine): the stop is still there, before navigation resumes.
TEST(TwistMux, StopBeforeFallBackWhateverComesFirst)
{
  TwistMux mux = navOverriddenByJoystick();
  mux.topicReceived(NAV, 0.65);      // joystick silent since 0.1: lost at 0.6
  EXPECT_TRUE(mux.checkStop(0.65));  // what the node asks first, on this message
  EXPECT_TRUE(mux.shouldForward(NAV, 0.65));
  EXPECT_FALSE(mux.checkStop(0.66));  // the timer's tick after it: no second stop
}

TEST(TwistMux, NoStopWhenAHigherPriorityOverrides)
{
  TwistMux mux = exampleMux();
  mux.topicReceived(NAV, 0.0);
  mux.shouldForward(NAV, 0.0);
  mux.topicReceived(JOY, 0.1);
  EXPECT_FALSE(mux.checkStop(0.1));  // navigation is alive, only outranked
  EXPECT_TRUE(mux.shouldForward(JOY, 0.1));
}

TEST(TwistMux, LockBlocksLowerOrEqualPriority)
{
  TwistMux mux = exampleMux();
  mux.topicReceived(NAV, 0.0);
  mux.topicReceived(KEY, 0.0);
  mux.lockReceived(PAUSE, true, 0.0);
  EXPECT_EQ(mux.lockPriority(0.0), 100);
  EXPECT_FALSE(mux.shouldForward(NAV, 0.0));
  EXPECT_FALSE(mux.shouldForward(KEY, 0.0));
  mux.topicReceived(JOY, 0.1);
  EXPECT_FALSE(mux.shouldForward(JOY, 0.1));  // equal priority is blocked too
  mux.lockReceived(PAUSE, false, 0.2);
  mux.topicReceived(JOY, 0.2);
  EXPECT_TRUE(mux.shouldForward(JOY, 0.2));
  mux.lockReceived(LOOP, true, 0.3);
  EXPECT_TRUE(mux.checkStop(0.3));  // locking the active source stops the robot
}

TEST(TwistMux, HeartbeatLockEngagesOnSilence)
{
  TwistMux mux;
  mux.addTopic({"nav", "nav_vel", 0.5, 10});
  mux.addLock({"e_stop_heartbeat", "heartbeat", 1.0, 255});
  EXPECT_EQ(mux.lockPriority(0.0), 255);  // never heard from: locked
  mux.lockReceived(0, false, 0.0);
  EXPECT_EQ(mux.lockPriority(0.5), -1);
  EXPECT_EQ(mux.lockPriority(1.5), 255);  // silent longer than its timeout
}

TEST(TwistMux, ZeroTimeoutTopicNeverExpires)
{
  TwistMux mux;
  mux.addTopic({"nav", "nav_vel", 0.0, 10});
  mux.topicReceived(0, 0.0);
  EXPECT_EQ(mux.active(1000.0), 0);
}

TEST(TwistMux, ValidateNamesTheEntry)
{
  TwistMux dup;
  dup.addTopic({"a", "x", 0.5, 1});
  dup.addTopic({"a", "y", 0.5, 2});
  EXPECT_NE(dup.validate().find("topics[1].name 'a'"), std::string::npos);
  TwistMux neg;
  neg.addTopic({"a", "x", -1.0, 1});
  EXPECT_NE(neg.validate().find("topics[0].timeout"), std::string::npos);
  TwistMux prio;
  prio.addTopic({"a", "x", 0.5, 1});
  prio.addLock({"l", "y", 0.0, 300});
  EXPECT_NE(prio.validate().find("locks[0].priority"), std::string::npos);
  EXPECT_NE(TwistMux().validate().find("topics"), std::string::npos);
}
