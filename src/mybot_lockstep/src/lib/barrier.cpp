#include "mybot_lockstep/barrier.h"

#include <algorithm>

namespace mybot_lockstep
{

bool Roster::ack(const std::string& node, std::uint64_t seq, bool leaving, const std::vector<Link>& sent)
{
  if (leaving)
  {
    members_.erase(node);
    return false;
  }
  auto it = members_.find(node);
  const bool joined = it == members_.end();
  Member& m = members_[node];
  // A joiner counts as done with everything up to the current period: it starts owing Acks
  // from the next one, so joining never stalls the period already under way.
  m.acked = joined ? std::max(seq, seq_) : std::max(m.acked, seq);
  m.sent = sent;
  return joined;
}

void Roster::begin(std::uint64_t seq, double wall)
{
  seq_ = seq;
  began_ = wall;
}

bool Roster::complete(double wall, std::vector<std::string>* dropped)
{
  bool done = true;
  for (auto it = members_.begin(); it != members_.end();)
  {
    if (it->second.acked >= seq_)
    {
      ++it;
      continue;
    }
    if (wall - began_ > timeout_)
    {
      if (dropped)
        dropped->push_back(it->first);
      it = members_.erase(it);
      continue;
    }
    done = false;
    ++it;
  }
  return done;
}

std::vector<std::string> Roster::waiting() const
{
  std::vector<std::string> out;
  for (const auto& [name, m] : members_)
    if (m.acked < seq_)
      out.push_back(name);
  return out;
}

bool Roster::remove(const std::string& node)
{
  return members_.erase(node) > 0;
}

std::vector<std::string> Roster::names() const
{
  std::vector<std::string> out;
  for (const auto& kv : members_)
    out.push_back(kv.first);
  return out;
}

std::vector<Link> Roster::expectations(const std::vector<Link>& own) const
{
  std::vector<Link> out;
  auto keep = [&](const Link& l)
  {
    if (members_.count(l.destination))
      out.push_back(l);
  };
  for (const Link& l : own)
    keep(l);
  for (const auto& kv : members_)
    for (const Link& l : kv.second.sent)
      keep(l);
  return out;
}

std::vector<Link> Roster::sentLinks() const
{
  std::vector<Link> out;
  for (const auto& kv : members_)
    out.insert(out.end(), kv.second.sent.begin(), kv.second.sent.end());
  return out;
}

std::vector<Link> Roster::owedTo(const std::string& self) const
{
  std::vector<Link> out;
  for (const auto& kv : members_)
    for (const Link& l : kv.second.sent)
      if (l.destination == self)
        out.push_back(l);
  return out;
}

void Ledger::received(const std::string& topic, const std::string& source)
{
  ++handled_[{topic, source}];
}

std::uint64_t Ledger::handled(const std::string& topic, const std::string& source) const
{
  const auto key = std::make_pair(topic, source);
  const auto h = handled_.find(key);
  const auto f = forgiven_.find(key);
  return (h == handled_.end() ? 0 : h->second) + (f == forgiven_.end() ? 0 : f->second);
}

std::uint64_t Ledger::owed(const Link& l) const
{
  if (l.destination != self_)
    return 0;
  const auto c = counted_.find(l.topic);
  return c == counted_.end() ? 0 : l.count * c->second;
}

const Link* Ledger::firstUnmet(const std::vector<Link>& expected) const
{
  for (const Link& l : expected)
    if (handled(l.topic, l.source) < owed(l))
      return &l;
  return nullptr;
}

std::uint64_t Ledger::releasable(const std::string& topic, const std::string& source, std::uint64_t taken,
                                 const std::vector<Link>& expected, bool source_participates) const
{
  const auto h = handled_.find({topic, source});
  const std::uint64_t received = h == handled_.end() ? 0 : h->second;
  const std::uint64_t waiting = received - std::min(received, taken);
  if (!source_participates)
    return waiting;
  std::uint64_t count = 0;
  bool found = false;
  for (const Link& l : expected)
    if (l.destination == self_ && l.topic == topic && l.source == source)
    {
      count = std::max(count, owed(l));
      found = true;
    }
  if (!found)
    return 0;  // sent after its publisher's last Ack: next period
  const auto f = forgiven_.find({topic, source});
  const std::uint64_t forgiven = f == forgiven_.end() ? 0 : f->second;
  // Message number taken+1 (in arrival order) is due once count covers it; forgiven ones
  // never arrived, so they shift the arrivals down.
  const std::uint64_t due = count > forgiven ? count - forgiven : 0;
  return due > taken ? std::min(waiting, due - taken) : 0;
}

void Ledger::forgive(const std::vector<Link>& expected)
{
  for (const Link& l : expected)
  {
    const std::uint64_t have = handled(l.topic, l.source), want = owed(l);
    if (have < want)
      forgiven_[{l.topic, l.source}] += want - have;
  }
}

int TickTimers::add(std::int64_t period_ns, std::int64_t now_ns, Callback cb)
{
  if (period_ns <= 0)
    period_ns = 1;
  const int id = next_id_++;
  timers_[id] = Entry{period_ns, nextMultiple(period_ns, now_ns), std::move(cb)};
  return id;
}

void TickTimers::remove(int id)
{
  timers_.erase(id);
}

int TickTimers::run(std::int64_t now_ns)
{
  int count = 0;
  if (now_ns < last_now_)  // time went backwards: every timer starts over from now
    for (auto& kv : timers_)
      kv.second.next = nextMultiple(kv.second.period, now_ns);
  last_now_ = now_ns;
  // Earliest due first; a callback may add or remove timers, so pick one at a time.
  std::set<int> fired;
  for (;;)
  {
    int best = -1;
    std::int64_t best_due = 0;
    for (const auto& [id, e] : timers_)
      if (!fired.count(id) && e.next <= now_ns && (best < 0 || e.next < best_due))
      {
        best = id;
        best_due = e.next;
      }
    if (best < 0)
      return count;
    fired.insert(best);
    ++count;
    Entry& e = timers_[best];
    const std::int64_t due = e.next;
    e.next = due + e.period;
    if (e.next <= now_ns)  // more than a period behind: skip to the next multiple
      e.next = nextMultiple(e.period, now_ns);
    Callback cb = e.cb;  // the callback may remove its own timer
    cb(due, now_ns);
  }
}

}  // namespace mybot_lockstep
