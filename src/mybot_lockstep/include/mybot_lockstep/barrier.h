// The bookkeeping of lockstep, without ROS: who takes part and what they acknowledged
// (Roster, the simulator's side), which messages a receiver has handled (Ledger, every
// side), and timers that fire on the periods' boundaries (TickTimers, the participants).
//
// Why counts: a participant's commands for period k and the Ack that says "done with k"
// travel on different TCP connections, so the Ack can overtake them. Each Ack therefore
// carries, per outgoing connection, how many messages have been written on it; the next
// Tick forwards these counts to the receivers, and a receiver acknowledges only once it
// has handled that many. Counts are per connection, from the moment it opened, on both
// ends, so a late joiner never waits for messages sent before it connected.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

namespace mybot_lockstep
{

// Messages sent on one connection since it opened.
struct Link
{
  std::string topic, source, destination;
  std::uint64_t count = 0;
};

// The simulator's view of the participants.
class Roster
{
public:
  // timeout: wall seconds a participant may take over one period before it is dropped.
  explicit Roster(double timeout) : timeout_(timeout) {}

  // An Ack for period `seq` from `node` arrived. Returns true if the node joined with it (it
  // was not a participant before).
  bool ack(const std::string& node, std::uint64_t seq, bool leaving, const std::vector<Link>& sent);
  // Period `seq` began at wall time `wall`: from now on every participant owes an Ack for it.
  void begin(std::uint64_t seq, double wall);
  // True when every participant has acknowledged the current period. A participant silent
  // for longer than the timeout since the period began is dropped and its name is added to
  // `dropped`.
  bool complete(double wall, std::vector<std::string>* dropped);
  // Participants that still owe an Ack for the current period.
  std::vector<std::string> waiting() const;
  // Removes a participant (its connection closed). Returns false if it was not one.
  bool remove(const std::string& node);
  bool has(const std::string& node) const { return members_.count(node) > 0; }
  std::size_t size() const { return members_.size(); }
  std::vector<std::string> names() const;
  std::uint64_t period() const { return seq_; }

  // What every receiver is owed: the participants' latest sent counts, plus `own` (the
  // coordinator's own connections), keeping links whose destination is a participant.
  std::vector<Link> expectations(const std::vector<Link>& own) const;
  // Every participant's connections as of its last Ack.
  std::vector<Link> sentLinks() const;
  // What the coordinator itself (`self`) is owed by the participants.
  std::vector<Link> owedTo(const std::string& self) const;

private:
  struct Member
  {
    std::uint64_t acked = 0;
    std::vector<Link> sent;
  };
  double timeout_;
  std::uint64_t seq_ = 0;
  double began_ = 0.0;
  std::map<std::string, Member> members_;
};

// What a receiver (`self`) has handled, per (topic, source), on the topics it counts.
class Ledger
{
public:
  explicit Ledger(std::string self = "") : self_(std::move(self)) {}
  void setSelf(const std::string& self) { self_ = self; }
  const std::string& self() const { return self_; }

  // Declares a subscription to `topic` (resolved name) as counted: expectations on other
  // topics are ignored. Two subscriptions to one topic in one process share a connection, so
  // each message sent on it is received (and handled) once per subscription.
  void count(const std::string& topic) { ++counted_[topic]; }
  // One message on `topic` from `source` has been handled.
  void received(const std::string& topic, const std::string& source);
  // The first expectation addressed to self on a counted topic that is not met, or nullptr.
  const Link* firstUnmet(const std::vector<Link>& expected) const;
  // Gives up on the messages `expected` says are missing (lost for good, e.g. dropped from
  // a full queue): later checks expect only what is sent after them.
  void forgive(const std::vector<Link>& expected);
  std::uint64_t handled(const std::string& topic, const std::string& source) const;
  // How many of the messages received on (topic, source) may be handled by now, given the
  // counts `expected` (the latest tick's) and that `taken` have been handled already.
  // A source that is not a participant is never waited for: all its messages may be handled.
  std::uint64_t releasable(const std::string& topic, const std::string& source, std::uint64_t taken,
                           const std::vector<Link>& expected, bool source_participates) const;

private:
  std::string self_;
  std::uint64_t owed(const Link& l) const;  // l.count times the subscriptions to l.topic
  std::map<std::string, std::uint64_t> counted_;
  std::map<std::pair<std::string, std::string>, std::uint64_t> handled_;  // (topic, source)
  std::map<std::pair<std::string, std::string>, std::uint64_t> forgiven_;
};

// Periodic callbacks driven by the ticks. A timer of period p fires at the whole multiples
// of p (in nanoseconds of sim time), once in the first tick that reaches each, so its phase
// does not depend on when its node started. A timer that falls more than a period behind
// (a period shorter than the lockstep period) fires once and skips to the next multiple
// after now, as roscpp's timers skip after a slow callback. Time going backwards (a
// simulation reset) realigns every timer to the new time.
class TickTimers
{
public:
  using Callback = std::function<void(std::int64_t expected_ns, std::int64_t now_ns)>;

  // Returns an id for remove(). `now_ns` is the sim time at creation.
  int add(std::int64_t period_ns, std::int64_t now_ns, Callback cb);
  void remove(int id);
  // Fires every timer due at or before now_ns, earliest due first (ties: creation order).
  // Returns how many fired.
  int run(std::int64_t now_ns);
  std::size_t size() const { return timers_.size(); }

private:
  struct Entry
  {
    std::int64_t period, next;
    Callback cb;
  };
  static std::int64_t nextMultiple(std::int64_t period, std::int64_t t) { return (t / period + 1) * period; }
  std::map<int, Entry> timers_;
  int next_id_ = 0;
  std::int64_t last_now_ = 0;
};

}  // namespace mybot_lockstep
