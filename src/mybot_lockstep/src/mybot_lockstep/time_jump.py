"""What a tf listener does when ROS time goes back, without ROS: the twin of time_jump.h, whose
comment says why. After time went back from a to b, until the clock reaches (a + b) / 2, a stamp
ahead of the clock by half the jump or more belongs to the old timeline."""

import math


class TimeJump:
    def __init__(self):
        self._last_now = None
        self.guard_until = -math.inf
        self._half_jump = 0.0

    def went_back(self, now):
        """Call with the clock (s) on each message received; True when time went back since the
        last call: clear the buffer."""
        back = self._last_now is not None and now < self._last_now
        if back:
            self._half_jump = 0.5 * (self._last_now - now)
            self.guard_until = now + self._half_jump
        self._last_now = now
        return back

    def stale(self, stamp, now):
        """Whether a message stamped `stamp`, received at clock `now`, predates the last jump."""
        return now < self.guard_until and stamp - now >= self._half_jump
