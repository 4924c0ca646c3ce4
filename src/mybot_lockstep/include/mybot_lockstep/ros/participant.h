// Makes a roscpp node a lockstep participant: the simulator does not start period k+1 until
// this process has handled, for period k, every message sent to it on the topics it
// subscribed through subscribe() and has run its timers made with createTimer().
//
//   auto& ls = mybot_lockstep::Participant::instance();
//   sub_ = ls.subscribe<sensor_msgs::JointState>(nh, "joint_states", 10, [this](const auto& m) { ... });
//   timer_ = ls.createTimer(nh, 0.02, [this](const ros::TimerEvent& e) { ... });
//
// Lockstep is on when the parameters /use_sim_time and /lockstep are both true (the
// simulator's launch files set them); otherwise subscribe() is nh.subscribe() and
// createTimer() a ros::Timer, so the same node runs on a real robot unchanged. One
// participant per process: the nodes of a chain or nodelet-free group share it.
// The protocol is described in mybot_lockstep's README.
#pragma once

#include <ros/callback_queue.h>
#include <ros/ros.h>

#include <deque>
#include <functional>
#include <map>
#include <set>
#include <memory>
#include <mutex>
#include <string>
#include <type_traits>

#include "mybot_lockstep/Ack.h"
#include "mybot_lockstep/Tick.h"
#include "mybot_lockstep/barrier.h"

namespace mybot_lockstep
{

// The outgoing connections of this process and the messages written on each
// (roscpp's per-connection publisher statistics). flush: first let roscpp's poll thread hand
// over what was published so far (two wake-ups of that thread); without it, messages
// published moments ago may not be counted yet.
std::vector<Link> collectSent(bool flush = true);

// True when /use_sim_time and /lockstep are both set.
bool lockstepRequested();

class Participant;

// A periodic timer: tick-driven under lockstep, a ros::Timer otherwise. Stops when destroyed.
class Timer
{
public:
  Timer() = default;
  Timer(Timer&&) noexcept;
  Timer& operator=(Timer&&) noexcept;
  ~Timer();
  void stop();

private:
  friend class Participant;
  int id_ = -1;
  ros::Timer ros_timer_;
};

class Participant
{
public:
  static Participant& instance();
  bool active() const { return active_; }
  // Keeps this process out of lockstep (call before the first instance()): a process whose
  // callbacks do not all go through subscribe() and createTimer() (they would run on other
  // threads, beside the period's).
  static void optOut(const std::string& why);

  // Off lockstep the timer runs on `nh`'s callback queue, as a subscription through `nh` does:
  // in a nodelet manager that is the nodelet's own queue, so a node's timer and callbacks never
  // run at once on two threads.
  Timer createTimer(const ros::NodeHandle& nh, double period, const std::function<void(const ros::TimerEvent&)>& cb);

  // A service whose callback runs where this process's period work runs. Under lockstep that is
  // the global queue (the node's spinner): in a nodelet manager nh's queue is the nodelet's own,
  // served by a worker thread beside the period's callbacks, so a reset_odometry there could
  // race the odometry update it resets. Off lockstep it is nh.advertiseService.
  template <class Req, class Res>
  ros::ServiceServer advertiseService(ros::NodeHandle& nh, const std::string& service,
                                      const boost::function<bool(Req&, Res&)>& cb)
  {
    if (!active_)
      return nh.advertiseService(service, cb);
    ros::AdvertiseServiceOptions ops;
    ops.template init<Req, Res>(service, cb);
    ops.callback_queue = ros::getGlobalCallbackQueue();
    return nh.advertiseService(ops);
  }

  // Subscribes through lockstep. `cb` takes `const M&` or `const M::ConstPtr&`. Under
  // lockstep the message is not handed to `cb` when it arrives but when its period is
  // processed: once everything owed to this process for the period is in and /clock has
  // reached the period's time, callbacks run in a fixed order (by topic, then publisher,
  // then arrival), then the timers, then whatever those published to this process.
  template <class M, class F>
  ros::Subscriber subscribe(ros::NodeHandle& nh, const std::string& topic, uint32_t queue_size, F cb,
                            const ros::TransportHints& hints = ros::TransportHints())
  {
    auto call = [cb](const boost::shared_ptr<M const>& m)
    {
      if constexpr (std::is_invocable_v<F, const boost::shared_ptr<M const>&>)
        cb(m);
      else
        cb(*m);
    };
    if (!active_)
      return nh.subscribe<M>(topic, queue_size, boost::function<void(const boost::shared_ptr<M const>&)>(call),
                             ros::VoidConstPtr(), hints);
    const std::string resolved = nh.resolveName(topic);
    {
      std::lock_guard<std::recursive_mutex> lock(mutex_);
      ledger_.count(resolved);
    }
    ros::SubscribeOptions ops;
    ops.template initByFullCallbackType<const ros::MessageEvent<M const>&>(
        topic, queue_size,
        [this, resolved, call](const ros::MessageEvent<M const>& e)
        {
          const boost::shared_ptr<M const> m = e.getConstMessage();
          arrived(resolved, e.getPublisherName(), [call, m] { call(m); });
        });
    ops.transport_hints = hints;
    ops.callback_queue = &inbound_;
    return nh.subscribe(ops);
  }

  ~Participant();

private:
  friend class Timer;
  Participant();
  void onTick(const Tick::ConstPtr& tick);
  void arrived(const std::string& topic, const std::string& source, std::function<void()> handle);
  bool runPeriod();  // true if anything ran
  void tryFinish();
  void pump();
  void onWatchdog(const ros::WallTimerEvent&);
  void removeTimer(int id);

  // Our subscriptions' deliveries: their own queue, so a period can take what this process
  // published to itself without calling roscpp's global queue from inside one of its own
  // callbacks (a nested callAvailable there appends to the thread's batch while the outer
  // call holds an iterator into it: undefined behaviour, an occasional SIGSEGV). Each delivery
  // also queues a pump on the global queue, so the node's own spinner drains it in order.
  class InboundQueue : public ros::CallbackQueueInterface
  {
  public:
    explicit InboundQueue(Participant& p);
    ~InboundQueue() override;
    void addCallback(const ros::CallbackInterfacePtr& cb, uint64_t owner_id) override;
    void removeByID(uint64_t owner_id) override;
    void callAvailable() { queue_.callAvailable(); }

  private:
    ros::CallbackQueue queue_;
    ros::CallbackInterfacePtr pump_;
  };

  std::recursive_mutex mutex_;
  InboundQueue inbound_{*this};
  bool active_ = false, finishing_ = false;
  std::string self_;
  Ledger ledger_;
  TickTimers timers_;
  Tick::ConstPtr pending_;
  ros::Time last_stamp_;  // of the last period handled: a tick before it means time went back
  Ack last_ack_;
  // Messages waiting for their period, by (topic, publisher): a fixed order across connections.
  std::map<std::pair<std::string, std::string>, std::deque<std::function<void()>>> inbox_;
  std::map<std::pair<std::string, std::string>, std::uint64_t> taken_;
  std::set<std::string> participants_;
  std::uint64_t arrivals_ = 0;  // messages received through subscribe(), ever
  std::vector<Link> expected_;
  ros::WallTime pending_since_;
  double forgive_after_ = 2.0;
  ros::NodeHandle nh_;
  ros::Subscriber tick_sub_;
  ros::Publisher ack_pub_;
  ros::WallTimer watchdog_;
};

}  // namespace mybot_lockstep
