"""actionlib's ActionClient with its topics through the lockstep participant.

rospy's ActionClient publishes goals and cancels and receives status, result and feedback on
rospy's own threads, whenever they arrive: in the simulator a goal then starts a period earlier
or later with the machine's load. Here the five topics go through the participant, so a goal
sent in period k reaches the server's callbacks in period k+1 (mybot_lockstep's C++
ActionServer takes it through lockstep) and the server's result for period k reaches this
client's callbacks in period k+1, on an idle and on a loaded machine alike. Off lockstep the
participant's calls are rospy's, so this is actionlib's ActionClient.
"""
import rospy
from actionlib.action_client import ActionClient as _ActionClient
from actionlib.action_client import ActionException, GoalManager
from actionlib_msgs.msg import GoalID, GoalStatusArray


class ActionClient(_ActionClient):

    def __init__(self, ns, ActionSpec, ls):
        # actionlib.ActionClient.__init__ (the same names, parameters and queue sizes), with the
        # participant's Publisher and Subscriber in place of rospy's.
        self.ns = ns
        self.last_status_msg = None
        try:
            a = ActionSpec()
            self.ActionSpec = ActionSpec
            self.ActionGoal = type(a.action_goal)
            self.ActionResult = type(a.action_result)
            self.ActionFeedback = type(a.action_feedback)
        except AttributeError:
            raise ActionException("Type is not an action spec: %s" % str(ActionSpec))
        self.pub_queue_size = rospy.get_param('actionlib_client_pub_queue_size', 10)
        if self.pub_queue_size < 0:
            self.pub_queue_size = 10
        base = rospy.remap_name(ns)
        self.pub_goal = ls.Publisher(base + '/goal', self.ActionGoal, queue_size=self.pub_queue_size)
        self.pub_cancel = ls.Publisher(base + '/cancel', GoalID, queue_size=self.pub_queue_size)
        self.manager = GoalManager(ActionSpec)
        self.manager.register_send_goal_fn(self.pub_goal.publish)
        self.manager.register_cancel_fn(self.pub_cancel.publish)
        self.sub_queue_size = rospy.get_param('actionlib_client_sub_queue_size', -1)
        if self.sub_queue_size < 0:
            self.sub_queue_size = None
        self.status_sub = ls.Subscriber(base + '/status', GoalStatusArray, self._status_cb,
                                        queue_size=self.sub_queue_size)
        self.result_sub = ls.Subscriber(base + '/result', self.ActionResult, self._result_cb,
                                        queue_size=self.sub_queue_size)
        self.feedback_sub = ls.Subscriber(base + '/feedback', self.ActionFeedback, self._feedback_cb,
                                          queue_size=self.sub_queue_size)
