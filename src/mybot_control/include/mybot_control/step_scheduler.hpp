// When to run a control step: immediately when a new command arrives (no added latency),
// and from a periodic timer only as a watchdog while commands are not arriving (timeouts,
// ramps to zero). Avoids both the up-to-one-period delay of a purely timer-driven loop and
// near-zero dt steps from bursts of commands.
#pragma once

namespace mybot_control
{

class StepScheduler
{
public:
  explicit StepScheduler(double period) : period_(period) {}

  // A command arrived at t. Returns true (and dt) if a step should run now; bursts faster
  // than a quarter period only update the command, the next step uses it.
  bool onEvent(double t, double& dt);
  // The timer fired at t. Returns true (and dt) if the watchdog should step.
  bool onTick(double t, double& dt);
  void reset() { started_ = false; }
  double period() const { return period_; }

private:
  bool step(double t, double& dt);

  double period_;
  bool started_ = false;
  bool last_by_timer_ = true;
  double last_step_ = 0.0;
};

// Thins a stream of stamped messages to `rate` per second (publish_rate of the odometry nodes).
// Due times advance by whole periods and a message up to a tenth of a period early counts as
// on time: a plain "at least one period since the last" gate turns a 50 Hz source with a
// little jitter into about 33 Hz, dropping every message that comes a microsecond early.
class RateGate
{
public:
  explicit RateGate(double rate) : period_(rate > 0.0 ? 1.0 / rate : 0.0) {}

  // True if a message stamped t should go out.
  bool due(double t);

private:
  double period_;
  bool started_ = false;
  double last_ = 0.0, next_ = 0.0;
};

}  // namespace mybot_control
