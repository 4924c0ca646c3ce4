"""Drive arbitration and the dead man (no ROS: times are plain seconds of ROS time).

One browser at a time drives: the client whose commands are fresh owns the output; other
clients are refused until the owner releases or goes silent for `timeout`. The output must be
zeroed when the owner releases, disconnects, sends bad input or goes silent; each of those
returns True exactly once so the caller publishes one zero twist.
"""


class DriveArbiter:
    def __init__(self, timeout):
        if not timeout > 0.0:
            raise ValueError("deadman timeout must be > 0 s, got %r" % (timeout,))
        self.timeout = float(timeout)
        self.owner = None
        self._last = None

    def _fresh(self, t):
        if self.owner is None:
            return False
        age = t - self._last
        # Time going backwards (a simulator reset) counts as stale: the safe side.
        return 0.0 <= age <= self.timeout

    def command(self, client, t):
        """A drive command from `client` at t. Returns None if it may drive, else why not."""
        if self.owner is not None and self.owner != client and self._fresh(t):
            return "another client is driving"
        self.owner = client
        self._last = t
        return None

    def release(self, client):
        """`client` let go (stop message, disconnect or bad input): True if the output must be zeroed."""
        if self.owner is None or self.owner != client:
            return False
        self.owner = None
        self._last = None
        return True

    def check(self, t):
        """Call periodically: True once when the owner's commands went stale at t."""
        if self.owner is None or self._fresh(t):
            return False
        self.owner = None
        self._last = None
        return True

    @property
    def driving(self):
        return self.owner is not None


def scale_command(drive, scale_linear, scale_angular, holonomic):
    """Normalised joystick values -> (vx, vy, wz) in m/s and rad/s; vy is 0 unless holonomic."""
    vy = drive.vy * scale_linear if holonomic else 0.0
    return drive.vx * scale_linear, vy, drive.wz * scale_angular
