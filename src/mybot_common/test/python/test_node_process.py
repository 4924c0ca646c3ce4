"""mybot_common.node_process against a stand-in master (the rostests use it with rostest's)."""
import os
import subprocess
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "src"))
from mybot_common import node_process  # noqa: E402


class FakeMaster:
    """Answers getSystemState as rosgraph.Master does: [publishers, subscribers, services]."""

    def __init__(self, *states):
        self.states = list(states)

    def getSystemState(self):
        return self.states.pop(0) if len(self.states) > 1 else self.states[0]


STARTING = [[['/rosout', ['/odom_node', '/other']]], [], []]
PARTLY_UP = [[['/rosout', ['/odom_node']], ['/tf', ['/odom_node']]], [], []]
UP = [[['/rosout', ['/odom_node']], ['/odom', ['/odom_node']], ['/tf', ['/odom_node', '/other']]], [], []]


def test_advertised_leaves_out_rosout_and_other_nodes():
    assert node_process.advertised('/odom_node', FakeMaster(STARTING)) == []
    assert node_process.advertised('/odom_node', FakeMaster(UP)) == ['/odom', '/tf']
    assert node_process.advertised('/odom', FakeMaster(UP)) == []  # a topic is not a node


def sleeper():
    """A process that is up once it has said so (unbuffered: its line is in the pipe before this returns)."""
    proc = subprocess.Popen([sys.executable, '-u', '-c', 'import time; print("up"); time.sleep(30)'],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    assert proc.stdout.readline() == 'up\n'
    return proc


def test_waits_until_the_node_advertises(monkeypatch):
    monkeypatch.setattr(node_process.rosgraph, 'Master', lambda name: FakeMaster(STARTING, STARTING, UP))
    proc = sleeper()
    try:
        assert node_process.wait_until_advertising(proc, '/odom_node', timeout=10) == ['/odom', '/tf']
        assert proc.poll() is None
    finally:
        node_process.stop(proc)


def test_waits_for_the_named_topics_not_the_first_one(monkeypatch):
    # A node registers its publishers one by one: a poll between two registrations sees only /tf.
    monkeypatch.setattr(node_process.rosgraph, 'Master', lambda name: FakeMaster(STARTING, PARTLY_UP, UP))
    proc = sleeper()
    try:
        assert node_process.wait_until_advertising(proc, '/odom_node', timeout=10, topics=['/odom']) == ['/odom', '/tf']
    finally:
        node_process.stop(proc)


def test_a_named_topic_never_advertised_is_named_at_the_timeout(monkeypatch):
    monkeypatch.setattr(node_process.rosgraph, 'Master', lambda name: FakeMaster(PARTLY_UP))
    proc = sleeper()
    with pytest.raises(AssertionError, match=r'/odom_node advertised /odom within 0.3 s \(it advertised /tf\)'):
        node_process.wait_until_advertising(proc, '/odom_node', timeout=0.3, topics=['/odom'])
    assert proc.poll() is not None


def test_a_node_that_exits_first_is_reported_with_its_output(monkeypatch):
    monkeypatch.setattr(node_process.rosgraph, 'Master', lambda name: FakeMaster(STARTING))
    proc = subprocess.Popen(['sh', '-c', 'echo "wheel_radius: must be > 0"; exit 1'],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    with pytest.raises(AssertionError, match=r'(?s)/odom_node exited \(1\).*wheel_radius: must be > 0'):
        node_process.wait_until_advertising(proc, '/odom_node', timeout=10)


def test_a_node_that_never_advertises_is_killed_at_the_timeout(monkeypatch):
    monkeypatch.setattr(node_process.rosgraph, 'Master', lambda name: FakeMaster(STARTING))
    proc = sleeper()
    with pytest.raises(AssertionError, match=r'advertised no topic within 0.3 s \(it advertised nothing\)'):
        node_process.wait_until_advertising(proc, '/odom_node', timeout=0.3)
    assert proc.poll() is not None


def test_subscribed_wants_a_subscriber_on_every_topic():
    state = [[], [['/cmd_vel', ['/controller']], ['/swerve_a/rqst_pivot_angle', []]], []]
    assert node_process.subscribed(['/cmd_vel'], FakeMaster(state))
    assert not node_process.subscribed(['/cmd_vel', '/swerve_a/rqst_pivot_angle'], FakeMaster(state))
    assert not node_process.subscribed(['/odom'], FakeMaster(state))


def test_executable_names_the_package_and_tool_it_cannot_find():
    with pytest.raises(FileNotFoundError, match="no_such_tool is not built .*no_such_package no_such_tool"):
        node_process.executable("no_such_package", "no_such_tool")
