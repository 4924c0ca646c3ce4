#include "mybot_lockstep/ros/participant.h"

#include <ros/callback_queue.h>
#include <ros/poll_manager.h>
#include <ros/publication.h>
#include <ros/topic_manager.h>

#include <condition_variable>
#include <mutex>
#include <thread>

#include "mybot_lockstep/Ack.h"
#include "ros_links.h"

namespace mybot_lockstep
{

namespace
{
// roscpp hands a published message to its connections (and counts it) in its poll thread,
// not in publish(). To count everything published so far: wake the poll thread and wait
// until a listener of ours, which runs after roscpp's own queue processing, has run once.
void flushPublishQueues()
{
  static std::mutex mutex;
  static std::condition_variable cv;
  static std::uint64_t rounds = 0;
  static std::once_flag once;
  std::call_once(once,
                 []
                 {
                   ros::PollManager::instance()->addPollThreadListener(
                       []
                       {
                         std::lock_guard<std::mutex> lock(mutex);
                         ++rounds;
                         cv.notify_all();
                       });
                 });
  // Twice: the first round may be one that was already past roscpp's queue processing (our
  // listener waiting on this mutex) when we published.
  std::unique_lock<std::mutex> lock(mutex);
  for (int i = 0; i < 2; ++i)
  {
    const std::uint64_t start = rounds;
    ros::PollManager::instance()->getPollSet().signal();
    cv.wait_for(lock, std::chrono::milliseconds(200), [&] { return rounds > start; });
  }
}
}  // namespace

std::vector<Link> collectSent(bool flush)
{
  if (flush)
    flushPublishQueues();
  std::vector<Link> out;
  const std::string self = ros::this_node::getName();
  ros::V_string topics;
  ros::TopicManager::instance()->getAdvertisedTopics(topics);
  for (const std::string& topic : topics)
  {
    const ros::PublicationPtr pub = ros::TopicManager::instance()->lookupPublication(topic);
    if (!pub)
      continue;
    // getInfo: [connection id, destination caller id, ...] per connection;
    // getStats: [topic, [[connection id, message bytes, bytes, messages, 0], ...]] (the
    // messages column is the last but one; older roscpp had [id, bytes, messages, 0]).
    XmlRpc::XmlRpcValue info;
    info.setSize(0);
    pub->getInfo(info);
    XmlRpc::XmlRpcValue stats = pub->getStats();
    if (info.size() == 0 || stats.size() < 2)
      continue;
    XmlRpc::XmlRpcValue& conns = stats[1];
    for (int i = 0; i < info.size(); ++i)
    {
      const int id = info[i][0];
      for (int j = 0; j < conns.size(); ++j)
        if (static_cast<int>(conns[j][0]) == id)
        {
          Link l;
          l.topic = topic;
          l.source = self;
          l.destination = static_cast<std::string>(info[i][1]);
          const int messages = conns[j].size() >= 5 ? 3 : 2;
          l.count = static_cast<std::uint64_t>(static_cast<int>(conns[j][messages]));
          out.push_back(std::move(l));
          break;
        }
    }
  }
  return out;
}

bool lockstepRequested()
{
  bool sim = false, lockstep = false;
  ros::param::get("/use_sim_time", sim);
  ros::param::get("/lockstep", lockstep);
  return sim && lockstep;
}

// ros::Timer has no move: a "moved" one is a copy sharing the timer, which the source's
// stop() would stop. Hand it over and leave the source empty.
Timer::Timer(Timer&& o) noexcept : id_(o.id_), ros_timer_(o.ros_timer_)
{
  o.id_ = -1;
  o.ros_timer_ = ros::Timer();
}

Timer& Timer::operator=(Timer&& o) noexcept
{
  if (this != &o)
  {
    stop();
    id_ = o.id_;
    ros_timer_ = o.ros_timer_;
    o.id_ = -1;
    o.ros_timer_ = ros::Timer();
  }
  return *this;
}

Timer::~Timer()
{
  stop();
}

void Timer::stop()
{
  if (id_ >= 0)
    Participant::instance().removeTimer(id_);
  id_ = -1;
  ros_timer_.stop();
}

namespace
{
std::string g_opt_out;
}

void Participant::optOut(const std::string& why)
{
  g_opt_out = why.empty() ? "opted out" : why;
}

Participant& Participant::instance()
{
  // Never destroyed: nodes' Timers may outlive main's locals during static destruction.
  static Participant* p = new Participant();
  return *p;
}

Participant::Participant() : self_(ros::this_node::getName()), ledger_(self_)
{
  active_ = lockstepRequested();
  if (active_ && !g_opt_out.empty())
  {
    ROS_INFO("lockstep: %s does not take part (%s)", self_.c_str(), g_opt_out.c_str());
    active_ = false;
  }
  if (!active_)
    return;
  ros::param::param("/lockstep_forgive_after", forgive_after_, 2.0);
  tick_sub_ = nh_.subscribe("/lockstep/tick", 100, &Participant::onTick, this, ros::TransportHints().tcpNoDelay());
  ack_pub_ = nh_.advertise<Ack>("/lockstep/ack", 100);
  watchdog_ = nh_.createWallTimer(ros::WallDuration(0.2), &Participant::onWatchdog, this);
  ROS_INFO("lockstep: %s takes part (simulated time waits for it)", self_.c_str());
}

Participant::~Participant() = default;

Timer Participant::createTimer(const ros::NodeHandle& nh, double period,
                               const std::function<void(const ros::TimerEvent&)>& cb)
{
  Timer t;
  if (!active_)
  {
    t.ros_timer_ = nh.createTimer(ros::Duration(period), [cb](const ros::TimerEvent& e) { cb(e); });
    return t;
  }
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  auto last = std::make_shared<ros::TimerEvent>();
  t.id_ = timers_.add(ros::Duration(period).toNSec(), ros::Time::now().toNSec(),
                      [cb, last](std::int64_t due, std::int64_t now)
                      {
                        ros::TimerEvent e;
                        e.last_expected = last->current_expected;
                        e.last_real = last->current_real;
                        e.current_expected.fromNSec(due);
                        e.current_real.fromNSec(now);
                        *last = e;
                        cb(e);
                      });
  return t;
}

void Participant::removeTimer(int id)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  timers_.remove(id);
}

void Participant::onTick(const Tick::ConstPtr& tick)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  // The same period again: the simulator republishes the tick while it waits for nodes to
  // join, and our first Ack may have gone out before it had connected to us.
  if (pending_ && tick->seq <= pending_->seq)
    return;
  if (!pending_ && tick->seq <= last_ack_.seq)
  {
    if (tick->seq == last_ack_.seq)
    {
      last_ack_.sent.clear();  // fresh counts: the simulator checks the connections are open
      for (const Link& l : collectSent())
        last_ack_.sent.push_back(toMsg(l));
      ack_pub_.publish(last_ack_);
    }
    return;
  }
  pending_ = tick;
  pending_since_ = ros::WallTime::now();
  expected_.clear();
  for (const LinkCount& l : tick->expected)
    if (l.destination == self_)
      expected_.push_back(fromMsg(l));
  participants_.clear();
  participants_.insert(tick->participants.begin(), tick->participants.end());
  tryFinish();
}

namespace
{
class Pump : public ros::CallbackInterface
{
public:
  explicit Pump(std::function<void()> f) : f_(std::move(f)) {}
  CallResult call() override
  {
    f_();
    return Success;
  }

private:
  std::function<void()> f_;
};
}  // namespace

Participant::InboundQueue::InboundQueue(Participant& p) : pump_(boost::make_shared<Pump>([&p] { p.pump(); })) {}

Participant::InboundQueue::~InboundQueue()
{
  ros::getGlobalCallbackQueue()->removeByID(reinterpret_cast<uint64_t>(this));
}

void Participant::InboundQueue::addCallback(const ros::CallbackInterfacePtr& cb, uint64_t owner_id)
{
  queue_.addCallback(cb, owner_id);
  ros::getGlobalCallbackQueue()->addCallback(pump_, reinterpret_cast<uint64_t>(this));
}

void Participant::InboundQueue::removeByID(uint64_t owner_id)
{
  queue_.removeByID(owner_id);
}

// Runs from the global queue (the node's spinner), never from inside inbound_: the arrivals
// are recorded first, then the period is finished if they were all it waited for.
void Participant::pump()
{
  inbound_.callAvailable();
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  if (pending_)
    tryFinish();
}

void Participant::arrived(const std::string& topic, const std::string& source, std::function<void()> handle)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  inbox_[{topic, source}].push_back(std::move(handle));
  ledger_.received(topic, source);
  ++arrivals_;
}

// Everything this process does for one period, in an order that does not depend on when
// messages arrived: the waiting messages, the timers, then what those published to this
// process itself (intra-process deliveries pass through roscpp's queue), until nothing is left.
bool Participant::runPeriod()
{
  // A message from another process is handled in the period its publisher's Ack announced
  // it, never earlier (it may arrive early, as the scheduler pleases); one this process sent
  // itself comes from this very period's deterministic work and is handled at once.
  auto drainInbox = [this]
  {
    bool any = false;
    for (auto& [key, queue] : inbox_)
    {
      const bool own = key.second == self_;
      const bool participates = own || participants_.count(key.second) > 0;
      std::uint64_t& taken = taken_[key];
      std::uint64_t n = own ? queue.size() : ledger_.releasable(key.first, key.second, taken, expected_, participates);
      for (; n > 0 && !queue.empty(); --n)
      {
        std::function<void()> handle = std::move(queue.front());
        queue.pop_front();
        ++taken;
        handle();
        any = true;
      }
    }
    return any;
  };
  bool work = drainInbox();  // the period's measurements first, so the timers act on them
  work = timers_.run(pending_->stamp.toNSec()) > 0 || work;
  bool any = work;
  for (int round = 0; round < 100; ++round)
  {
    if (!work)
      return any;
    // What the callbacks above published to this process: a message published by reference
    // reaches even a subscriber in the same process through roscpp's poll thread, so let it
    // pass first; then our subscriptions' own queue hands it over (never nested: runPeriod is
    // called from the global queue's callbacks, pump() the only other caller of it).
    flushPublishQueues();
    const std::uint64_t before = arrivals_;
    inbound_.callAvailable();
    work = drainInbox() || arrivals_ != before;
    any = any || work;
  }
  ROS_WARN_THROTTLE(5.0, "lockstep: %s: messages to itself still arriving after 100 rounds in one period",
                    self_.c_str());
  return any;
}

void Participant::tryFinish()
{
  if (!pending_ || finishing_ || ledger_.firstUnmet(expected_))
    return;
  finishing_ = true;
  // /clock is handled by roscpp's own thread; the period's callbacks must see its time. After a
  // reset, exactly: the clock goes back with this tick, and a node that still read the old time
  // would take the new timeline's transforms for the old one's (tf2 refused them as data from
  // the past). Otherwise a clock ahead is fine: a node that joined while time ran handles the
  // ticks it missed.
  const bool went_back = !last_stamp_.isZero() && pending_->stamp < last_stamp_;
  last_stamp_ = pending_->stamp;
  const ros::WallTime give_up = ros::WallTime::now() + ros::WallDuration(forgive_after_);
  while (ros::Time::isSimTime() &&
         (ros::Time::now() < pending_->stamp || (went_back && ros::Time::now() > pending_->stamp)) &&
         ros::WallTime::now() < give_up && ros::ok())
    std::this_thread::sleep_for(std::chrono::microseconds(50));
  // An idle period published nothing: the counts need no wake-up of roscpp's poll thread.
  const bool work = runPeriod();
  Ack ack;
  ack.node = self_;
  ack.seq = pending_->seq;
  for (const Link& l : collectSent(work))
    ack.sent.push_back(toMsg(l));
  ack_pub_.publish(ack);
  last_ack_ = ack;
  pending_.reset();
  finishing_ = false;
}

void Participant::onWatchdog(const ros::WallTimerEvent&)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  if (!pending_ || (ros::WallTime::now() - pending_since_).toSec() < forgive_after_)
    return;
  if (const Link* l = ledger_.firstUnmet(expected_))
    ROS_WARN(
        "lockstep: %s gives up waiting for %s from %s (%llu of %llu handled after %.1f s); check the "
        "subscriber's queue size",
        self_.c_str(), l->topic.c_str(), l->source.c_str(),
        static_cast<unsigned long long>(ledger_.handled(l->topic, l->source)),
        static_cast<unsigned long long>(l->count), forgive_after_);
  ledger_.forgive(expected_);
  tryFinish();
}

}  // namespace mybot_lockstep
