#include <gtest/gtest.h>

#include "mybot_control/step_scheduler.hpp"

using mybot_control::StepScheduler;

TEST(StepScheduler, EventsDriveAndTimerTakesOverWhenTheyStop)
{
  StepScheduler s(0.02);
  double dt = 0.0;
  EXPECT_TRUE(s.onEvent(1.000, dt));
  EXPECT_DOUBLE_EQ(dt, 0.02);  // first step: nominal period
  EXPECT_FALSE(s.onTick(1.010, dt));  // events are driving
  EXPECT_TRUE(s.onEvent(1.020, dt));
  EXPECT_NEAR(dt, 0.02, 1e-12);
  EXPECT_FALSE(s.onTick(1.030, dt));
  EXPECT_FALSE(s.onTick(1.040, dt));  // 20 ms < 1.25 periods
  EXPECT_TRUE(s.onTick(1.050, dt));   // events stopped: watchdog steps
  EXPECT_NEAR(dt, 0.03, 1e-12);
  EXPECT_TRUE(s.onTick(1.070, dt));   // and keeps stepping every tick
  EXPECT_NEAR(dt, 0.02, 1e-12);
}

TEST(StepScheduler, BurstsDoNotStepWithTinyDt)
{
  StepScheduler s(0.02);
  double dt = 0.0;
  EXPECT_TRUE(s.onEvent(0.0, dt));
  EXPECT_FALSE(s.onEvent(0.001, dt));
  EXPECT_TRUE(s.onEvent(0.006, dt));
  EXPECT_NEAR(dt, 0.006, 1e-12);
}

TEST(StepScheduler, TimeJumpsAreBounded)
{
  StepScheduler s(0.02);
  double dt = 0.0;
  s.onTick(10.0, dt);
  EXPECT_TRUE(s.onTick(5.0, dt));  // backwards: nominal period
  EXPECT_DOUBLE_EQ(dt, 0.02);
  EXPECT_TRUE(s.onTick(50.0, dt));  // long pause: at most 5 periods
  EXPECT_DOUBLE_EQ(dt, 0.1);
}
