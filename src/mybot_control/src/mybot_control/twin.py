"""A simulated twin driven by a real robot's own sensors (the Cairo TurtleBot-Burger report): its
two wheel speeds (rad/s) give the linear speed, the gyro's yaw rate (deg/s, an MPU6050) the
angular speed. A gyro at rest is never exactly 0 (bias and noise of a few tenths of a degree per
second), and the twin spun by itself until its authors added a dead band: readings within
`deadband_dps` of the bias are taken as 0. Wheel speeds get one too (`wheel_deadband`, rad/s): an
encoder at rest reads a tick now and then, a simulated joint a jitter of its solver. No rospy."""
import math


class TwinMapper:
    """Latest wheel speeds and gyro reading -> the twin's (v, w). Stale or missing input (older
    than `timeout` s, or from before a jump back in time) gives (0, 0): the twin stops rather than
    replaying a speed the real robot may no longer have."""

    def __init__(self, wheel_radius, deadband_dps, gyro_bias_dps=0.0, timeout=0.5, wheel_deadband=0.02):
        if not (math.isfinite(wheel_radius) and wheel_radius > 0):
            raise ValueError("wheel_radius must be a positive number of metres, got %r" % (wheel_radius,))
        if not (math.isfinite(deadband_dps) and deadband_dps >= 0):
            raise ValueError("gyro_deadband must be >= 0 deg/s, got %r" % (deadband_dps,))
        if not math.isfinite(gyro_bias_dps):
            raise ValueError("gyro_bias must be a finite number of deg/s, got %r" % (gyro_bias_dps,))
        if not (math.isfinite(wheel_deadband) and wheel_deadband >= 0):
            raise ValueError("wheel_deadband must be >= 0 rad/s, got %r" % (wheel_deadband,))
        if not (math.isfinite(timeout) and timeout > 0):
            raise ValueError("timeout must be > 0 s, got %r" % (timeout,))
        self.radius = wheel_radius
        self.deadband = deadband_dps
        self.bias = gyro_bias_dps
        self.timeout = timeout
        self.wheel_deadband = wheel_deadband
        self._wheels = None  # (t, left rad/s, right rad/s)
        self._gyro = None    # (t, deg/s)

    def wheels(self, t, left, right):
        if math.isfinite(left) and math.isfinite(right):
            self._wheels = (t, left, right)

    def gyro(self, t, dps):
        if math.isfinite(dps):
            self._gyro = (t, dps)

    def _fresh(self, sample, t):
        return sample is not None and 0.0 <= t - sample[0] <= self.timeout

    def yaw_rate(self, dps):
        """deg/s of the gyro -> rad/s of the twin: bias removed, the dead band zeroed."""
        rate = dps - self.bias
        return 0.0 if abs(rate) <= self.deadband else math.radians(rate)

    def twist(self, t):
        """(v m/s, w rad/s) for the twin at time t."""
        if not (self._fresh(self._wheels, t) and self._fresh(self._gyro, t)):
            return 0.0, 0.0
        _, left, right = self._wheels
        left, right = (0.0 if abs(s) <= self.wheel_deadband else s for s in (left, right))
        return self.radius * (left + right) / 2.0, self.yaw_rate(self._gyro[1])


def propose_deadband(samples_dps, margin=1.5):
    """From gyro readings at rest: (bias, dead band) in deg/s. The bias is their mean; the dead
    band covers the largest deviation from it seen, with a margin, so the twin stays still."""
    if len(samples_dps) < 10:
        raise ValueError("need at least 10 gyro readings at rest, got %d" % len(samples_dps))
    bias = sum(samples_dps) / len(samples_dps)
    spread = max(abs(s - bias) for s in samples_dps)
    return bias, spread * margin
