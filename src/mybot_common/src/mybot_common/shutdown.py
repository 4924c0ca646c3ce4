"""What a rospy node does on its way out."""
import time


def linger():
    """Let rospy's connection threads send the last message (a stop, a final status) before the
    process exits.

    Publishing is asynchronous; exiting right after publish() can drop the message (explore's
    "done" status was lost that way in a loaded gate, 2026-11-27). This is wall time on purpose:
    it is about sockets, not robot behaviour. Under lockstep, release the period first.
    """
    time.sleep(0.3)
