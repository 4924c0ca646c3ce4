"""A SimpleActionClient that does not lose a goal's first transition.

rospy's SimpleActionClient stores the new goal handle only after ActionClient.send_goal has
published the goal. A fast server's first status (ACTIVE, or even DONE) can arrive on the
status thread in between: the client logs "Got a transition callback on a goal handle that we're
not tracking" and drops that transition for good (ros/actionlib#206). The active_cb then never
runs, and the simple state stays PENDING.

Here sending and handling transitions share a lock, so a transition waits until the handle
is stored. Transitions of goals no longer tracked (after a newer send_goal) are ignored
silently, as stop_tracking_goal intends.

Given a lockstep participant (`ls`, mybot_lockstep) the action's topics go through it
(mybot_lockstep.action_client), and wait_for_server / wait_for_result sleep through it, period
by period in sim time: under lockstep a goal then starts, and its result is seen, in the same
period on an idle and on a loaded machine. actionlib's own waits would hold a period the
main thread has not finished, while time cannot move.
"""
import threading

import actionlib
import rospy
from actionlib import SimpleGoalState


class SimpleActionClient(actionlib.SimpleActionClient):

    def __init__(self, ns, action_spec, ls=None):
        # Before the topics are subscribed: status callbacks may start at once.
        self._send_lock = threading.RLock()
        self._ls = ls if ls is not None and ls.active else None
        if self._ls is None:
            super().__init__(ns, action_spec)
            return
        from mybot_lockstep.action_client import ActionClient
        self.action_client = ActionClient(ns, action_spec, self._ls)
        self.simple_state = SimpleGoalState.DONE
        self.gh = None
        self.done_condition = threading.Condition()

    def _wait(self, predicate, timeout):
        """Waits through the participant, looking once every lockstep period (a step shorter
        than any period wakes at the next one); timeout 0 means for ever, as in actionlib."""
        seconds = timeout.to_sec() if isinstance(timeout, rospy.Duration) else float(timeout)
        if seconds > 0:
            return self._ls.wait_for(predicate, seconds, period=1e-4)
        while not predicate():
            self._ls.sleep(1e-4)
        return True

    def wait_for_server(self, timeout=rospy.Duration()):
        if self._ls is None:
            return super().wait_for_server(timeout)
        return self._wait(self._server_ready, timeout)

    def _server_ready(self):
        """actionlib's test, one look: the server's status is in and every topic is connected."""
        ac = self.action_client
        if not ac.last_status_msg:
            return False
        server = ac.last_status_msg._connection_header['callerid']
        return (ac.pub_goal.impl.has_connection(server) and ac.pub_cancel.impl.has_connection(server) and
                any(c.callerid_pub == server for c in ac.result_sub.impl.connections) and
                any(c.callerid_pub == server for c in ac.feedback_sub.impl.connections))

    def wait_for_result(self, timeout=rospy.Duration()):
        if self._ls is None:
            return super().wait_for_result(timeout)
        if not self.gh:
            rospy.logerr("Called wait_for_result when no goal exists")
            return False
        return self._wait(lambda: self.simple_state == SimpleGoalState.DONE, timeout)

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
