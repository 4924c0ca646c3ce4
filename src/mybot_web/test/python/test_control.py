import pytest

from mybot_web.control import DriveArbiter, scale_command
from mybot_web.protocol import Drive


class FakeClock:
    """ROS time stand-in: only advances when told to."""

    def __init__(self, t=100.0):
        self.t = t

    def advance(self, dt):
        self.t += dt
        return self.t


def test_deadman_zeroes_once_after_timeout():
    clock = FakeClock()
    a = DriveArbiter(0.3)
    # A page streaming at 20 Hz keeps the output alive.
    for _ in range(10):
        assert a.command(1, clock.t) is None
        clock.advance(0.05)
        assert not a.check(clock.t)
    clock.advance(0.25)  # 0.30 s since the last command: still fresh (inclusive bound)
    assert not a.check(clock.t)
    clock.advance(0.02)
    assert a.check(clock.t)  # stale: zero exactly once
    assert not a.check(clock.advance(1.0))
    assert not a.driving


def test_release_zeroes_only_for_the_owner():
    a = DriveArbiter(0.3)
    a.command(1, 0.0)
    assert not a.release(2)
    assert a.release(1)
    assert not a.release(1)  # already released
    assert not a.check(10.0)


def test_second_client_is_refused_while_the_first_drives():
    clock = FakeClock()
    a = DriveArbiter(0.3)
    assert a.command(1, clock.t) is None
    assert a.command(2, clock.advance(0.1)) == "another client is driving"
    assert a.owner == 1
    # Once the first goes silent the second may take over.
    assert a.command(2, clock.advance(0.4)) is None
    assert a.owner == 2


def test_time_going_backwards_counts_as_stale():
    a = DriveArbiter(0.3)
    a.command(1, 50.0)
    assert a.check(10.0)  # simulator reset: /clock jumped back


def test_timeout_must_be_positive():
    with pytest.raises(ValueError):
        DriveArbiter(0.0)


def test_scale_command():
    assert scale_command(Drive(1.0, 0.5, -0.5), 0.4, 2.0, holonomic=True) == (0.4, 0.2, -1.0)
    # A differential robot never gets a sideways command.
    assert scale_command(Drive(1.0, 0.5, -0.5), 0.4, 2.0, holonomic=False) == (0.4, 0.0, -1.0)
