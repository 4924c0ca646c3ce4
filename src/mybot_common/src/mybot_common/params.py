"""Validation of configuration values (pure: no ROS).

Every check raises ParamError naming the parameter, so a node can stop with one
clear message ("parameter '~speed': must be > 0, got -1.0").
"""
import math


class ParamError(ValueError):
    def __init__(self, name, message):
        super().__init__("parameter '%s': %s" % (name, message))
        self.name = name


def number(name, value, low=None, high=None, low_open=False, high_open=False, integer=False):
    """Return value as float (or int) after checking type, finiteness and range."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ParamError(name, "must be a number, got %r" % (value,))
    if integer and int(value) != value:
        raise ParamError(name, "must be an integer, got %r" % (value,))
    if not math.isfinite(value):
        raise ParamError(name, "must be finite, got %r" % (value,))
    if low is not None and (value < low or (low_open and value == low)):
        raise ParamError(name, "must be %s %g, got %g" % (">" if low_open else ">=", low, value))
    if high is not None and (value > high or (high_open and value == high)):
        raise ParamError(name, "must be %s %g, got %g" % ("<" if high_open else "<=", high, value))
    return int(value) if integer else float(value)


def boolean(name, value):
    if not isinstance(value, bool):
        raise ParamError(name, "must be true or false, got %r" % (value,))
    return value


def string(name, value, choices=None):
    if not isinstance(value, str):
        raise ParamError(name, "must be a string, got %r" % (value,))
    if choices is not None and value not in choices:
        raise ParamError(name, "must be one of %s, got %r" % (", ".join(choices), value))
    return value
