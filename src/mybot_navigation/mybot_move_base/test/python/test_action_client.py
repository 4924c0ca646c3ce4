"""The first transition of a goal reaches the callbacks even when the server answers before
send_goal has returned (ros/actionlib#206), replayed without ROS: a stand-in ActionClient
delivers the ACTIVE transition from another thread while send_goal is still running."""
import threading

import pytest
from actionlib import CommState, SimpleGoalState

from mybot_move_base.action_client import SimpleActionClient


class FakeHandle:
    def __init__(self, state):
        self.state = state

    def get_comm_state(self):
        return self.state

    def get_goal_status(self):
        return 3

    def get_result(self):
        return None


class RacingActionClient:
    """send_goal lets the status thread deliver a transition before it returns."""

    ns = "move_base"

    def __init__(self, state):
        self.state = state
        self.thread = None

    def send_goal(self, goal, transition_cb, feedback_cb):
        gh = FakeHandle(self.state)
        self.thread = threading.Thread(target=transition_cb, args=(gh,))
        self.thread.start()
        # Long enough for an unguarded client to handle (and drop) the transition.
        self.thread.join(0.2)
        return gh


def client_with(action_client):
    # The real constructor needs a ROS node; set up what it would.
    c = SimpleActionClient.__new__(SimpleActionClient)
    c._send_lock = threading.RLock()
    c.action_client = action_client
    c.simple_state = SimpleGoalState.DONE
    c.gh = None
    c.done_condition = threading.Condition()
    return c


@pytest.mark.parametrize("resend", [False, True])
def test_early_active_transition_is_delivered(resend):
    fake = RacingActionClient(CommState.ACTIVE)
    client = client_with(fake)
    if resend:  # a newer goal while an old handle is tracked (the usual case after the first)
        client.send_goal("old")
        fake.thread.join()
    active = []
    client.send_goal("goal", active_cb=lambda: active.append(True))
    fake.thread.join(5.0)
    assert active == [True]
    assert client.simple_state == SimpleGoalState.ACTIVE


def test_early_done_transition_is_delivered():
    fake = RacingActionClient(CommState.DONE)
    client = client_with(fake)
    done = []
    client.send_goal("goal", done_cb=lambda status, result: done.append(status))
    fake.thread.join(5.0)
    assert done == [3]
    assert client.simple_state == SimpleGoalState.DONE


def test_transitions_of_an_untracked_goal_are_ignored():
    fake = RacingActionClient(CommState.ACTIVE)
    client = client_with(fake)
    client.send_goal("goal")
    fake.thread.join(5.0)
    old = client.gh
    client.stop_tracking_goal()
    active = []
    client.active_cb = lambda: active.append(True)
    client._handle_transition(old)
    assert active == []
