import math

import pytest

from mybot_control import timed_moves as tm
from mybot_common.params import ParamError


def test_forward_duration_and_direction():
    (seg,) = tm.forward(0.5, 0.1)
    assert seg.twist == (0.1, 0.0, 0.0) and seg.duration == pytest.approx(5.0)
    (back,) = tm.forward(-0.2, 0.1)
    assert back.twist == (-0.1, 0.0, 0.0) and back.duration == pytest.approx(2.0)


def test_rotate():
    (seg,) = tm.rotate(-math.pi / 2, 0.5)
    assert seg.twist == (0.0, 0.0, -0.5) and seg.duration == pytest.approx(math.pi)


def test_square_profile_and_lookup():
    p = tm.square(1.0, 0.2, 0.5, pause=0.5)
    names = [s.name for s in p]
    assert names[:4] == ["side 1", "pause", "turn 1", "pause"] and names[-1] == "turn 4"
    assert sum(1 for s in p if s.name.startswith("side")) == 4
    total = 4 * 5.0 + 4 * math.pi + 7 * 0.5
    assert tm.total_duration(p) == pytest.approx(total)
    assert tm.command_at(p, 0.0) == (0, (0.2, 0.0, 0.0))
    assert tm.command_at(p, 5.2) == (1, tm.ZERO)
    assert tm.command_at(p, 5.6)[1] == (0.0, 0.0, 0.5)
    assert tm.command_at(p, total + 1e-9) == (None, tm.ZERO)
    assert tm.command_at(p, -1.0) == (None, tm.ZERO)
    assert tm.next_boundary(p, 0.0) == pytest.approx(5.0)
    assert tm.next_boundary(p, total) == math.inf


def test_constant_runs_forever():
    p = tm.build("custom", 0.1, 0.5, 0.5, 1.0, 0.5, 0.0, False, 0.2, 0.0, 0.3, 0.0)
    assert tm.command_at(p, 1e9) == (0, (0.2, 0.0, 0.3))


@pytest.mark.parametrize("args, name", [
    (("forward", 0.0, 0.5, 0.5, 1.0, 0.5, 0.0, False, 0, 0, 0, 0), "~linear_speed"),
    (("rotate", 0.1, -1.0, 0.5, 1.0, 0.5, 0.0, False, 0, 0, 0, 0), "~angular_speed"),
    (("square", 0.1, 0.5, 0.5, 1.0, -1.0, 0.0, False, 0, 0, 0, 0), "~side"),
    (("square", 0.1, 0.5, 0.5, 1.0, 1.0, -0.5, False, 0, 0, 0, 0), "~pause"),
    (("spiral", 0.1, 0.5, 0.5, 1.0, 1.0, 0.0, False, 0, 0, 0, 0), "~mode"),
    (("forward", 0.1, 0.5, float("inf"), 1.0, 1.0, 0.0, False, 0, 0, 0, 0), "~distance"),
])
def test_bad_parameters_are_named(args, name):
    with pytest.raises(ParamError) as e:
        tm.build(*args)
    assert e.value.name == name and name in str(e.value)
