// The watchdog ticks of a StepScheduler-driven node, one per period: from the measurements
// (joint_states) while they arrive, else from a timer. At 50 Hz a timer's thread wake-ups cost
// more CPU than the control step itself, so while measurements flow the timer is stopped and
// only a slow check runs; it restarts within one check period once they stop.
#pragma once

#include <ros/ros.h>

#include <functional>
#include <utility>

namespace mybot_control
{

class TickSource
{
public:
  TickSource() = default;

  void start(ros::NodeHandle& nh, double period, std::function<void(const ros::Time&)> tick)
  {
    period_ = period;
    tick_ = std::move(tick);
    timer_ = nh.createTimer(ros::Duration(period), [this](const ros::TimerEvent&) { tick_(ros::Time::now()); });
    check_ = nh.createTimer(ros::Duration(kCheckPeriod), [this](const ros::TimerEvent&) { check(); });
  }

  // A measurement arrived: tick now.
  void onMeasurement()
  {
    last_measurement_ = ros::Time::now();
    if (tick_)
      tick_(last_measurement_);
  }

private:
  static constexpr double kCheckPeriod = 0.2;  // s

  void check()
  {
    const ros::Time now = ros::Time::now();
    const bool flowing = !last_measurement_.isZero() && now >= last_measurement_ &&
                         (now - last_measurement_).toSec() < 2.0 * period_;
    if (flowing && timer_running_)
      timer_.stop();
    else if (!flowing && !timer_running_)
      timer_.start();
    timer_running_ = !flowing;
  }

  double period_ = 0.02;
  std::function<void(const ros::Time&)> tick_;
  ros::Timer timer_, check_;
  bool timer_running_ = true;
  ros::Time last_measurement_;
};

}  // namespace mybot_control
