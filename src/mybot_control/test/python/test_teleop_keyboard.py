import pytest

from mybot_control import teleop_keyboard as tk


def test_key_map_matches_teleop_twist_keyboard():
    assert tk.MOVE_BINDINGS["i"] == (1, 0, 0, 0)
    assert tk.MOVE_BINDINGS["o"] == (1, 0, 0, -1)
    assert tk.MOVE_BINDINGS["j"] == (0, 0, 0, 1)
    assert tk.MOVE_BINDINGS["l"] == (0, 0, 0, -1)
    assert tk.MOVE_BINDINGS["u"] == (1, 0, 0, 1)
    assert tk.MOVE_BINDINGS[","] == (-1, 0, 0, 0)
    assert tk.MOVE_BINDINGS["."] == (-1, 0, 0, 1)
    assert tk.MOVE_BINDINGS["m"] == (-1, 0, 0, -1)
    # shifted keys strafe (holonomic)
    assert tk.MOVE_BINDINGS["J"] == (0, 1, 0, 0)
    assert tk.MOVE_BINDINGS["L"] == (0, -1, 0, 0)
    assert tk.MOVE_BINDINGS["U"] == (1, 1, 0, 0)
    assert tk.MOVE_BINDINGS["O"] == (1, -1, 0, 0)
    assert tk.MOVE_BINDINGS["M"] == (-1, 1, 0, 0)
    assert tk.MOVE_BINDINGS[">"] == (-1, -1, 0, 0)
    assert tk.MOVE_BINDINGS["<"] == (-1, 0, 0, 0)
    assert tk.MOVE_BINDINGS["t"] == (0, 0, 1, 0) and tk.MOVE_BINDINGS["b"] == (0, 0, -1, 0)
    assert len(tk.MOVE_BINDINGS) == 18
    assert tk.SPEED_BINDINGS == {"q": (1.1, 1.1), "z": (.9, .9), "w": (1.1, 1), "x": (.9, 1),
                                 "e": (1, 1.1), "c": (1, .9)}
    assert "For Holonomic mode (strafing), hold down the shift key:" in tk.MSG
    assert tk.vels(0.5, 1.0) == "currently:\tspeed 0.5\tturn 1.0 "


def test_moves_scale_with_speed_and_turn():
    t = tk.KeyboardTeleop()
    assert t.handle_key("u") == (True, [])
    assert t.twist() == (0.5, 0.0, 0.0, 1.0)
    t.handle_key("J")
    assert t.twist() == (0.0, 0.5, 0.0, 0.0)
    t.handle_key("m")
    assert t.twist() == (-0.5, 0.0, 0.0, -1.0)


def test_speed_steps_print_and_apply():
    t = tk.KeyboardTeleop()
    t.handle_key("i")
    changed, lines = t.handle_key("q")
    assert changed and lines == [tk.vels(0.5 * 1.1, 1.0 * 1.1)]
    assert t.twist()[0] == pytest.approx(0.55)  # still moving, at the new speed
    t.handle_key("x")
    assert t.speed == pytest.approx(0.495) and t.turn == pytest.approx(1.1)
    t.handle_key("c")
    assert t.turn == pytest.approx(0.99)


def test_help_reprinted_every_15_speed_changes():
    t = tk.KeyboardTeleop()
    outputs = [t.handle_key("e")[1] for _ in range(15)]
    assert all(tk.MSG not in o for o in outputs[:14])
    assert tk.MSG in outputs[14]


def test_speed_limit():
    t = tk.KeyboardTeleop(speed=0.95, speed_limit=1.0)
    _, lines = t.handle_key("w")
    assert t.speed == 1.0 and "Linear speed limit reached!" in lines


def test_other_key_stops_and_timeout_only_when_moving():
    t = tk.KeyboardTeleop()
    assert t.handle_key(tk.TIMEOUT) == (False, [])  # stopped: nothing to send
    t.handle_key("i")
    assert t.handle_key(tk.TIMEOUT) == (True, [])
    assert t.twist() == (0.0, 0.0, 0.0, 0.0)
    t.handle_key("i")
    t.handle_key("k")
    assert t.twist() == (0.0, 0.0, 0.0, 0.0) and not t.done
    t.handle_key(tk.CTRL_C)
    assert t.done
