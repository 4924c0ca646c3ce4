"""A simulated PWM wheel motor with an encoder (no ROS types).

Model, per motor: the steady-state wheel speed for a command u is
    w_ss(u) = gain * rad_per_cmd * sign(u) * max(0, |u| - deadband)
(a DC motor under constant load: nothing below the dead band, then linear),
approached with a first-order lag of ``time_constant``. The encoder reports the
wheel angle quantised to ``counts_per_rev`` counts; optional Gaussian speed noise
(seeded, so runs are repeatable) stands for load and floor variation.
Time is whatever the caller passes in (ROS time in the node), never the wall clock.
"""
import math
import random


class SimMotor:
    def __init__(self, deadband, rad_per_cmd, gain=1.0, time_constant=0.1,
                 counts_per_rev=360, noise_std=0.0, seed=0, max_step=0.005):
        checks = (("deadband", deadband, deadband >= 0.0),
                  ("rad_per_cmd", rad_per_cmd, rad_per_cmd > 0.0),
                  ("gain", gain, gain >= 0.0),
                  ("time_constant", time_constant, time_constant >= 0.0),
                  ("counts_per_rev", counts_per_rev, counts_per_rev > 0),
                  ("noise_std", noise_std, noise_std >= 0.0),
                  ("max_step", max_step, max_step > 0.0))
        for name, value, ok in checks:
            if not ok or not math.isfinite(value):
                raise ValueError("simulated motor: invalid %s = %r" % (name, value))
        self.deadband = float(deadband)
        self.rad_per_cmd = float(rad_per_cmd)
        self.gain = float(gain)
        self.time_constant = float(time_constant)
        self.counts_per_rev = int(counts_per_rev)
        self.noise_std = float(noise_std)
        self.max_step = float(max_step)
        self._rng = random.Random(seed)
        self.command = 0.0
        self.velocity = 0.0   # true wheel speed, rad/s
        self.position = 0.0   # true wheel angle, rad
        self._t = None

    def steady_state_velocity(self, command):
        excess = max(0.0, abs(command) - self.deadband)
        return math.copysign(self.gain * self.rad_per_cmd * excess, command) if excess > 0.0 else 0.0

    def set_command(self, command, t):
        self.advance(t)
        self.command = float(command)

    def advance(self, t):
        """Integrate the model up to time t (s). Going back in time resets the clock only."""
        if self._t is None or t < self._t:
            self._t = t
            return
        remaining = t - self._t
        target = self.steady_state_velocity(self.command)
        # Sub-steps keep the integration exact-ish at any caller rate.
        while remaining > 1e-12:
            h = min(remaining, self.max_step)
            if self.time_constant > 0.0:
                alpha = 1.0 - math.exp(-h / self.time_constant)
                new_velocity = self.velocity + (target - self.velocity) * alpha
            else:
                new_velocity = target
            if self.noise_std > 0.0 and target != 0.0:
                new_velocity += self._rng.gauss(0.0, self.noise_std) * math.sqrt(h / self.max_step)
            self.position += 0.5 * (self.velocity + new_velocity) * h
            self.velocity = new_velocity
            remaining -= h
        self._t = t

    def encoder_count(self):
        """Quantised wheel angle in encoder counts (floor, as a real counter does)."""
        return int(math.floor(self.position * self.counts_per_rev / (2.0 * math.pi)))
