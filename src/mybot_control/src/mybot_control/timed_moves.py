"""Timed motion profiles: a twist held for a duration, then the next (pure: no ROS).

The GoPiGo tutorial's nav_timed moves the robot open-loop: drive forward for
distance/speed seconds, turn for angle/rate seconds, or both four times for a square.
"""
import math
from collections import namedtuple

from mybot_common.params import ParamError, number

# twist = (linear x, linear y, angular z); duration in s (math.inf: until stopped)
Segment = namedtuple("Segment", "name twist duration")
ZERO = (0.0, 0.0, 0.0)


def forward(distance, speed):
    """Straight line of `distance` m (negative: backwards) at |speed| m/s."""
    number("~distance", distance)
    number("~linear_speed", speed, low=0, low_open=True)
    return [Segment("forward", (math.copysign(speed, distance), 0.0, 0.0), abs(distance) / speed)]


def rotate(angle, rate):
    """In-place turn of `angle` rad (positive: counter-clockwise) at |rate| rad/s."""
    number("~angle", angle)
    number("~angular_speed", rate, low=0, low_open=True)
    return [Segment("rotate", (0.0, 0.0, math.copysign(rate, angle)), abs(angle) / rate)]


def square(side, speed, rate, pause=0.0, clockwise=False):
    """Four sides and four 90 degree turns, with optional stops in between."""
    number("~pause", pause, low=0)
    turn = rotate(-math.pi / 2 if clockwise else math.pi / 2, rate)[0]
    side_seg = forward(side, speed)[0]
    profile = []
    for k in range(4):
        profile.append(side_seg._replace(name="side %d" % (k + 1)))
        if pause > 0:
            profile.append(Segment("pause", ZERO, pause))
        profile.append(turn._replace(name="turn %d" % (k + 1)))
        if pause > 0 and k < 3:
            profile.append(Segment("pause", ZERO, pause))
    return profile


def constant(twist, duration=math.inf):
    """One twist for `duration` s (kbot's constant-twist publisher: forever)."""
    if math.isfinite(duration):
        number("~duration", duration, low=0)
    return [Segment("constant", tuple(float(v) for v in twist), duration)]


def total_duration(profile):
    return sum(s.duration for s in profile)


def command_at(profile, t):
    """(segment index, twist) in force t s after the start; (None, ZERO) once finished."""
    if t < 0:
        return None, ZERO
    start = 0.0
    for k, seg in enumerate(profile):
        if t < start + seg.duration:
            return k, seg.twist
        start += seg.duration
    return None, ZERO


def next_boundary(profile, t):
    """Time of the first segment boundary strictly after t (math.inf if none)."""
    start = 0.0
    for seg in profile:
        start += seg.duration
        if start > t:
            return start
    return math.inf


def build(mode, linear_speed, angular_speed, distance, angle, side, pause, clockwise,
          linear_x, linear_y, angular_z, duration):
    """Profile for a nav_timed mode; raises ParamError naming the offending parameter."""
    if mode == "forward":
        return forward(distance, linear_speed)
    if mode == "rotate":
        return rotate(angle, angular_speed)
    if mode == "square":
        if side <= 0:
            raise ParamError("~side", "must be > 0, got %g" % side)
        return square(side, linear_speed, angular_speed, pause, clockwise)
    if mode == "custom":
        return constant((linear_x, linear_y, angular_z), math.inf if duration == 0 else duration)
    raise ParamError("~mode", "must be one of forward, rotate, square, custom; got %r" % (mode,))
