#include "mybot_control/twist_mux.hpp"

#include <set>

namespace mybot_control
{

int TwistMux::addTopic(const MuxSource& source)
{
  topics_.push_back(source);
  topic_state_.emplace_back();
  return static_cast<int>(topics_.size()) - 1;
}

int TwistMux::addLock(const MuxSource& source)
{
  locks_.push_back(source);
  lock_state_.emplace_back();
  return static_cast<int>(locks_.size()) - 1;
}

std::string TwistMux::validate() const
{
  auto check = [](const std::vector<MuxSource>& list, const std::string& kind) -> std::string
  {
    std::set<std::string> names;
    for (std::size_t k = 0; k < list.size(); ++k)
    {
      const auto& s = list[k];
      const std::string where = kind + "[" + std::to_string(k) + "]";
      if (s.name.empty())
        return where + ".name must be a non-empty string";
      if (!names.insert(s.name).second)
        return where + ".name '" + s.name + "' is used twice";
      if (s.topic.empty())
        return where + ".topic must be a non-empty string (" + s.name + ")";
      if (!(s.timeout >= 0.0))
        return where + ".timeout must be >= 0 s (" + s.name + ")";
      if (s.priority < 0 || s.priority > 255)
        return where + ".priority must be in [0, 255] (" + s.name + ")";
    }
    return "";
  };
  if (topics_.empty())
    return "topics must list at least one input";
  std::string err = check(topics_, "topics");
  return err.empty() ? check(locks_, "locks") : err;
}

void TwistMux::topicReceived(int index, double t)
{
  topic_state_.at(index).received = true;
  topic_state_.at(index).stamp = t;
}

void TwistMux::lockReceived(int index, bool locked, double t)
{
  auto& s = lock_state_.at(index);
  s.received = true;
  s.stamp = t;
  s.value = locked;
}

int TwistMux::lockPriority(double t) const
{
  int priority = -1;
  for (std::size_t k = 0; k < locks_.size(); ++k)
  {
    const auto& s = lock_state_[k];
    const double timeout = locks_[k].timeout;
    // A lock with a timeout is a heartbeat: silence engages it (as upstream twist_mux).
    // A stamp in the future means time went backwards: as silent as a stale one.
    const bool silent = timeout > 0.0 && (!s.received || t - s.stamp > timeout || t < s.stamp);
    if (silent || (s.received && s.value))
      priority = std::max(priority, locks_[k].priority);
  }
  return priority;
}

bool TwistMux::topicAlive(int index, double t) const
{
  const auto& s = topic_state_[index];
  if (!s.received)
    return false;
  const double timeout = topics_[index].timeout;
  // A message stamped after t came before time went backwards (a simulation reset): not alive.
  return t >= s.stamp && (timeout <= 0.0 || t - s.stamp <= timeout);
}

int TwistMux::active(double t) const
{
  const int lock = lockPriority(t);
  int best = -1;
  for (std::size_t k = 0; k < topics_.size(); ++k)
  {
    if (topics_[k].priority <= lock || !topicAlive(static_cast<int>(k), t))
      continue;
    if (best < 0 || topics_[k].priority > topics_[best].priority)
      best = static_cast<int>(k);
  }
  return best;
}

bool TwistMux::shouldForward(int index, double t)
{
  if (active(t) != index)
    return false;
  last_forwarded_ = index;
  return true;
}

bool TwistMux::checkStop(double t)
{
  if (last_forwarded_ < 0)
    return false;
  // Only a source that lost control (timed out or locked) calls for a stop; one overridden by a
  // higher priority is replaced by that source's message, forwarded as it arrives.
  const bool locked = topics_[last_forwarded_].priority <= lockPriority(t);
  if (topicAlive(last_forwarded_, t) && !locked)
    return false;
  // If another source takes over, its next message is forwarded anyway; stopping in between
  // is the safe side.
  last_forwarded_ = -1;
  return true;
}

}  // namespace mybot_control
