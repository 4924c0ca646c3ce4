"""Validation of the messages a browser sends over the websocket (no ROS, no tornado).

Every message is one JSON object with a "type" and exactly the fields listed in SCHEMA for
that type. Numbers must be finite JSON numbers (booleans are not numbers here) inside the
listed range: an out-of-range joystick value is rejected, never clamped, because it means a
broken or hostile client and the robot must not move on it.
"""
import json
import math
from collections import namedtuple

MAX_MESSAGE_BYTES = 4096
MAX_TOKEN_CHARS = 256
# Messages are flat objects (depth 1). json decodes nesting recursively: 2000 levels fit in a
# 4 kB frame and exceed Python's recursion limit, so deep input is refused before decoding.
MAX_NESTING = 4
# Goals are in metres in the global frame; anything beyond this is a client bug.
MAX_GOAL_COORDINATE = 1.0e5

MODES = ("manual", "autonomous")


class ProtocolError(ValueError):
    """A message that does not follow the protocol; str() names the offending field."""


Auth = namedtuple("Auth", "token")
Drive = namedtuple("Drive", "vx vy wz")  # normalised to [-1, 1]
Stop = namedtuple("Stop", "")
Mode = namedtuple("Mode", "mode")
Goal = namedtuple("Goal", "x y yaw")  # global frame, m and rad
Cancel = namedtuple("Cancel", "")

# type -> (constructor, {field: spec}); a spec is ("number", lo, hi), ("string", max_len)
# or ("enum", choices).
SCHEMA = {
    "auth": (Auth, {"token": ("string", MAX_TOKEN_CHARS)}),
    "drive": (Drive, {"vx": ("number", -1.0, 1.0), "vy": ("number", -1.0, 1.0),
                      "wz": ("number", -1.0, 1.0)}),
    "stop": (Stop, {}),
    "mode": (Mode, {"mode": ("enum", MODES)}),
    "goal": (Goal, {"x": ("number", -MAX_GOAL_COORDINATE, MAX_GOAL_COORDINATE),
                    "y": ("number", -MAX_GOAL_COORDINATE, MAX_GOAL_COORDINATE),
                    "yaw": ("number", -2.0 * math.pi, 2.0 * math.pi)}),
    "cancel": (Cancel, {}),
}

# Messages that act on the robot and therefore need the token when one is required.
CONTROL_TYPES = (Drive, Stop, Mode, Goal, Cancel)


def _check_field(kind, name, value, spec):
    where = "%s.%s" % (kind, name)
    if spec[0] == "number":
        # bool is an int subclass in Python; JSON true must not pass as 1.
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ProtocolError("%s must be a number" % where)
        value = float(value)
        if not math.isfinite(value):
            raise ProtocolError("%s must be finite" % where)
        lo, hi = spec[1], spec[2]
        if not lo <= value <= hi:
            raise ProtocolError("%s = %g is outside [%g, %g]" % (where, value, lo, hi))
        return value
    if spec[0] == "string":
        if not isinstance(value, str):
            raise ProtocolError("%s must be a string" % where)
        if len(value) > spec[1]:
            raise ProtocolError("%s is longer than %d characters" % (where, spec[1]))
        if not _is_unicode(value):
            raise ProtocolError("%s is not valid Unicode (a lone UTF-16 surrogate)" % where)
        return value
    if value not in spec[1]:
        raise ProtocolError("%s must be one of %s" % (where, ", ".join(spec[1])))
    return value


def parse_message(raw):
    """Parse one websocket text frame; returns one of the namedtuples or raises ProtocolError."""
    if isinstance(raw, bytes):
        raise ProtocolError("binary frames are not accepted")
    if len(raw) > MAX_MESSAGE_BYTES:
        raise ProtocolError("message longer than %d bytes" % MAX_MESSAGE_BYTES)
    if _nesting(raw) > MAX_NESTING:
        raise ProtocolError("message nested deeper than %d levels" % MAX_NESTING)
    try:
        # Python's json accepts NaN/Infinity literals; reject them at the source.
        obj = json.loads(raw, parse_constant=_reject_constant)
    except ValueError as e:
        raise ProtocolError("not valid JSON (%s)" % e) from None
    if not isinstance(obj, dict):
        raise ProtocolError("message must be a JSON object")
    kind = obj.get("type")
    if not isinstance(kind, str) or kind not in SCHEMA:
        raise ProtocolError("type must be one of %s" % ", ".join(sorted(SCHEMA)))
    ctor, fields = SCHEMA[kind]
    extra = sorted(set(obj) - set(fields) - {"type"})
    if extra:
        # ascii(): the names come from the client and end up in the log; escaped, they cannot
        # forge log lines or carry text that does not encode.
        raise ProtocolError("%s has unknown field(s) %s" % (kind, ", ".join(map(ascii, extra))))
    values = {}
    for name, spec in fields.items():
        if name not in obj:
            raise ProtocolError("%s.%s is missing" % (kind, name))
        values[name] = _check_field(kind, name, obj[name], spec)
    return ctor(**values)


def _nesting(raw):
    """Deepest [ / { nesting of a JSON text, brackets inside strings not counted."""
    depth = deepest = 0
    in_string = escaped = False
    for c in raw:
        if in_string:
            if escaped:
                escaped = False
            elif c == "\\":
                escaped = True
            elif c == '"':
                in_string = False
        elif c == '"':
            in_string = True
        elif c in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif c in "]}":
            depth -= 1
    return deepest


def _is_unicode(text):
    # JSON's \uXXXX escapes can spell half of a UTF-16 surrogate pair, which is no character:
    # Python keeps it in the str, and encoding it later (the token comparison) would raise.
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


def _reject_constant(name):
    raise ValueError("%s is not allowed" % name)
