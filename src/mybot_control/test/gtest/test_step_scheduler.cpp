#include <gtest/gtest.h>

#include "mybot_control/step_scheduler.hpp"

using mybot_control::StepScheduler;

TEST(StepScheduler, EventsDriveAndTimerTakesOverWhenTheyStop)
{
  StepScheduler s(0.02);
  double dt = 0.0;
  EXPECT_TRUE(s.onEvent(1.000, dt));
  EXPECT_DOUBLE_EQ(dt, 0.02);         // first step: nominal period
  EXPECT_FALSE(s.onTick(1.010, dt));  // events are driving
  EXPECT_TRUE(s.onEvent(1.020, dt));
  EXPECT_NEAR(dt, 0.02, 1e-12);
  EXPECT_FALSE(s.onTick(1.030, dt));
  EXPECT_FALSE(s.onTick(1.040, dt));  // 20 ms < 1.25 periods
  EXPECT_TRUE(s.onTick(1.050, dt));   // events stopped: watchdog steps
  EXPECT_NEAR(dt, 0.03, 1e-12);
  EXPECT_TRUE(s.onTick(1.070, dt));  // and keeps stepping every tick
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

namespace
{
// Messages from a source at `source_hz` with +/- jitter (deterministic), for `seconds`.
int passed(mybot_control::RateGate& g, double source_hz, double jitter, double seconds, double t0 = 0.0)
{
  int n = 0;
  const int count = static_cast<int>(seconds * source_hz);
  for (int i = 0; i < count; ++i)
  {
    const double t = t0 + i / source_hz + ((i * 7919) % 11 - 5) / 5.0 * jitter;
    n += g.due(t) ? 1 : 0;
  }
  return n;
}
}  // namespace

TEST(RateGate, SameRateSourceWithJitterKeepsEveryMessage)
{
  mybot_control::RateGate g(50.0);
  EXPECT_EQ(passed(g, 50.0, 0.0002, 10.0), 500);  // +/- 1 % of the period
}

TEST(RateGate, FasterSourcesAreThinnedToTheRate)
{
  mybot_control::RateGate g100(50.0), g60(50.0);
  EXPECT_EQ(passed(g100, 100.0, 0.0, 10.0), 500);
  EXPECT_NEAR(passed(g60, 60.0, 0.0, 10.0), 500, 1);
}

TEST(RateGate, SlowerSourcesPassAndTimeResetsRestart)
{
  mybot_control::RateGate g(50.0), off(0.0);
  EXPECT_EQ(passed(g, 20.0, 0.0, 10.0), 200);
  EXPECT_TRUE(g.due(1.0));  // sim time went back to 1 s
  EXPECT_FALSE(g.due(1.005));
  EXPECT_TRUE(g.due(1.02));
  EXPECT_EQ(passed(off, 100.0, 0.0, 1.0), 100);  // rate 0: every message
}
