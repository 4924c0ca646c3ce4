// Link <-> mybot_lockstep/LinkCount.
#pragma once

#include "mybot_lockstep/LinkCount.h"
#include "mybot_lockstep/barrier.h"

namespace mybot_lockstep
{

inline Link fromMsg(const LinkCount& m)
{
  Link l;
  l.topic = m.topic;
  l.source = m.source;
  l.destination = m.destination;
  l.count = m.count;
  return l;
}

inline LinkCount toMsg(const Link& l)
{
  LinkCount m;
  m.topic = l.topic;
  m.source = l.source;
  m.destination = l.destination;
  m.count = l.count;
  return m;
}

}  // namespace mybot_lockstep
