"""The move_base client keeps the first transition of a goal whose handle is not stored yet."""
import types

from actionlib import SimpleGoalState
from actionlib.action_client import CommState

from mybot_navigation.action_client import SimpleActionClient


class FakeHandle:
    def __init__(self, state):
        self.state = state

    def get_comm_state(self):
        return self.state


def bare_client():
    # Only the state _handle_transition touches: no ROS node, no topics.
    c = SimpleActionClient.__new__(SimpleActionClient)
    c.gh = None
    c.simple_state = SimpleGoalState.PENDING
    c.active_cb = c.done_cb = c.feedback_cb = None
    c.action_client = types.SimpleNamespace(ns="move_base")
    return c


def test_transition_before_send_goal_returns_is_tracked():
    c = bare_client()
    h = FakeHandle(CommState.ACTIVE)
    c._handle_transition(h)
    assert c.gh is h
    assert c.simple_state == SimpleGoalState.ACTIVE


def test_transitions_of_another_goal_are_still_ignored():
    c = bare_client()
    tracked = FakeHandle(CommState.ACTIVE)
    c._handle_transition(tracked)
    c._handle_transition(FakeHandle(CommState.PENDING))
    assert c.gh is tracked
    assert c.simple_state == SimpleGoalState.ACTIVE
