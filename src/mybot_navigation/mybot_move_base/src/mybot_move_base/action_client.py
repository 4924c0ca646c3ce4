"""A SimpleActionClient that does not lose a goal's first transition.

rospy's SimpleActionClient stores the new goal handle only after ActionClient.send_goal has
published the goal. A fast server's first status (ACTIVE, or even DONE) can arrive on the
status thread in between: the client logs "Got a transition callback on a goal handle that we're
not tracking" and drops that transition for good (ros/actionlib#206). The active_cb then never
runs, and the simple state stays PENDING.

Here sending and handling transitions share a lock, so a transition waits until the handle
is stored. Transitions of goals no longer tracked (after a newer send_goal) are ignored
silently, as stop_tracking_goal intends.
"""
import threading

import actionlib


class SimpleActionClient(actionlib.SimpleActionClient):

    def __init__(self, ns, action_spec):
        # Before the base class subscribes: status callbacks may start at once.
        self._send_lock = threading.RLock()
        super().__init__(ns, action_spec)

    def send_goal(self, goal, done_cb=None, active_cb=None, feedback_cb=None):
        with self._send_lock:
            super().send_goal(goal, done_cb=done_cb, active_cb=active_cb, feedback_cb=feedback_cb)

    def stop_tracking_goal(self):
        with self._send_lock:
            super().stop_tracking_goal()

    def _handle_transition(self, gh):
        with self._send_lock:
            if gh != self.gh:
                return
            super()._handle_transition(gh)
