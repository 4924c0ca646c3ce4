import math

import pytest

from fakes import FakeGoPiGo3, make_fake_gopigo
from gopigo_bringup.backends import BackendError, GoPiGo3Backend, GoPiGoBackend, SimBackend
from gopigo_bringup.motor_map import MotorMap

MM = MotorMap()


# ---- GoPiGo v1/v2 ---------------------------------------------------------
def test_gopigo_left_is_motor1_right_is_motor2():
    g = make_fake_gopigo()
    b = GoPiGoBackend(g, MM)
    g.calls.clear()
    b.write(5.32, -1.28, 0.0)
    assert g.calls == [("motor1", 1, 255), ("motor2", 0, 110)]


def test_gopigo_enables_board_watchdog():
    g = make_fake_gopigo()
    GoPiGoBackend(g, MM, board_timeout=0.8)
    assert ("enable_com_timeout", 800) in g.calls


def test_gopigo_encoders_left_is_enc0_and_in_radians():
    g = make_fake_gopigo()
    b = GoPiGoBackend(g, MM)
    g.raw = [1000, 5000]
    assert b.read_positions(0.0) == (0.0, 0.0)
    b.write(3.0, 3.0, 0.0)
    g.raw = [1018, 5009]              # left one full turn (18 pulses), right half a turn
    left, right = b.read_positions(0.1)
    assert left == pytest.approx(2 * math.pi)
    assert right == pytest.approx(math.pi)


def test_gopigo_encoder_direction_and_wrap():
    g = make_fake_gopigo()
    b = GoPiGoBackend(g, MM)
    g.raw = [65530, 65530]
    b.read_positions(0.0)
    b.write(-3.0, 3.0, 0.0)
    g.raw = [65530 + 9, 65530 + 9]     # fake wraps at 2^16 on read
    left, right = b.read_positions(0.1)
    assert left == pytest.approx(-math.pi)
    assert right == pytest.approx(math.pi)


def test_gopigo_read_error_raises_backend_error():
    g = make_fake_gopigo()
    b = GoPiGoBackend(g, MM)
    g.fail_reads = True
    with pytest.raises(BackendError, match="enc_read"):
        b.read_positions(0.0)


def test_gopigo_stop_and_close():
    g = make_fake_gopigo()
    b = GoPiGoBackend(g, MM)
    b.write(3.0, 3.0, 0.0)
    g.calls.clear()
    b.close()
    assert ("motor1", 1, 0) in g.calls and ("motor2", 1, 0) in g.calls and ("stop",) in g.calls
    assert b.battery_voltage() == pytest.approx(9.1)
    g.voltage = -1
    assert b.battery_voltage() is None


# ---- GoPiGo3 --------------------------------------------------------------
def test_gopigo3_dps_per_port_and_clamp():
    board = FakeGoPiGo3()
    b = GoPiGo3Backend(board, max_dps=500)
    b.write(math.radians(90), -100.0, 0.0)
    assert board.dps[board.MOTOR_LEFT] == 90
    assert board.dps[board.MOTOR_RIGHT] == -500
    b.write(float("nan"), 0.0, 0.0)
    assert board.dps[board.MOTOR_LEFT] == 0


def test_gopigo3_encoder_degrees_to_radians_per_wheel():
    board = FakeGoPiGo3()
    b = GoPiGo3Backend(board)
    tpd = board.MOTOR_TICKS_PER_DEGREE
    board.set_ticks(board.MOTOR_LEFT, int(100 * tpd))
    board.set_ticks(board.MOTOR_RIGHT, int(-50 * tpd))
    b.read_positions(0.0)
    board.set_ticks(board.MOTOR_LEFT, int(460 * tpd))
    board.set_ticks(board.MOTOR_RIGHT, int(-230 * tpd))
    left, right = b.read_positions(0.1)
    assert left == pytest.approx(2 * math.pi)
    assert right == pytest.approx(-math.pi)


def test_gopigo3_encoder_wraps_at_32_bit_ticks():
    board = FakeGoPiGo3()
    b = GoPiGo3Backend(board)
    tpd = board.MOTOR_TICKS_PER_DEGREE
    start = 2 ** 31 - int(10 * tpd)
    board.set_ticks(board.MOTOR_LEFT, start)
    b.read_positions(0.0)
    board.set_ticks(board.MOTOR_LEFT, start + int(30 * tpd))   # crosses +2^31 -> negative
    assert board.get_motor_encoder(board.MOTOR_LEFT) < 0
    left, _ = b.read_positions(0.1)
    assert math.degrees(left) == pytest.approx(30, abs=1.5)


def test_gopigo3_stop_and_close_float_motors():
    board = FakeGoPiGo3()
    b = GoPiGo3Backend(board)
    b.write(1.0, 1.0, 0.0)
    b.stop(0.0)
    assert board.dps == {board.MOTOR_LEFT: 0, board.MOTOR_RIGHT: 0}
    b.close()
    assert board.power[board.MOTOR_LEFT] == board.MOTOR_FLOAT
    assert b.battery_voltage() == pytest.approx(11.1)


# ---- simulated ------------------------------------------------------------
def run_sim(b, left, right, seconds, dt=0.02):
    t = 0.0
    b.read_positions(t)
    while t < seconds - 1e-9:
        b.write(left, right, t)
        t += dt
        pos = b.read_positions(t)
    return pos


def test_sim_open_loop_matches_the_motor_map():
    b = SimBackend.from_params(MM, time_constant=0.05)
    run_sim(b, 3.0, -3.0, 2.0)
    _, (vl, vr) = b.true_state()
    assert vl == pytest.approx(3.0, rel=0.01)
    assert vr == pytest.approx(-3.0, rel=0.01)


def test_sim_weak_left_motor_and_quantised_encoder():
    b = SimBackend.from_params(MM, left_gain=0.8, counts_per_rev=18)
    pos = run_sim(b, 3.0, 3.0, 2.0)
    (pl, pr), (vl, vr) = b.true_state()
    assert vl == pytest.approx(0.8 * vr, rel=0.02)
    step = 2 * math.pi / 18
    for p, true in zip(pos, (pl, pr)):
        assert abs(p / step - round(p / step)) < 1e-9
        assert 0 <= true - p < step


def test_sim_below_deadband_motor_does_not_turn():
    b = SimBackend.from_params(MM, deadband=150.0)
    run_sim(b, 1.0, 1.0, 1.0)   # maps to 110 < 150
    assert b.true_state()[1] == (0.0, 0.0)
