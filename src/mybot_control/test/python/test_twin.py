import math
import random

import pytest

from mybot_control.twin import TwinMapper, propose_deadband


def test_linear_speed_from_the_wheels_angular_from_the_gyro():
    t = TwinMapper(wheel_radius=0.033, deadband_dps=0.5)
    t.wheels(1.0, 10.0, 12.0)  # rad/s
    t.gyro(1.0, 30.0)          # deg/s
    v, w = t.twist(1.1)
    assert v == pytest.approx(0.033 * 11.0)
    assert w == pytest.approx(math.radians(30.0))


def test_dead_band_zeroes_a_gyro_at_rest_around_its_bias():
    t = TwinMapper(wheel_radius=0.033, deadband_dps=0.4, gyro_bias_dps=-0.7)
    t.wheels(0.0, 0.0, 0.0)
    for dps in (-0.7, -0.35, -1.05, -0.9):
        t.gyro(0.0, dps)
        assert t.twist(0.0) == (0.0, 0.0)
    t.gyro(0.0, 9.3)  # a real turn: 10 deg/s once the bias is removed
    assert t.twist(0.0)[1] == pytest.approx(math.radians(10.0))


def test_wheel_jitter_at_rest_is_zero():
    t = TwinMapper(wheel_radius=0.1, deadband_dps=0.5, wheel_deadband=0.02)
    t.wheels(0.0, 0.015, -0.01)
    t.gyro(0.0, 0.0)
    assert t.twist(0.0) == (0.0, 0.0)
    t.wheels(0.0, 0.5, 0.5)
    assert t.twist(0.0)[0] == pytest.approx(0.05)


def test_stale_input_stops_the_twin():
    t = TwinMapper(wheel_radius=0.1, deadband_dps=0.5, timeout=0.5)
    assert t.twist(0.0) == (0.0, 0.0)  # nothing yet
    t.wheels(1.0, 5.0, 5.0)
    t.gyro(1.0, 0.0)
    assert t.twist(1.4)[0] == pytest.approx(0.5)
    assert t.twist(1.6) == (0.0, 0.0)       # older than the timeout
    t.gyro(1.6, 0.0)
    assert t.twist(1.6) == (0.0, 0.0)       # the wheels are still stale


def test_time_going_back_makes_input_stale():
    t = TwinMapper(wheel_radius=0.1, deadband_dps=0.5)
    t.wheels(10.0, 5.0, 5.0)
    t.gyro(10.0, 0.0)
    assert t.twist(0.5) == (0.0, 0.0)  # a simulation reset: input from "the future" is not fresh


def test_non_finite_readings_are_ignored():
    t = TwinMapper(wheel_radius=0.1, deadband_dps=0.5)
    t.wheels(0.0, 1.0, 1.0)
    t.gyro(0.0, 0.0)
    t.wheels(0.1, float("nan"), 1.0)
    t.gyro(0.1, float("inf"))
    assert t.twist(0.2) == (pytest.approx(0.1), 0.0)


@pytest.mark.parametrize("kw, field", [
    (dict(wheel_radius=0.0, deadband_dps=0.5), "wheel_radius"),
    (dict(wheel_radius=float("nan"), deadband_dps=0.5), "wheel_radius"),
    (dict(wheel_radius=0.1, deadband_dps=-1.0), "gyro_deadband"),
    (dict(wheel_radius=0.1, deadband_dps=0.5, gyro_bias_dps=float("inf")), "gyro_bias"),
    (dict(wheel_radius=0.1, deadband_dps=0.5, timeout=0.0), "timeout"),
    (dict(wheel_radius=0.1, deadband_dps=0.5, wheel_deadband=-0.1), "wheel_deadband"),
])
def test_bad_parameters_are_named(kw, field):
    with pytest.raises(ValueError, match=field):
        TwinMapper(**kw)


def test_calibration_proposes_a_band_that_holds_the_twin_still():
    rng = random.Random(3)
    rest = [-0.6 + rng.gauss(0.0, 0.08) for _ in range(500)]  # an MPU6050 at rest
    bias, band = propose_deadband(rest)
    assert bias == pytest.approx(-0.6, abs=0.02)
    t = TwinMapper(wheel_radius=0.033, deadband_dps=band, gyro_bias_dps=bias)
    t.wheels(0.0, 0.0, 0.0)
    for dps in rest:
        t.gyro(0.0, dps)
        assert t.twist(0.0) == (0.0, 0.0)
    with pytest.raises(ValueError):
        propose_deadband([0.1] * 3)
