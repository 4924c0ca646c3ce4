"""Encoder counters: wrap-around and direction handling (no ROS types)."""
import math


class EncoderUnwrapper:
    """Turns a modular hardware counter into an unbounded count.

    The counter is assumed to change by less than half its range between two
    reads (at 50 Hz that is thousands of wheel turns per second for both GoPiGo
    boards), so the shortest signed difference modulo ``modulus`` is the real
    motion, also across the wrap.
    """

    def __init__(self, modulus):
        if modulus <= 0:
            raise ValueError("encoder modulus must be > 0, got %r" % modulus)
        self.modulus = modulus
        self._last_raw = None
        self.count = 0

    def update(self, raw):
        """Feed one raw reading; returns the unwrapped count (0 at the first reading)."""
        if self._last_raw is None:
            self._last_raw = raw
            return self.count
        delta = (raw - self._last_raw) % self.modulus
        if delta >= self.modulus / 2.0:
            delta -= self.modulus
        self._last_raw = raw
        self.count += delta
        return self.count


class DirectionalPulseCounter:
    """A single-channel (unsigned, 16-bit) pulse counter made signed.

    The GoPiGo v1/v2 encoders count pulses without direction and wrap at 2^16.
    The direction comes from the sign of the command the motor is being driven
    with (the only information the board has); the tutorial instead read the
    count as centimetres and took the sign from a topic.
    """

    MODULUS = 1 << 16

    def __init__(self, modulus=MODULUS):
        if modulus <= 0:
            raise ValueError("encoder modulus must be > 0, got %r" % modulus)
        self.modulus = modulus
        self._last_raw = None
        self._last_direction = 1
        self.count = 0

    def update(self, raw, direction):
        """raw: counter value; direction: sign of the command applied since the last read."""
        if self._last_raw is None:
            self._last_raw = raw
            return self.count
        delta = (raw - self._last_raw) % self.modulus  # unsigned counter: always moves up
        self._last_raw = raw
        if direction < 0:
            delta = -delta
        elif direction == 0:
            # Coasting to a stop after a command: keep the last direction's sign.
            delta = delta if self._last_direction >= 0 else -delta
        if direction != 0:
            self._last_direction = direction
        self.count += delta
        return self.count


def counts_to_radians(count, counts_per_rev):
    return 2.0 * math.pi * count / counts_per_rev


class VelocityEstimator:
    """Wheel speed from positions over a sliding time window.

    A quantised encoder read at a high rate gives a noisy difference quotient;
    a least-squares slope over the last ``window`` seconds of samples trades a
    little lag (window/2) for resolution.
    """

    def __init__(self, window):
        if window < 0.0:
            raise ValueError("velocity window must be >= 0 s, got %r" % window)
        self.window = window
        self._samples = []  # (t, position)

    def reset(self):
        self._samples = []

    def update(self, t, position):
        samples = self._samples
        if samples and t <= samples[-1][0]:
            # Same or earlier time (sim clock paused/reset): restart the window.
            if t < samples[-1][0]:
                samples.clear()
            else:
                samples[-1] = (t, position)
                return self._velocity()
        samples.append((t, position))
        # Keep the newest sample older than the window as the reference point.
        while len(samples) > 2 and samples[1][0] <= t - self.window:
            samples.pop(0)
        return self._velocity()

    def _velocity(self):
        samples = self._samples
        if len(samples) < 2:
            return 0.0
        n = len(samples)
        t_mean = sum(s[0] for s in samples) / n
        p_mean = sum(s[1] for s in samples) / n
        stt = sum((s[0] - t_mean) ** 2 for s in samples)
        if stt <= 0.0:
            return 0.0
        return sum((s[0] - t_mean) * (s[1] - p_mean) for s in samples) / stt
