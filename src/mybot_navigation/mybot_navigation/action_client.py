"""A SimpleActionClient without rospy actionlib's send_goal race.

SimpleActionClient.send_goal stores the new goal's handle only after the goal went out. A
server as quick as ours can publish the goal's first status before that, and the client then
logs "Got a transition callback on a goal handle that we're not tracking" (an ERROR line in
every demo run) and drops the PENDING -> ACTIVE transition. Between stop_tracking_goal() and that
assignment no other goal can transition (earlier ones are done), so a transition arriving while
no goal is tracked belongs to the goal being sent."""
import actionlib


class SimpleActionClient(actionlib.SimpleActionClient):
    def _handle_transition(self, gh):
        if self.gh is None:
            self.gh = gh
        super()._handle_transition(gh)
