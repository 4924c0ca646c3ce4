"""The tutorial's angular-velocity -> motor-command map (no ROS types).

A PWM motor does not turn below some command (its dead band) and tops out at the
largest command. The GoPiGo tutorial measured two points of the wheel speed
curve, (motor_min_angular_vel, motor_cmd_min) and (motor_max_angular_vel,
motor_cmd_max), and maps a wanted wheel speed through the straight line between
them. Differences from the tutorial's angularvel_2_motorcmd: the parameters are
validated, the result is rounded to the integer the hardware accepts, and the
map is a pure function so it can be tested.
"""
import math


class MotorMapError(ValueError):
    """A motor map parameter is invalid; the message names it."""


class MotorMap:
    """Signed wheel speed (rad/s) -> signed integer motor command.

    * 0 -> 0 (a stopped wheel gets no power, never the dead-band minimum);
    * |w| below motor_min_angular_vel -> +-motor_cmd_min (the smallest command
      that still turns the wheel: asking for less would stall it);
    * |w| above motor_max_angular_vel -> +-motor_cmd_max (clamped);
    * in between: linear through the two calibration points; sign of w kept.
    """

    def __init__(self, motor_min_angular_vel=1.28, motor_max_angular_vel=5.32,
                 motor_cmd_min=110, motor_cmd_max=255, zero_threshold=1e-6):
        for name, value in (("motor_min_angular_vel", motor_min_angular_vel),
                            ("motor_max_angular_vel", motor_max_angular_vel),
                            ("motor_cmd_min", motor_cmd_min),
                            ("motor_cmd_max", motor_cmd_max),
                            ("zero_threshold", zero_threshold)):
            if not isinstance(value, (int, float)) or isinstance(value, bool) or not math.isfinite(value):
                raise MotorMapError("%s must be a finite number, got %r" % (name, value))
        if motor_min_angular_vel <= 0.0:
            raise MotorMapError("motor_min_angular_vel must be > 0 rad/s, got %r" % motor_min_angular_vel)
        if motor_max_angular_vel <= motor_min_angular_vel:
            raise MotorMapError("motor_max_angular_vel (%r) must be greater than motor_min_angular_vel (%r)"
                                % (motor_max_angular_vel, motor_min_angular_vel))
        if motor_cmd_min < 0:
            raise MotorMapError("motor_cmd_min must be >= 0, got %r" % motor_cmd_min)
        if motor_cmd_max <= motor_cmd_min:
            raise MotorMapError("motor_cmd_max (%r) must be greater than motor_cmd_min (%r)"
                                % (motor_cmd_max, motor_cmd_min))
        if zero_threshold < 0.0:
            raise MotorMapError("zero_threshold must be >= 0, got %r" % zero_threshold)
        self.motor_min_angular_vel = float(motor_min_angular_vel)
        self.motor_max_angular_vel = float(motor_max_angular_vel)
        self.motor_cmd_min = float(motor_cmd_min)
        self.motor_cmd_max = float(motor_cmd_max)
        self.zero_threshold = float(zero_threshold)
        self.slope = (self.motor_cmd_max - self.motor_cmd_min) / (self.motor_max_angular_vel - self.motor_min_angular_vel)
        # Command at which the calibration line reaches 0 rad/s: the motor's
        # effective dead band if it really were linear.
        self.intercept = self.motor_cmd_max - self.slope * self.motor_max_angular_vel

    def command(self, angular_vel):
        """Signed integer command for a signed wheel speed in rad/s."""
        if not math.isfinite(angular_vel):
            return 0
        magnitude = abs(angular_vel)
        if magnitude <= self.zero_threshold:
            return 0
        cmd = self.slope * magnitude + self.intercept
        cmd = min(max(cmd, self.motor_cmd_min), self.motor_cmd_max)
        return int(math.copysign(round(cmd), angular_vel))

    def angular_vel(self, command):
        """Inverse on the linear part (what the calibration predicts a command gives)."""
        magnitude = abs(command)
        if magnitude < self.motor_cmd_min:
            return 0.0
        w = (min(magnitude, self.motor_cmd_max) - self.intercept) / self.slope
        return math.copysign(w, command)
