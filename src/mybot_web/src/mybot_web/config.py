"""The node's private parameters: names, defaults and validation (no ROS: `get(name, default)`
is passed in). Names follow teleop_twist_joy (scale_linear, scale_angular) where they exist."""
from collections import namedtuple

from .auth import ConfigError
from .hosts import normal_name
from .protocol import MODES


def _number(lo, hi, lo_open=False):
    def check(v):
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            return "must be a number"
        if (v <= lo if lo_open else v < lo) or v > hi:
            return "must be in %s%g, %g]" % ("(" if lo_open else "[", lo, hi)
        return None
    return check


def _integer(lo, hi):
    def check(v):
        if isinstance(v, bool) or not isinstance(v, int):
            return "must be an integer"
        return None if lo <= v <= hi else "must be in [%d, %d]" % (lo, hi)
    return check


def _string(v):
    return None if isinstance(v, str) and v else "must be a non-empty string"


def _token(v):
    return None if isinstance(v, str) else "must be a string"


def _bool(v):
    return None if isinstance(v, bool) else "must be true or false"


def _mode(v):
    return None if v in MODES else "must be one of %s" % ", ".join(MODES)


def _pattern(v):
    if not isinstance(v, str) or "{module}" not in v:
        return "must be a topic name containing {module}"
    return None


def _names(v):
    if not isinstance(v, list) or not all(isinstance(m, str) and m for m in v):
        return "must be a list of non-empty strings"
    return "has duplicates" if len(set(v)) != len(v) else None


def _hosts(v):
    if not isinstance(v, list) or not all(isinstance(h, str) for h in v):
        return "must be a list of host names (strings)"
    bad = [h for h in v if normal_name(h) is None]
    if bad:
        return ("has %r, not a host name or address (the name alone: no scheme, port or path)"
                % bad[0])
    return None


# name: (default, check, meaning)
PARAMS = {
    "host": ("127.0.0.1", _string, "address to bind; not loopback => a control token is required"),
    "allowed_hosts": ([], _hosts, "more names the page may be opened with (DNS-rebinding "
                      "defence); loopback, ~host, addresses and, on 0.0.0.0/::, this machine's "
                      "names are always accepted"),
    "port": (8080, _integer(0, 65535), "TCP port (0 = any free port, see ~url)"),
    "token": ("", _token, "control token; empty = none on loopback, generated otherwise"),
    "holonomic": (False, _bool, "offer sideways motion (linear.y), for the swerve robot"),
    "scale_linear": (0.5, _number(0.0, 10.0, lo_open=True), "m/s at full joystick deflection"),
    "scale_angular": (1.0, _number(0.0, 20.0, lo_open=True), "rad/s at full joystick deflection"),
    "deadman_timeout": (0.3, _number(0.0, 5.0, lo_open=True),
                        "s of ROS time without a command before the output is zeroed"),
    "view_rate": (10.0, _number(0.0, 50.0, lo_open=True), "Hz of live view updates to the page"),
    "lock_rate": (2.0, _number(0.0, 50.0, lo_open=True), "Hz of the mode lock republication"),
    "global_frame": ("map", _string, "frame of the map and goals"),
    "odom_frame": ("odom", _string, "frame shown when global_frame is not available"),
    "base_frame": ("base_footprint", _string, "robot frame"),
    "initial_mode": ("autonomous", _mode, "mode at start-up"),
    "move_base_action": ("move_base", _string, "move_base_msgs/MoveBase action namespace"),
    "swerve_modules": ([], _names, "swerve module names (e.g. [a, b, c, d]); empty = no panel"),
    "swerve_angle_topic": ("swerve_{module}/pivot_angle", _pattern,
                           "per-module measured pivot angle (Float64/Float32, rad)"),
    "swerve_speed_topic": ("swerve_{module}/wheel_speed", _pattern,
                           "per-module measured wheel speed (Float64/Float32)"),
    "max_scan_points": (360, _integer(1, 10000), "laser points sent per update"),
    "max_path_points": (500, _integer(2, 10000), "path points sent per update"),
}

Config = namedtuple("Config", sorted(PARAMS))


def load(get):
    """get(name, default) -> value of ~name. Raises ConfigError naming the first bad parameter."""
    values = {}
    for name, (default, check, _) in PARAMS.items():
        value = get(name, default)
        # YAML/XML-RPC give ints for "1"; accept them where a float is wanted.
        if isinstance(default, float) and isinstance(value, int) and not isinstance(value, bool):
            value = float(value)
        problem = check(value)
        if problem:
            raise ConfigError("~%s %s (got %r)" % (name, problem, value))
        values[name] = value
    return Config(**values)
