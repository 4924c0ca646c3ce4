#include "mybot_lockstep/time_jump.h"

#include <cmath>

namespace mybot_lockstep
{

bool TimeJump::wentBack(double now)
{
  const bool back = !std::isnan(last_now_) && now < last_now_;
  if (back)
  {
    half_jump_ = 0.5 * (last_now_ - now);
    guard_until_ = now + half_jump_;
  }
  last_now_ = now;
  return back;
}

}  // namespace mybot_lockstep
