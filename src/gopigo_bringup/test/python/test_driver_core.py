import threading

import pytest

from gopigo_bringup.backends import Backend, BackendError, SimBackend
from gopigo_bringup.driver import LEFT, RIGHT, DriverCore
from gopigo_bringup.motor_map import MotorMap


class RecordingBackend(Backend):
    name = "rec"

    def __init__(self):
        self.writes, self.stops, self.closed = [], 0, False
        self.pos = (0.0, 0.0)
        self.fail = False

    def write(self, left, right, t):
        self.writes.append((left, right, t))

    def stop(self, t):
        self.stops += 1

    def read_positions(self, t):
        if self.fail:
            raise BackendError("read failed")
        return self.pos

    def close(self):
        self.closed = True


def test_no_command_no_motion():
    b = RecordingBackend()
    core = DriverCore(b)
    core.step(0.0)
    assert b.writes == [] and core.stopped


def test_both_wheels_needed_and_fresh():
    b = RecordingBackend()
    core = DriverCore(b, cmd_timeout=0.5)
    core.command(LEFT, 2.0, 1.0)
    core.step(1.0)
    assert b.writes == []            # right wheel never commanded
    core.command(RIGHT, -2.0, 1.0)
    core.step(1.02)
    assert b.writes[-1] == (2.0, -2.0, 1.02) and not core.stopped


def test_timeout_stops_within_cmd_timeout():
    b = RecordingBackend()
    core = DriverCore(b, cmd_timeout=0.5)
    core.command(LEFT, 2.0, 10.0)
    core.command(RIGHT, 2.0, 10.0)
    t = 10.0
    while not core.stopped or t == 10.0:
        core.step(t)
        t = round(t + 0.05, 6)
        assert t < 11.0
    assert t - 0.05 - 10.0 <= 0.55 and b.writes[-1][2] <= 10.5
    n = len(b.writes)
    core.step(t + 1.0)
    assert len(b.writes) == n       # stays stopped, stop re-sent
    assert b.stops >= 2


def test_a_stop_is_written_on_receipt_other_commands_in_the_loop():
    b = RecordingBackend()
    core = DriverCore(b, cmd_timeout=0.5)
    core.command(LEFT, 2.0, 1.0)
    core.command(RIGHT, 2.0, 1.0)
    assert b.writes == []                        # driving waits for the loop
    core.step(1.0)
    core.command(LEFT, 1.0, 1.02)
    core.command(RIGHT, 1.0, 1.02)
    assert b.writes == [(2.0, 2.0, 1.0)]         # so does slowing down
    core.command(LEFT, 0.0, 1.03)                # a wheel stopping is written at once
    assert b.writes[-1] == (0.0, 1.0, 1.03) and core.stops_written == 1
    core.command(RIGHT, 0.0, 1.03)               # the other in the same instant (simulated time) too
    assert b.writes[-1] == (0.0, 0.0, 1.03) and core.stops_written == 2
    core.command(RIGHT, 0.0, 1.05)               # already zero: nothing new to write
    assert len(b.writes) == 3 and core.stops_written == 2


def test_a_zero_while_stopped_or_stale_drives_nothing():
    b = RecordingBackend()
    core = DriverCore(b, cmd_timeout=0.5)
    core.command(LEFT, 2.0, 1.0)
    core.command(LEFT, 0.0, 1.0)                 # never driven: stays stopped
    assert b.writes == [] and core.stopped and core.stops_written == 0
    core.command(RIGHT, 2.0, 1.0)
    core.command(LEFT, 2.0, 1.0)
    core.step(1.0)
    core.command(LEFT, 0.0, 2.0)                 # the right wheel's command is stale by now
    assert b.writes == [(2.0, 2.0, 1.0)] and core.stopped and "no command" in core.stop_reason


def test_messages_are_logged_with_the_lock_released():
    """A log call may block (rospy asks the master for a parameter): the lock must be free then."""
    logged = []

    def log(level, msg):
        free = []
        t = threading.Thread(target=lambda: free.append(core.lock.acquire(blocking=False) and not core.lock.release()))
        t.start()
        t.join()
        logged.append((msg, free[0]))

    b = RecordingBackend()
    core = DriverCore(b, cmd_timeout=0.5, log=log)
    core.command(LEFT, 2.0, 1.0)
    core.command(RIGHT, 2.0, 1.0)
    core.step(1.0)                 # "motors driven"
    core.step(2.0)                 # stale: "motors stopped"
    core.inhibit("master lost", 2.1)
    core.release()
    b.fail = True
    core.step(2.2)                 # a read failure is logged too
    assert [m for m, _ in logged] == ["motors driven (commands fresh)", "motors stopped: no command for 0.50 s",
                                      "stopping motors: master lost", "commands accepted again (was: master lost)",
                                      "read failed"]
    assert all(free for _, free in logged), logged


def test_one_stale_wheel_stops_both():
    b = RecordingBackend()
    core = DriverCore(b, cmd_timeout=0.5)
    for k in range(20):
        t = 0.1 * k
        core.command(LEFT, 1.0, t)
        if k < 5:
            core.command(RIGHT, 1.0, t)
        core.step(t)
    assert core.stopped and "no command" in core.stop_reason


def test_time_going_backwards_stops():
    b = RecordingBackend()
    core = DriverCore(b)
    core.command(LEFT, 1.0, 5.0)
    core.command(RIGHT, 1.0, 5.0)
    core.step(5.1)
    assert not core.stopped
    core.step(0.1)
    assert core.stopped


def test_inhibit_refuses_commands_until_release():
    b = RecordingBackend()
    core = DriverCore(b)
    core.command(LEFT, 1.0, 0.0)
    core.command(RIGHT, 1.0, 0.0)
    core.step(0.0)
    core.inhibit("master lost", 0.1)
    assert core.stopped
    core.command(LEFT, 1.0, 0.2)
    core.command(RIGHT, 1.0, 0.2)
    n = len(b.writes)
    core.step(0.2)
    assert len(b.writes) == n
    core.release()
    core.step(0.25)
    assert len(b.writes) == n + 1


def test_non_finite_command_rejected():
    core = DriverCore(RecordingBackend())
    assert not core.command(LEFT, float("nan"), 0.0)


def test_read_failure_skips_cycle_but_keeps_driving():
    b = RecordingBackend()
    core = DriverCore(b)
    core.command(LEFT, 1.0, 0.0)
    core.command(RIGHT, 1.0, 0.0)
    b.fail = True
    assert core.step(0.0) is None
    assert b.writes


def test_shutdown_closes_and_never_drives_again():
    b = RecordingBackend()
    core = DriverCore(b)
    core.command(LEFT, 1.0, 0.0)
    core.command(RIGHT, 1.0, 0.0)
    core.shutdown()
    core.shutdown()
    assert b.closed
    n = len(b.writes)
    core.step(0.01)
    assert len(b.writes) == n


def test_joint_velocity_from_sim_backend():
    b = SimBackend.from_params(MotorMap(), time_constant=0.02)
    core = DriverCore(b, velocity_window=0.2)
    t, samples = 0.0, []
    while t < 3.0:
        core.command(LEFT, 3.0, t)
        core.command(RIGHT, -2.0, t)
        state = core.step(t)
        if t > 1.0:
            samples.append(state.velocities)
        t += 0.05
    for wheel, target in ((0, 3.0), (1, -2.0)):
        values = [v[wheel] for v in samples]
        assert sum(values) / len(values) == pytest.approx(target, rel=0.01)
        assert all(v == pytest.approx(target, rel=0.05) for v in values)


def test_invalid_timeout():
    with pytest.raises(ValueError, match="cmd_timeout"):
        DriverCore(RecordingBackend(), cmd_timeout=0.0)


def test_deadline_is_oldest_command_plus_timeout():
    core = DriverCore(RecordingBackend(), cmd_timeout=0.5)
    assert core.deadline() is None
    core.command(LEFT, 1.0, 1.0)
    core.command(RIGHT, 1.0, 1.2)
    core.step(1.2)
    assert core.deadline() == pytest.approx(1.5)
    core.step(1.5001)
    assert core.stopped and core.deadline() is None
