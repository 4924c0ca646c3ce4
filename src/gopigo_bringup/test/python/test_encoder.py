import math

import pytest

from gopigo_bringup.encoder import (DirectionalPulseCounter, EncoderUnwrapper, VelocityEstimator,
                                    counts_to_radians)


def test_unwrapper_forward_across_wrap():
    u = EncoderUnwrapper(65536)
    assert u.update(65530) == 0
    assert u.update(65535) == 5
    assert u.update(3) == 9          # wrapped: 65535 -> 0 -> 3
    assert u.update(10) == 16


def test_unwrapper_backward_across_wrap():
    u = EncoderUnwrapper(65536)
    u.update(2)
    assert u.update(65534) == -4
    assert u.update(65500) == -38


def test_unwrapper_signed_32bit_degrees():
    mod = round(2 ** 32 / (120.0 * 16.0 / 360.0))
    top = mod // 2 - 1
    u = EncoderUnwrapper(mod)
    u.update(top - 10)
    assert u.update(top) == 10
    assert u.update(top + 20 - mod) == 30   # jumped to the negative end


def test_directional_counter_sign_from_command():
    c = DirectionalPulseCounter()
    c.update(100, 1)
    assert c.update(118, 1) == 18
    assert c.update(127, -1) == 9          # pulses keep counting up; direction from the command
    assert c.update(65535, -1) == 9 - (65535 - 127)


def test_directional_counter_wraps_unsigned_16bit():
    c = DirectionalPulseCounter()
    c.update(65530, 1)
    assert c.update(4, 1) == 10


def test_directional_counter_coasting_keeps_last_direction():
    c = DirectionalPulseCounter()
    c.update(0, -1)
    c.update(5, -1)
    assert c.update(7, 0) == -7


def test_counts_to_radians():
    assert counts_to_radians(18, 18) == pytest.approx(2 * math.pi)
    assert counts_to_radians(-90, 360) == pytest.approx(-math.pi / 2)


def test_velocity_estimator_window_and_time_reset():
    v = VelocityEstimator(0.1)
    assert v.update(0.0, 0.0) == 0.0
    for i in range(1, 11):
        w = v.update(0.02 * i, 2.0 * 0.02 * i)
    assert w == pytest.approx(2.0)
    # clock went back (sim reset): no bogus huge speed
    assert v.update(0.01, 0.0) == 0.0
    assert v.update(0.03, 0.1) == pytest.approx(5.0)


def test_bad_arguments():
    with pytest.raises(ValueError):
        EncoderUnwrapper(0)
    with pytest.raises(ValueError):
        VelocityEstimator(-1)
