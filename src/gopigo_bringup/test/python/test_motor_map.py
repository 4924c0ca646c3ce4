import pytest

from gopigo_bringup.motor_map import MotorMap, MotorMapError


@pytest.fixture
def mm():
    return MotorMap(motor_min_angular_vel=1.28, motor_max_angular_vel=5.32, motor_cmd_min=110, motor_cmd_max=255)


def test_zero_maps_to_zero(mm):
    assert mm.command(0.0) == 0
    assert mm.command(-0.0) == 0


def test_calibration_points_are_hit(mm):
    assert mm.command(1.28) == 110
    assert mm.command(5.32) == 255
    assert mm.command(-1.28) == -110
    assert mm.command(-5.32) == -255


def test_below_dead_band_gets_minimum_command_with_sign(mm):
    assert mm.command(0.01) == 110
    assert mm.command(1.0) == 110
    assert mm.command(-0.5) == -110


def test_above_maximum_is_clamped(mm):
    assert mm.command(6.0) == 255
    assert mm.command(1e6) == 255
    assert mm.command(-100.0) == -255


def test_linear_between_points_and_odd(mm):
    mid = (1.28 + 5.32) / 2
    assert mm.command(mid) == round((110 + 255) / 2)
    for w in (1.5, 2.0, 3.3, 4.9):
        assert mm.command(-w) == -mm.command(w)
        assert 110 <= mm.command(w) <= 255
    cmds = [mm.command(1.28 + 0.1 * i) for i in range(41)]
    assert cmds == sorted(cmds)


def test_non_finite_is_zero(mm):
    assert mm.command(float("nan")) == 0
    assert mm.command(float("inf")) == 0


def test_inverse_on_linear_part(mm):
    for w in (1.5, 3.0, 5.0):
        assert mm.angular_vel(mm.slope * w + mm.intercept) == pytest.approx(w)
    assert mm.angular_vel(50) == 0.0
    assert mm.angular_vel(-300) == pytest.approx(-5.32)


@pytest.mark.parametrize("kwargs, word", [
    (dict(motor_min_angular_vel=0.0), "motor_min_angular_vel"),
    (dict(motor_min_angular_vel=5.0, motor_max_angular_vel=4.0), "motor_max_angular_vel"),
    (dict(motor_cmd_min=200, motor_cmd_max=100), "motor_cmd_max"),
    (dict(motor_cmd_min=-1), "motor_cmd_min"),
    (dict(motor_max_angular_vel=float("nan")), "motor_max_angular_vel"),
])
def test_bad_parameters_name_the_parameter(kwargs, word):
    with pytest.raises(MotorMapError, match=word):
        MotorMap(**kwargs)
