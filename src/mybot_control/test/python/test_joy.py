import math

import pytest

from mybot_control import joy

# Recorded from a gamepad (8 bytes per js_event): init burst, deadman (button 4)
# press, left stick forward, release.
RECORDED = bytes.fromhex(
    "10270000" "0000" "81" "00"
    "10270000" "0000" "81" "04"
    "10270000" "0000" "82" "00"
    "10270000" "0000" "82" "01"
    "a0270000" "0100" "01" "04"
    "d0270000" "0180" "02" "01"
    "00280000" "0000" "01" "04")


def test_decode_recorded_bytes():
    events, rest = joy.decode_events(RECORDED + b"\x01\x02")
    assert rest == b"\x01\x02"
    assert len(events) == 7
    assert events[0] == joy.JsEvent(10000, 0, joy.JS_EVENT_BUTTON, 0, True)
    assert events[3] == joy.JsEvent(10000, 0, joy.JS_EVENT_AXIS, 1, True)
    assert events[4] == joy.JsEvent(10144, 1, joy.JS_EVENT_BUTTON, 4, False)
    assert events[5] == joy.JsEvent(10192, -32767, joy.JS_EVENT_AXIS, 1, False)


def test_encode_decode_round_trip():
    b = joy.encode_event(123456, -1234, joy.JS_EVENT_AXIS, 3, init=True)
    assert len(b) == 8
    assert joy.decode_events(b)[0] == [joy.JsEvent(123456, -1234, joy.JS_EVENT_AXIS, 3, True)]


def test_axis_scaling_like_joy():
    assert joy.scale_axis(-32767, 0.0) == pytest.approx(1.0)  # sign flipped: stick up is +
    assert joy.scale_axis(32767, 0.05) == pytest.approx(-1.0)  # full range kept with a deadzone
    assert joy.scale_axis(1000, 0.05) == 0.0                   # inside the deadzone
    half = joy.scale_axis(-16384, 0.05)
    assert half == pytest.approx((16384 - 0.05 * 32767) / (0.95 * 32767))
    with pytest.raises(ValueError):
        joy.check_deadzone(0.95)
    with pytest.raises(ValueError):
        joy.check_deadzone(-0.1)


def test_state_grows_and_coalesces():
    events, _ = joy.decode_events(RECORDED)
    groups = joy.coalesce(events, 1.0)
    assert [len(g) for g in groups] == [4, 1, 1, 1]
    s = joy.JoystickState(deadzone=0.05)
    published = []
    for g in groups:
        if any([s.apply(e) for e in g]) or not published:
            published.append((list(s.axes), list(s.buttons)))
    assert published[0] == ([0.0, 0.0], [0, 0, 0, 0, 0])
    assert published[1][1][4] == 1
    assert published[2][0][1] == pytest.approx(1.0)
    assert published[3][1][4] == 0
    s.release_all()
    assert s.axes == [0.0, 0.0] and s.buttons == [0] * 5


def test_sticky_buttons_toggle():
    s = joy.JoystickState(sticky_buttons=True)
    press = joy.JsEvent(1, 1, joy.JS_EVENT_BUTTON, 2, False)
    release = joy.JsEvent(2, 0, joy.JS_EVENT_BUTTON, 2, False)
    assert s.apply(press) and s.buttons[2] == 1
    assert not s.apply(release) and s.buttons[2] == 1
    assert s.apply(press) and s.buttons[2] == 0


def test_twist_joy_defaults_cairo_mapping_and_deadman():
    m = joy.TwistJoy()
    axes = [-1.0, 1.0]  # stick right, full forward
    assert m.process(axes, [1]) == pytest.approx((0.5, 0, 0, 0, 0, -math.pi / 2))
    assert m.process(axes, [0]) == (0.0,) * 6      # released: one zero twist
    assert m.process(axes, [0]) is None            # ... and only one
    assert m.process([0.0, 0.5], [1]) == pytest.approx((0.25, 0, 0, 0, 0, 0))


def test_twist_joy_turbo_holonomic_and_inverted_reverse():
    m = joy.TwistJoy(enable_button=4, enable_turbo_button=5,
                     axis_linear={"x": 1, "y": 3}, scale_linear={"x": 0.4, "y": 0.3},
                     scale_linear_turbo={"x": 1.0}, axis_angular=0, scale_angular={"yaw": 1.0},
                     inverted_reverse=True)
    axes = [0.5, -1.0, 0.0, 1.0]
    buttons = [0, 0, 0, 0, 1, 0]
    assert m.process(axes, buttons) == pytest.approx((-0.4, 0.3, 0, 0, 0, -0.5))
    buttons[5] = 1  # turbo wins even without the deadman; y falls back to the normal scale
    assert m.process(axes, [0, 0, 0, 0, 0, 1]) == pytest.approx((-1.0, 0.3, 0, 0, 0, -0.5))
    # short Joy messages: unmapped axes/buttons read as 0 / released
    assert m.process([], []) == (0.0,) * 6


def test_twist_joy_no_enable_required():
    m = joy.TwistJoy(require_enable_button=False)
    assert m.process([0.0, 1.0], []) == pytest.approx((0.5, 0, 0, 0, 0, 0))


@pytest.mark.parametrize("kwargs, name", [
    ({"axis_linear": {"w": 1}}, "axis_linear"),
    ({"axis_linear": {"x": -1}}, "axis_linear.x"),
    ({"axis_linear": {"x": 1, "y": 2}}, "scale_linear.y"),
    ({"scale_angular": {"pitch": 1.0}}, "scale_angular.pitch"),
    ({"enable_button": -2}, "enable_button"),
    ({"scale_linear": {"x": float("nan")}}, "scale_linear.x"),
])
def test_twist_joy_bad_config_names_parameter(kwargs, name):
    with pytest.raises(ValueError) as e:
        joy.TwistJoy(**kwargs)
    assert str(e.value).startswith(name)
