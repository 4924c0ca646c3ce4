"""The driver's logic, free of ROS: command bookkeeping, safety stop, encoder readout.

The node feeds it commands and the current (ROS) time; everything here is
deterministic and testable with a fake backend.
"""
import contextlib
import math
import threading

from .backends import BackendError
from .encoder import VelocityEstimator

LEFT, RIGHT = 0, 1


class WheelState:
    __slots__ = ("stamp", "positions", "velocities")

    def __init__(self, stamp, positions, velocities):
        self.stamp = stamp
        self.positions = positions
        self.velocities = velocities


class DriverCore:
    """Owns the backend; every backend call goes through here under one lock
    (subscriber callbacks, the main loop and the watchdog run in different threads,
    and the GoPiGo libraries are not thread safe).

    Messages are logged once the lock is released: a rospy log call asks the ROS master for a
    parameter every time (rosout's /rosout_disable_topics_generation, unless it is set), so with
    the master unreachable it blocks (1.3 s measured in test_two_machines), and a stop written
    by another thread must not wait for it."""

    def __init__(self, backend, cmd_timeout=0.5, velocity_window=0.2, log=None):
        if not (cmd_timeout > 0.0 and math.isfinite(cmd_timeout)):
            raise ValueError("cmd_timeout must be > 0 s, got %r" % cmd_timeout)
        self.backend = backend
        self.cmd_timeout = float(cmd_timeout)
        self._lock = threading.RLock()
        self._targets = [0.0, 0.0]
        self._stamps = [None, None]       # ROS time of the last command per wheel
        self._velocity = (VelocityEstimator(velocity_window), VelocityEstimator(velocity_window))
        self.stopped = True               # motors currently held at zero
        self.stop_reason = "no command yet"
        self.inhibited = None             # reason commands are refused (e.g. master lost)
        self.closed = False               # after shutdown() the backend is never driven again
        self.stops_written = 0            # wheels' zeros written on receipt (see command)
        self._log = log or (lambda level, msg: None)
        self._depth = 0                   # how deep the lock's owner holds it (an RLock)
        self._owner = None                # the thread holding it
        self._pending = []                # messages to log once it is released

    @contextlib.contextmanager
    def _locked(self):
        """The lock; the messages logged meanwhile are logged after it is released."""
        with self._lock:
            self._depth += 1
            self._owner = threading.get_ident()
            try:
                yield
            finally:
                self._depth -= 1
                pending = []
                if self._depth == 0:
                    self._owner = None
                    pending, self._pending = self._pending, []
        for level, msg in pending:
            self._log(level, msg)

    def log(self, level, msg):
        if self._owner == threading.get_ident():
            self._pending.append((level, msg))
        else:
            self._log(level, msg)

    @property
    def lock(self):
        """Held around every backend call; hold it to read the backend from another thread."""
        return self._lock

    # ---- inputs -----------------------------------------------------------
    def command(self, wheel, angular_vel, t):
        """A wheel speed command (rad/s) received at time t. Returns False if rejected.

        A wheel commanded to zero while the motors run is written at once: the loop would
        write it up to a period (1 / rate) later, and a stop (a released key, a controller
        whose input timed out) should not wait for the loop. Other commands wait for it, so
        the motors are written at the loop's rate."""
        if not math.isfinite(angular_vel):
            self.log("error", "non-finite %s wheel command %r ignored" % ("left" if wheel == LEFT else "right", angular_vel))
            return False
        with self._locked():
            stopping = angular_vel == 0.0 and self._targets[wheel] != 0.0
            self._targets[wheel] = float(angular_vel)
            self._stamps[wheel] = t
            if stopping and not self.stopped:
                self.write_commands(t)
                self.stops_written += 1
        return True

    def inhibit(self, reason, t):
        """Refuse commands and stop until release() (master lost, fatal error)."""
        with self._locked():
            if self.inhibited is None:
                self.log("error", "stopping motors: %s" % reason)
            self.inhibited = reason
            self._stamps = [None, None]
            self._stop(t, reason)

    def release(self):
        with self._locked():
            if self.inhibited is not None:
                self.log("info", "commands accepted again (was: %s)" % self.inhibited)
            self.inhibited = None

    # ---- safety -----------------------------------------------------------
    def command_fresh(self, t):
        """Both wheels commanded within cmd_timeout of t (ROS time)."""
        for stamp in self._stamps:
            if stamp is None or t - stamp > self.cmd_timeout or t < stamp:
                return False
        return True

    def deadline(self):
        """ROS time at which the motors must be stopped if no new command comes, or None."""
        with self._locked():
            if self.stopped or None in self._stamps:
                return None
            return min(self._stamps) + self.cmd_timeout

    def check_timeout(self, t):
        """Stop the motors if the commands went stale. Returns True when stopped."""
        with self._locked():
            if not self.stopped and (self.inhibited is not None or not self.command_fresh(t)):
                self._stop(t, "no command for %.2f s" % self.cmd_timeout)
            return self.stopped

    def emergency_stop(self, reason, t=None):
        with self._locked():
            self._stamps = [None, None]
            self._stop(t, reason)

    def _stop(self, t, reason):
        if self.closed:
            return
        was_stopped = self.stopped
        self.stopped = True
        self.stop_reason = reason
        self._targets = [0.0, 0.0]
        self.backend.stop(t)  # always re-sent: cheap, and it must reach the board
        if not was_stopped:
            self.log("warn", "motors stopped: %s" % reason)

    # ---- main loop --------------------------------------------------------
    def write_commands(self, t):
        """Send the current targets if fresh, otherwise hold the motors stopped."""
        with self._locked():
            if self.closed:
                return False
            if self.inhibited is None and self.command_fresh(t):
                if self.stopped:
                    self.log("info", "motors driven (commands fresh)")
                self.stopped = False
                self.backend.write(self._targets[LEFT], self._targets[RIGHT], t)
            elif not self.stopped:
                self.check_timeout(t)
            else:
                self.backend.stop(t)  # re-sent every cycle: a lost bus write must not leave a wheel running
            return not self.stopped

    def read_state(self, t):
        """WheelState at t, or None if the encoders could not be read this cycle."""
        with self._locked():
            if self.closed:
                return None
            try:
                positions = self.backend.read_positions(t)
            except BackendError as e:
                self.log("warn", str(e))
                return None
        velocities = tuple(est.update(t, p) for est, p in zip(self._velocity, positions))
        return WheelState(t, positions, velocities)

    def step(self, t):
        self.write_commands(t)
        return self.read_state(t)

    def battery_voltage(self):
        with self._locked():
            return None if self.closed else self.backend.battery_voltage()

    def shutdown(self):
        """Stop and release the hardware (node exit); safe to call more than once."""
        with self._locked():
            if self.closed:
                return
            try:
                self._stop(None, "shutdown")
            finally:
                self.closed = True
                self.backend.close()
