"""Linux joystick decoding and Joy -> Twist mapping (pure: no ROS).

The kernel's joystick API (linux/joystick.h) delivers 8-byte events:
    struct js_event { __u32 time; /* ms */  __s16 value;  __u8 type;  __u8 number; };
type is JS_EVENT_BUTTON (0x01) or JS_EVENT_AXIS (0x02), or'ed with JS_EVENT_INIT
(0x80) for the synthetic events that report the initial state after open().

Axis scaling and deadzone follow the ROS joy package: values are negated (stick
up/left -> +1), the deadzone (a fraction of full travel) is cut out and the rest
is rescaled so the output still spans [-1, 1].
"""
import math
import struct
from collections import namedtuple

JS_EVENT_BUTTON = 0x01
JS_EVENT_AXIS = 0x02
JS_EVENT_INIT = 0x80
EVENT = struct.Struct("<IhBB")
EVENT_SIZE = EVENT.size  # 8

JsEvent = namedtuple("JsEvent", "time value type number init")


def encode_event(time_ms, value, type_, number, init=False):
    """Bytes of one js_event (used to record/replay and in tests)."""
    return EVENT.pack(time_ms & 0xFFFFFFFF, value, type_ | (JS_EVENT_INIT if init else 0), number)


def decode_events(data):
    """Split bytes into events; returns (events, leftover bytes of a partial event)."""
    n = len(data) // EVENT_SIZE
    events = []
    for k in range(n):
        t, value, type_, number = EVENT.unpack_from(data, k * EVENT_SIZE)
        events.append(JsEvent(t, value, type_ & ~JS_EVENT_INIT, number, bool(type_ & JS_EVENT_INIT)))
    return events, bytes(data[n * EVENT_SIZE:])


def check_deadzone(deadzone):
    if not 0.0 <= deadzone <= 0.9:
        raise ValueError("must be in [0, 0.9] (a fraction of full stick travel), got %g" % deadzone)
    return deadzone


def scale_axis(raw, deadzone):
    """joy's mapping of a raw s16 axis value to [-1, 1] (sign flipped) with a deadzone."""
    unscaled_deadzone = 32767.0 * deadzone
    val = float(raw)
    if val > unscaled_deadzone:
        val -= unscaled_deadzone
    elif val < -unscaled_deadzone:
        val += unscaled_deadzone
    else:
        val = 0.0
    return val * (-1.0 / (1.0 - deadzone) / 32767.0)


class JoystickState:
    """Axes and buttons of a joystick, updated from events.

    Arrays grow to the highest axis/button number seen (a FIFO or recorded file
    cannot answer the JSIOCGAXES/JSIOCGBUTTONS ioctls a real device does).
    """

    def __init__(self, deadzone=0.05, n_axes=0, n_buttons=0, sticky_buttons=False):
        self.deadzone = check_deadzone(deadzone)
        self.axes = [0.0] * n_axes
        self.buttons = [0] * n_buttons
        self.sticky_buttons = sticky_buttons

    def apply(self, ev):
        """Apply one event; True if the published state changed."""
        if ev.type == JS_EVENT_AXIS:
            if ev.number >= len(self.axes):
                self.axes.extend([0.0] * (ev.number + 1 - len(self.axes)))
            value = scale_axis(ev.value, self.deadzone)
            changed = self.axes[ev.number] != value
            self.axes[ev.number] = value
            return changed
        if ev.type == JS_EVENT_BUTTON:
            if ev.number >= len(self.buttons):
                self.buttons.extend([0] * (ev.number + 1 - len(self.buttons)))
            if self.sticky_buttons:
                if ev.value == 1 and not ev.init:  # toggle on press
                    self.buttons[ev.number] = 1 - self.buttons[ev.number]
                    return True
                return False
            value = 1 if ev.value else 0
            changed = self.buttons[ev.number] != value
            self.buttons[ev.number] = value
            return changed
        return False

    def release_all(self):
        """State published when the device disappears: sticks centred, buttons up."""
        self.axes = [0.0] * len(self.axes)
        self.buttons = [0] * len(self.buttons)


def coalesce(events, interval_ms):
    """Group events whose kernel times lie within interval_ms of the group's first event.

    joy coalesces events that arrive close together into one Joy message; doing it
    on the kernel timestamps gives the same grouping live and when replaying a file.
    """
    groups = []
    for ev in events:
        if groups and ev.time - groups[-1][0].time <= interval_ms:
            groups[-1].append(ev)
        else:
            groups.append([ev])
    return groups


LINEAR_FIELDS = ("x", "y", "z")
ANGULAR_FIELDS = ("yaw", "pitch", "roll")


def _field_map(name, value, fields, kind):
    """teleop_twist_joy accepts an int (the first field's axis) or a dict field -> value."""
    if isinstance(value, dict):
        out = {}
        for k, v in value.items():
            if k not in fields:
                raise ValueError("%s: unknown field %r (expected one of %s)" % (name, k, ", ".join(fields)))
            if isinstance(v, bool) or not isinstance(v, (int, float)) or (kind is int and int(v) != v):
                raise ValueError("%s.%s: must be %s, got %r" % (name, k, "an integer" if kind is int else "a number", v))
            if kind is int and v < 0:
                raise ValueError("%s.%s: axis index must be >= 0, got %r" % (name, k, v))
            if kind is float and not math.isfinite(v):
                raise ValueError("%s.%s: must be finite, got %r" % (name, k, v))
            out[k] = kind(v)
        return out
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError("%s: must be %s or a map of %s, got %r" % (name, kind.__name__, "/".join(fields), value))
    return _field_map(name, {fields[0]: value}, fields, kind)


class TwistJoy:
    """teleop_twist_joy's Joy -> Twist mapping.

    Defaults are the Cairo project's mapping: left stick Y -> linear.x in
    [-scale_linear.x, +scale_linear.x] (0.5 m/s), stick X -> angular.z in
    [-pi/2, +pi/2] rad/s. (Upstream's default angular scale is 0.5 rad/s.)
    """

    def __init__(self, enable_button=0, enable_turbo_button=-1, require_enable_button=True,
                 axis_linear=None, scale_linear=None, scale_linear_turbo=None,
                 axis_angular=None, scale_angular=None, scale_angular_turbo=None,
                 inverted_reverse=False):
        for name, b in (("enable_button", enable_button), ("enable_turbo_button", enable_turbo_button)):
            if isinstance(b, bool) or not isinstance(b, int) or b < -1:
                raise ValueError("%s: must be a button index >= 0 (or -1 for none), got %r" % (name, b))
        self.enable_button = enable_button
        self.enable_turbo_button = enable_turbo_button
        self.require_enable_button = require_enable_button
        self.inverted_reverse = inverted_reverse
        self.axis_linear = _field_map("axis_linear", {"x": 1} if axis_linear is None else axis_linear,
                                      LINEAR_FIELDS, int)
        self.axis_angular = _field_map("axis_angular", {"yaw": 0} if axis_angular is None else axis_angular,
                                       ANGULAR_FIELDS, int)
        self.scale = {}
        self.scale["linear", "normal"] = self._scales("scale_linear", scale_linear, {"x": 0.5},
                                                      self.axis_linear, LINEAR_FIELDS)
        self.scale["angular", "normal"] = self._scales("scale_angular", scale_angular, {"yaw": math.pi / 2},
                                                       self.axis_angular, ANGULAR_FIELDS)
        self.scale["linear", "turbo"] = self._scales("scale_linear_turbo", scale_linear_turbo,
                                                     self.scale["linear", "normal"], self.axis_linear, LINEAR_FIELDS)
        self.scale["angular", "turbo"] = self._scales("scale_angular_turbo", scale_angular_turbo,
                                                      self.scale["angular", "normal"], self.axis_angular,
                                                      ANGULAR_FIELDS)
        self.sent_disable_msg = False

    @staticmethod
    def _scales(name, value, fallback, axes, fields):
        given = {} if value is None else _field_map(name, value, fields, float)
        kind = "linear" if fields is LINEAR_FIELDS else "angular"
        for k in given:  # a scale without an axis is a typo worth reporting
            if k not in axes:
                raise ValueError("%s.%s: no axis mapped for this field (add it to axis_%s)" % (name, k, kind))
        out = {}
        for k in axes:
            if k in given:
                out[k] = given[k]
            elif k in fallback:
                out[k] = fallback[k]
            else:
                raise ValueError("%s.%s: axis_%s.%s is mapped but has no scale" % (name, k, kind, k))
        return out

    def _value(self, axes, kind, which, field):
        amap = self.axis_linear if kind == "linear" else self.axis_angular
        if field not in amap or amap[field] >= len(axes):
            return 0.0
        return axes[amap[field]] * self.scale[kind, which].get(field, 0.0)

    def _pressed(self, buttons, idx):
        return 0 <= idx < len(buttons) and bool(buttons[idx])

    def process(self, axes, buttons):
        """Twist for one Joy message as (lx, ly, lz, ax, ay, az), or None to publish nothing."""
        if self.enable_turbo_button >= 0 and self._pressed(buttons, self.enable_turbo_button):
            which = "turbo"
        elif not self.require_enable_button or self._pressed(buttons, self.enable_button):
            which = "normal"
        else:
            # Deadman released: exactly one zero twist, then silence so other sources can drive.
            if self.sent_disable_msg:
                return None
            self.sent_disable_msg = True
            return (0.0,) * 6
        lx, ly, lz = (self._value(axes, "linear", which, f) for f in LINEAR_FIELDS)
        az, ay, ax = (self._value(axes, "angular", which, f) for f in ANGULAR_FIELDS)
        if self.inverted_reverse and lx < 0:
            az = -az
        self.sent_disable_msg = False
        return (lx, ly, lz, ax, ay, az)
