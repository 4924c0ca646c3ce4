// What a tf listener does when ROS time goes back (a simulation reset, a bag played again),
// without ROS. tf2_ros's listener clears its buffer when it sees the clock go back; that is
// not enough. A transform a node published just before the jump can reach a subscriber just
// after it, once the buffer has been cleared (under lockstep, every message a participant
// published in the last period before a reset is handed over in the first period after it).
// Its stamp lies in the future of the new clock, and tf2 then refuses every newer transform of
// the same frame as data from the past (TF_OLD_DATA) for as long as the buffer's cache_time
// (10 s), so the frame seems gone: move_base once aborted a goal after a reset with "the robot
// pose is unknown". TimeJump recognises those late arrivals so the listener can drop them.
//
// The rule: after time went back from `a` to `b`, until the clock reaches the midpoint
// (a + b) / 2, a stamp ahead of the clock by half the jump or more belongs to the old timeline.
// A message of the new timeline is stamped near the clock (a publisher future-dates a transform
// by tenths of a second: amcl's transform_tolerance), one of the old timeline near `a`. Once the
// clock is past the midpoint the old timeline's messages have long arrived (they are in flight
// for a period or two), and nothing is dropped any more.
#pragma once

#include <limits>

namespace mybot_lockstep
{

class TimeJump
{
public:
  // Call with the clock (s) on each message received, before stale(); true when time went
  // back since the last call: clear the buffer.
  bool wentBack(double now);

  // Whether a message stamped `stamp` (s), received when the clock reads `now`, was stamped on
  // the timeline before the last jump back.
  bool stale(double stamp, double now) const { return now < guard_until_ && stamp - now >= half_jump_; }

  // Until when (s) late arrivals are looked for: the midpoint of the last jump back.
  double guardUntil() const { return guard_until_; }

private:
  double last_now_ = std::numeric_limits<double>::quiet_NaN();
  double guard_until_ = -std::numeric_limits<double>::infinity();
  double half_jump_ = 0.0;
};

}  // namespace mybot_lockstep
