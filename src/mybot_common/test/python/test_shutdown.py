"""mybot_common.shutdown.linger against stand-ins for rospy's topic manager and connections."""
import os
import sys
import threading
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "src"))
from mybot_common import shutdown  # noqa: E402


class Connection:
    """rospy's QueuedConnection as linger sees it: a `_queue` a writer thread empties."""

    def __init__(self, queued):
        self._queue = list(queued)


class Publication:
    def __init__(self, *connections):
        self.connections = list(connections)


class TopicManager:
    def __init__(self, **pubs):
        self.pubs = pubs


def test_waits_for_a_slow_writer_to_empty_its_queue():
    slow = Connection(["stop"])
    manager = TopicManager(cmd_vel=Publication(Connection([]), slow), status=Publication())

    emptied = []

    def writer():  # a writer thread starved for 0.5 s, longer than the old fixed 0.3 s sleep
        time.sleep(0.5)
        emptied.append(time.monotonic())  # before the queue empties: linger cannot see it empty earlier
        slow._queue = []
    threading.Thread(target=writer).start()
    shutdown.linger(timeout=5.0, settle=0.0, topic_manager=manager)
    returned = time.monotonic()
    # linger returned once the writer had emptied the queue, not after a fixed time. (Measured from
    # a start taken after the writer's, 0.5 s could come out 0.4996 s: a failed gate at 77b6026.)
    assert slow._queue == []
    assert emptied and returned >= emptied[0]


def test_a_queue_that_never_empties_is_left_at_the_timeout():
    manager = TopicManager(cmd_vel=Publication(Connection(["stop"])))
    start = time.monotonic()
    shutdown.linger(timeout=0.2, settle=0.0, topic_manager=manager)
    assert 0.2 <= time.monotonic() - start < 2.0


def test_unqueued_connections_and_closed_publications_count_nothing():
    # A publisher without queue_size writes directly (no _queue); a closed one has connections None.
    closed = Publication()
    closed.connections = None
    manager = TopicManager(a=Publication(object()), b=closed)
    assert shutdown._queued(manager) == 0
