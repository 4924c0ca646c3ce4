"""What a rospy node does on its way out."""
import time


def _queued(topic_manager=None):
    """How many messages this process's publishers still hold in their connections' queues
    (rospy's QueuedConnection, for publishers made with a queue_size), not yet handed to the
    socket by the connections' writer threads."""
    if topic_manager is None:
        from rospy.impl.registration import get_topic_manager
        topic_manager = get_topic_manager()
    pending = 0
    for impl in list(getattr(topic_manager, "pubs", {}).values()):
        for connection in list(getattr(impl, "connections", None) or []):
            pending += len(getattr(connection, "_queue", None) or [])
    return pending


def linger(timeout=5.0, settle=0.3, topic_manager=None):
    """Let rospy's connection threads send the last message (a stop, a final status) before the
    process exits.

    Publishing is asynchronous: publish() queues the message for each subscriber and a writer
    thread per connection sends it, so exiting right after publish() can drop it (explore's "done"
    status was lost that way in a loaded gate, 2026-11-27). This waits until every queue is empty
    (at most `timeout` s: a subscriber that stopped reading must not keep the node alive), then
    `settle` s more for the batch a writer took off its queue last. Wall time on purpose: it is
    about sockets, not robot behaviour. Under lockstep, release the period first."""
    deadline = time.monotonic() + timeout
    while _queued(topic_manager) and time.monotonic() < deadline:
        time.sleep(0.01)
    time.sleep(settle)
