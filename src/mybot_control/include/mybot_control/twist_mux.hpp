// Source selection of a twist multiplexer (twist_mux semantics): the highest-priority input
// that has not timed out wins, unless a lock of equal or higher priority is engaged. A lock
// is engaged while its last Bool was true, or (timeout > 0) while it is silent longer than
// its timeout. Unlike upstream, losing the active source produces a one-off "stop" event.
#pragma once

#include <string>
#include <vector>

namespace mybot_control
{

struct MuxSource
{
  std::string name;
  std::string topic;
  double timeout = 0.5;  // s; for topics 0 = never times out
  int priority = 0;
};

class TwistMux
{
public:
  // Returns the index. Validation (unique names, timeout >= 0, priority in [0, 255]) is
  // done by validate() so the caller can report all problems with their names.
  int addTopic(const MuxSource& source);
  int addLock(const MuxSource& source);
  std::string validate() const;

  void topicReceived(int index, double t);
  void lockReceived(int index, bool locked, double t);

  // Highest lock priority engaged at time t, -1 when none.
  int lockPriority(double t) const;
  // Index of the active topic at time t, -1 when none.
  int active(double t) const;
  // Whether a message that just arrived on `index` at t should be forwarded.
  bool shouldForward(int index, double t);
  // Call periodically, and before shouldForward on each message: true exactly once when the
  // source last forwarded is lost (timeout or lock), i.e. when the output should be zeroed.
  // Checked on each message too, so that the stop between a source that timed out and the one
  // that takes over does not depend on whether the timer or the message comes first.
  bool checkStop(double t);

  const std::vector<MuxSource>& topics() const { return topics_; }
  const std::vector<MuxSource>& locks() const { return locks_; }
  int lastForwarded() const { return last_forwarded_; }

private:
  struct State
  {
    bool received = false;
    double stamp = 0.0;
    bool value = false;
  };
  bool topicAlive(int index, double t) const;

  std::vector<MuxSource> topics_, locks_;
  std::vector<State> topic_state_, lock_state_;
  int last_forwarded_ = -1;  // -1: output currently idle/zeroed
};

}  // namespace mybot_control
