#!/usr/bin/python3
"""actionlib in lockstep (mybot_lockstep's C++ ActionServer, mybot_move_base's SimpleActionClient
given the participant): a goal sent while this node holds period k is handled by the server in
period k+1, and the client sees the result in period k+2; a cancel likewise. Exactly, every time:
that is what makes a navigation run repeat on a loaded machine."""
import sys
import unittest

import rospy
import rostest
from actionlib.msg import TestAction, TestGoal
from actionlib_msgs.msg import GoalStatus

from mybot_lockstep import participant
from mybot_move_base.action_client import SimpleActionClient


def period():
    return int(round(rospy.get_rostime().to_sec() / 0.01))


class LockstepActionTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('lockstep_action_test')
        cls.ls = participant(defer_join=True)
        cls.client = SimpleActionClient('test_action', TestAction, ls=cls.ls)

    def test_a_goals_and_results_take_one_period_each_way(self):
        self.assertTrue(self.ls.active, 'lockstep is not on')
        self.assertTrue(self.client.wait_for_server(rospy.Duration(10)), 'no action server')
        for i in range(5):
            self.ls.sleep(0.01 * (i + 1))  # goals at different phases
            sent = period()
            self.client.send_goal(TestGoal(goal=0))
            self.assertTrue(self.client.wait_for_result(rospy.Duration(1.0)), 'goal %d: no result' % i)
            self.assertEqual(self.client.get_state(), GoalStatus.SUCCEEDED)
            self.assertEqual(self.client.get_result().result, sent + 1, 'goal %d: handled in the wrong period' % i)
            self.assertEqual(period(), sent + 2, 'goal %d: result seen in the wrong period' % i)

    def test_b_a_cancel_takes_one_period(self):
        self.client.send_goal(TestGoal(goal=1))
        self.ls.sleep(0.05)
        self.assertEqual(self.client.get_state(), GoalStatus.ACTIVE)
        sent = period()
        self.client.cancel_goal()
        self.assertTrue(self.client.wait_for_result(rospy.Duration(1.0)), 'no result after the cancel')
        self.assertEqual(self.client.get_state(), GoalStatus.PREEMPTED)
        self.assertEqual(self.client.get_result().result, sent + 1)
        self.assertEqual(period(), sent + 2)


if __name__ == '__main__':
    rostest.rosrun('mybot_gazebo_lite', 'lockstep_action', LockstepActionTest, sys.argv)
