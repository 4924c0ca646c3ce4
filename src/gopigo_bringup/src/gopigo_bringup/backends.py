"""Motor/encoder backends behind one interface (no ROS types).

Every backend takes wheel speeds in rad/s (positive = the wheel rolls the robot
forward, i.e. positive rotation about the joint's +y axis) and reports unwrapped
wheel angles in rad, left and right, in that order.

* GoPiGoBackend  - GoPiGo v1/v2 ``gopigo`` module (I2C): motor1 = LEFT,
  motor2 = RIGHT, ``enc_read(0)`` = motor1 = LEFT, ``enc_read(1)`` = RIGHT
  (the tutorial read enc_read(1) as the left wheel). ``enc_read`` returns a
  16-bit unsigned pulse count (18 pulses per wheel turn; the library comment
  calls it "distance in cm", which it is not), or -1 on an I2C error.
* GoPiGo3Backend - ``gopigo3.GoPiGo3`` (SPI): the board runs its own speed loop,
  so speeds go out as ``set_motor_dps``; ``get_motor_encoder`` is in wheel
  degrees (a signed 32-bit tick counter divided by MOTOR_TICKS_PER_DEGREE).
* SimBackend     - two SimMotor models driven through the same motor map as
  the v1/v2 board.
"""
import abc
import math

from .encoder import DirectionalPulseCounter, EncoderUnwrapper, counts_to_radians
from .sim_motor import SimMotor


class BackendError(RuntimeError):
    """The hardware did not answer as expected (read failed, bad reply)."""


class Backend(abc.ABC):
    name = "abstract"
    counts_per_rev = 0

    @abc.abstractmethod
    def write(self, left, right, t):
        """Drive the wheels at left/right rad/s (t: current time, s)."""

    @abc.abstractmethod
    def stop(self, t):
        """Zero power/speed to both motors. Must not raise for a healthy link."""

    @abc.abstractmethod
    def read_positions(self, t):
        """(left, right) unwrapped wheel angles in rad; raises BackendError."""

    def battery_voltage(self):
        """Battery voltage in V, or None when it could not be read."""
        return None

    def close(self):
        """Leave the motors unpowered for good (node exit)."""


def _sign(x):
    return (x > 0) - (x < 0)


class GoPiGoBackend(Backend):
    name = "gopigo"
    FORWARD, BACKWARD = 1, 0
    LEFT_ENCODER, RIGHT_ENCODER = 0, 1  # enc_read argument: 0 = motor1, 1 = motor2

    def __init__(self, module, motor_map, counts_per_rev=18, board_timeout=1.0):
        if counts_per_rev <= 0:
            raise ValueError("encoder_ppr must be > 0, got %r" % counts_per_rev)
        self.gopigo = module
        if board_timeout > 0.0 and hasattr(module, "enable_com_timeout"):
            # The board's own watchdog: stops the motors even if this process
            # dies without a word (kill -9, Pi crash).
            module.enable_com_timeout(int(round(board_timeout * 1000)))
        self.motor_map = motor_map
        self.counts_per_rev = counts_per_rev
        self._counters = (DirectionalPulseCounter(), DirectionalPulseCounter())
        self._directions = [0, 0]
        self.last_commands = (0, 0)

    def _drive(self, motor_fn, command):
        direction = self.FORWARD if command >= 0 else self.BACKWARD
        motor_fn(direction, int(min(abs(command), 255)))

    def write(self, left, right, t):
        lcmd, rcmd = self.motor_map.command(left), self.motor_map.command(right)
        self._drive(self.gopigo.motor1, lcmd)
        self._drive(self.gopigo.motor2, rcmd)
        self._directions = [_sign(lcmd), _sign(rcmd)]
        self.last_commands = (lcmd, rcmd)

    def stop(self, t):
        self.gopigo.motor1(self.FORWARD, 0)
        self.gopigo.motor2(self.FORWARD, 0)
        self._directions = [0, 0]
        self.last_commands = (0, 0)

    def read_positions(self, t):
        out = []
        for index, (channel, counter) in enumerate(((self.LEFT_ENCODER, self._counters[0]),
                                                    (self.RIGHT_ENCODER, self._counters[1]))):
            raw = self.gopigo.enc_read(channel)
            if raw is None or not isinstance(raw, int) or raw < 0:
                raise BackendError("gopigo.enc_read(%d) failed (returned %r)" % (channel, raw))
            count = counter.update(raw, self._directions[index])
            out.append(counts_to_radians(count, self.counts_per_rev))
        return tuple(out)

    def battery_voltage(self):
        v = self.gopigo.volt()
        return float(v) if v is not None and v >= 0 else None

    def close(self):
        self.stop(None)
        if hasattr(self.gopigo, "stop"):
            self.gopigo.stop()


class GoPiGo3Backend(Backend):
    name = "gopigo3"

    def __init__(self, board, max_dps=1000.0):
        if not max_dps > 0.0:
            raise ValueError("gopigo3_max_dps must be > 0, got %r" % max_dps)
        self.board = board
        self.max_dps = float(max_dps)
        ticks_per_degree = float(getattr(board, "MOTOR_TICKS_PER_DEGREE", 120.0 * 16.0 / 360.0))
        # get_motor_encoder divides a signed 32-bit tick counter: it wraps by 2^32 ticks.
        self._unwrappers = (EncoderUnwrapper(round(2 ** 32 / ticks_per_degree)),
                            EncoderUnwrapper(round(2 ** 32 / ticks_per_degree)))
        self.counts_per_rev = 360
        self.last_commands = (0.0, 0.0)

    def _dps(self, w):
        dps = math.degrees(w) if math.isfinite(w) else 0.0
        return max(-self.max_dps, min(self.max_dps, dps))

    def write(self, left, right, t):
        ldps, rdps = self._dps(left), self._dps(right)
        self.board.set_motor_dps(self.board.MOTOR_LEFT, ldps)
        self.board.set_motor_dps(self.board.MOTOR_RIGHT, rdps)
        self.last_commands = (ldps, rdps)

    def stop(self, t):
        self.board.set_motor_dps(self.board.MOTOR_LEFT + self.board.MOTOR_RIGHT, 0)
        self.last_commands = (0.0, 0.0)

    def read_positions(self, t):
        try:
            left = self.board.get_motor_encoder(self.board.MOTOR_LEFT)
            right = self.board.get_motor_encoder(self.board.MOTOR_RIGHT)
        except IOError as e:
            raise BackendError("gopigo3.get_motor_encoder failed: %s" % e)
        return (math.radians(self._unwrappers[0].update(left)),
                math.radians(self._unwrappers[1].update(right)))

    def battery_voltage(self):
        try:
            return float(self.board.get_voltage_battery())
        except IOError:
            return None

    def close(self):
        try:
            self.stop(None)
        finally:
            # Let the wheels float (no holding current) once the driver is gone.
            float_power = getattr(self.board, "MOTOR_FLOAT", -128)
            self.board.set_motor_power(self.board.MOTOR_LEFT + self.board.MOTOR_RIGHT, float_power)


class SimBackend(Backend):
    name = "sim"

    def __init__(self, left_motor, right_motor, motor_map, battery_voltage=9.6):
        if left_motor.counts_per_rev != right_motor.counts_per_rev:
            raise ValueError("simulated motors must share one encoder resolution")
        self.motors = (left_motor, right_motor)
        self.motor_map = motor_map
        self.counts_per_rev = left_motor.counts_per_rev
        self._battery = float(battery_voltage)
        self.last_commands = (0, 0)

    @classmethod
    def from_params(cls, motor_map, time_constant=0.1, left_gain=1.0, right_gain=1.0,
                    counts_per_rev=360, noise_std=0.0, seed=0, deadband=None,
                    rad_per_cmd=None, battery_voltage=9.6):
        # By default the motor is exactly what the calibration line describes, so
        # open loop is right with gain 1 and a weaker motor shows up as a gain < 1.
        deadband = motor_map.intercept if deadband is None else deadband
        deadband = max(0.0, deadband)
        rad_per_cmd = 1.0 / motor_map.slope if rad_per_cmd is None else rad_per_cmd
        make = lambda gain, s: SimMotor(deadband, rad_per_cmd, gain, time_constant,
                                         counts_per_rev, noise_std, s)
        return cls(make(left_gain, seed), make(right_gain, seed + 1), motor_map, battery_voltage)

    def write(self, left, right, t):
        lcmd, rcmd = self.motor_map.command(left), self.motor_map.command(right)
        self.motors[0].set_command(lcmd, t)
        self.motors[1].set_command(rcmd, t)
        self.last_commands = (lcmd, rcmd)

    def stop(self, t):
        for m in self.motors:
            if t is None:
                m.command = 0.0
            else:
                m.set_command(0, t)
        self.last_commands = (0, 0)

    def read_positions(self, t):
        for m in self.motors:
            m.advance(t)
        return tuple(counts_to_radians(m.encoder_count(), self.counts_per_rev) for m in self.motors)

    def true_state(self):
        """(positions, velocities) of the model itself, for tests and benchmarks."""
        return tuple(m.position for m in self.motors), tuple(m.velocity for m in self.motors)

    def battery_voltage(self):
        return self._battery

    def close(self):
        self.stop(None)
