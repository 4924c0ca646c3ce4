import math

import pytest

from gopigo_bringup.sim_motor import SimMotor


def run(m, cmd, seconds, t0=0.0, dt=0.02):
    m.advance(t0)
    m.set_command(cmd, t0)
    t = t0
    while t < t0 + seconds - 1e-9:
        t += dt
        m.advance(t)
    return t


def test_dead_band_no_motion():
    m = SimMotor(deadband=64.0, rad_per_cmd=0.03, time_constant=0.1)
    run(m, 60, 2.0)
    assert m.velocity == 0.0 and m.position == 0.0


def test_first_order_response():
    m = SimMotor(deadband=50.0, rad_per_cmd=0.02, time_constant=0.2)
    run(m, 150, 0.2)
    ss = 0.02 * 100
    assert m.velocity == pytest.approx(ss * (1 - math.exp(-1)), rel=1e-3)
    run(m, 150, 2.0, t0=0.2)
    assert m.velocity == pytest.approx(ss, rel=1e-3)


def test_gain_and_sign():
    strong = SimMotor(50.0, 0.02, gain=1.0, time_constant=0.0)
    weak = SimMotor(50.0, 0.02, gain=0.8, time_constant=0.0)
    run(strong, -150, 1.0)
    run(weak, -150, 1.0)
    assert strong.velocity == pytest.approx(-2.0)
    assert weak.velocity == pytest.approx(-1.6)
    assert weak.position == pytest.approx(0.8 * strong.position)


def test_encoder_quantisation():
    m = SimMotor(0.0, 1.0, time_constant=0.0, counts_per_rev=18)
    m.position = 2 * math.pi * (5.5 / 18)
    assert m.encoder_count() == 5
    m.position = -2 * math.pi * (0.5 / 18)
    assert m.encoder_count() == -1


def test_noise_is_seeded():
    a = SimMotor(0.0, 0.02, noise_std=0.2, seed=7)
    b = SimMotor(0.0, 0.02, noise_std=0.2, seed=7)
    run(a, 100, 1.0)
    run(b, 100, 1.0)
    assert a.position == b.position and a.velocity != pytest.approx(2.0, abs=1e-9)


def test_time_going_back_does_not_integrate():
    m = SimMotor(0.0, 0.02, time_constant=0.0)
    run(m, 100, 1.0)
    p = m.position
    m.advance(0.5)
    assert m.position == p


def test_invalid_parameters():
    with pytest.raises(ValueError, match="time_constant"):
        SimMotor(0.0, 1.0, time_constant=-1.0)
    with pytest.raises(ValueError, match="counts_per_rev"):
        SimMotor(0.0, 1.0, counts_per_rev=0)
