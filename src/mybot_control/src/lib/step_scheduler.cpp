#include "mybot_control/step_scheduler.hpp"

#include <algorithm>

namespace mybot_control
{

bool StepScheduler::step(double t, double& dt)
{
  if (!started_ || t < last_step_)  // first step, or time went backwards (sim reset)
    dt = period_;
  else
    dt = std::min(t - last_step_, 5.0 * period_);  // bounded after long pauses
  started_ = true;
  last_step_ = t;
  return true;
}

bool StepScheduler::onEvent(double t, double& dt)
{
  if (started_ && t >= last_step_ && t - last_step_ < 0.25 * period_)
    return false;
  last_by_timer_ = false;
  return step(t, dt);
}

bool StepScheduler::onTick(double t, double& dt)
{
  // While events drive the loop the timer stays quiet; it takes over once they stop.
  if (started_ && !last_by_timer_ && t >= last_step_ && t - last_step_ < 1.25 * period_)
    return false;
  last_by_timer_ = true;
  return step(t, dt);
}

bool RateGate::due(double t)
{
  if (period_ <= 0.0)
    return true;
  if (started_ && t >= last_)
  {
    if (t < next_ - 0.1 * period_)
      return false;
    // On schedule, unless the stream paused for more than a period: then start over from t.
    next_ = t < next_ + period_ ? next_ + period_ : t + period_;
  }
  else  // first message, or time went backwards (simulation reset)
  {
    next_ = t + period_;
    started_ = true;
  }
  last_ = t;
  return true;
}

}  // namespace mybot_control
