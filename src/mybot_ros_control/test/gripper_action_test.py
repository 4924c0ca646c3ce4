#!/usr/bin/env python3
"""gripper_action_controller's two types on a gripper, through gazebo_ros_control, measured by the
simulator's joint states: a goal reached and ended SUCCEEDED with `reached_goal`; a goal the joint
cannot reach (past its limit, or a load heavier than max_effort) ended ABORTED with `stalled` after
stall_timeout, the joint still held; a cancel holding the finger where it is; a new goal preempting
the running one; goals with a value that is not finite rejected naming it; a controller without its
joint refused naming the parameter."""
import subprocess

import rospy
import rostest
from actionlib_msgs.msg import GoalStatus

from control_msgs.msg import GripperCommand, GripperCommandAction, GripperCommandGoal
from mybot_move_base.action_client import SimpleActionClient

from controller_test import ControllerTest, refusal


def goal(position, max_effort=0.0):
    return GripperCommandGoal(command=GripperCommand(position=position, max_effort=max_effort))


class GripperAction(ControllerTest):
    @classmethod
    def setUpClass(cls):
        cls.join("gripper_action_test")
        cls.finger = SimpleActionClient("/gripper_controller/gripper_cmd", GripperCommandAction, ls=cls.ls)
        cls.finger2 = SimpleActionClient("/gripper_controller/gripper_cmd", GripperCommandAction, ls=cls.ls)
        cls.lift = SimpleActionClient("/lift_controller/gripper_cmd", GripperCommandAction, ls=cls.ls)
        cls.unpause_when_running(3, (cls.finger, cls.finger2, cls.lift))

    def test_0_the_action_speaks_control_msgs(self):
        # control_msgs' types, as `rostopic type` shows them (their MD5 sums are upstream's:
        # test/python/test_upstream_messages.py): MoveIt's GripperCommand handle connects.
        self.assert_advertises({
            "/gripper_controller/gripper_cmd/goal": "control_msgs/GripperCommandActionGoal",
            "/gripper_controller/gripper_cmd/result": "control_msgs/GripperCommandActionResult",
            "/gripper_controller/gripper_cmd/feedback": "control_msgs/GripperCommandActionFeedback"})
        types = {c.name: c.type for c in self.list().controller}
        self.assertEqual(types["gripper_controller"], "position_controllers/GripperActionController")
        self.assertEqual(types["lift_controller"], "effort_controllers/GripperActionController")

    def test_1_a_goal_is_reached(self):
        self.assertTrue(self.ls.wait_for(lambda: self.position("finger_joint") is not None, 5.0), "no joint_states")
        feedback = []
        t0 = rospy.get_time()
        state, result = self.run_goal(self.finger, goal(0.03, 10.0), feedback=feedback.append)
        t1 = rospy.get_time()
        self.assertEqual(state, GoalStatus.SUCCEEDED, self.finger.get_goal_status_text())
        self.assertTrue(result.reached_goal)
        self.assertFalse(result.stalled)
        self.assertLess(abs(result.position - 0.03), 0.002)
        self.assertEqual(result.effort, 10.0)  # the position type reports the goal's max_effort
        # Succeeded once within goal_tolerance (as upstream, on its way); the command stays, and
        # the finger comes to rest at it.
        self.assertTrue(self.comes_to_rest("finger_joint", 0.03, 0.0005), self.position("finger_joint"))
        # The finger's <limit velocity> is 0.1 m/s: 0.028 m of the way take 0.28 s at least.
        self.assertGreaterEqual(t1 - t0, 0.28 - 1e-6)
        self.assertTrue(feedback, "no feedback while the finger moved")
        self.assertTrue(all(0.0 <= f.position <= 0.0301 for f in feedback), [f.position for f in feedback])

    def test_2_a_goal_past_the_limit_stalls_and_aborts(self):
        t0 = rospy.get_time()
        state, result = self.run_goal(self.finger, goal(0.06, 5.0))
        t1 = rospy.get_time()
        self.assertEqual(state, GoalStatus.ABORTED)
        self.assertIn("stalled", self.finger.get_goal_status_text())
        self.assertTrue(result.stalled)
        self.assertFalse(result.reached_goal)
        self.assertLess(abs(result.position - 0.04), 0.002)
        # At the limit after 0.1 s at most, then at rest for over stall_timeout (0.5 s).
        self.assertGreater(t1 - t0, 0.5)
        self.assertLess(t1 - t0, 0.5 + 0.1 + 0.2)
        # Ended, the command still holds: the finger stays at its limit.
        self.ls.sleep(1.0)
        self.assertLess(abs(self.position("finger_joint") - 0.04), 0.002)

    def test_3_a_cancel_holds_the_finger_where_it_is(self):
        self.finger.send_goal(goal(0.0))
        self.ls.sleep(0.1)  # 0.01 m of the 0.04 m way at 0.1 m/s
        self.finger.cancel_goal()
        self.assertTrue(self.finger.wait_for_result(rospy.Duration(5)))
        self.assertEqual(self.finger.get_state(), GoalStatus.PREEMPTED)
        at_cancel = self.position("finger_joint")
        self.assertGreater(at_cancel, 0.02, "the finger was not on its way")
        self.ls.sleep(1.0)
        self.assertLess(abs(self.position("finger_joint") - at_cancel), 0.002, "the finger went on after the cancel")

    def test_4_a_new_goal_preempts_the_running_one(self):
        self.finger2.send_goal(goal(0.0))
        self.ls.sleep(0.05)
        state, result = self.run_goal(self.finger, goal(0.01))
        self.assertEqual(state, GoalStatus.SUCCEEDED)
        self.assertTrue(self.ls.wait_for(lambda: self.finger2.get_state() == GoalStatus.PREEMPTED, 5.0),
                        "the first goal is %d" % self.finger2.get_state())
        self.assertIn("replaced by a new goal", self.finger2.get_goal_status_text())
        self.assertTrue(self.comes_to_rest("finger_joint", 0.01, 0.0005), self.position("finger_joint"))

    def test_5_goals_that_are_not_finite_are_rejected(self):
        self.assertTrue(self.comes_to_rest("finger_joint", self.position("finger_joint"), 0.01))
        before = self.position("finger_joint")
        for g, text in ((goal(float("nan")), "command.position is not finite"),
                        (goal(0.02, float("inf")), "command.max_effort is not finite")):
            state, _ = self.run_goal(self.finger, g, timeout=5.0)
            self.assertEqual(state, GoalStatus.REJECTED)
            self.assertEqual(self.finger.get_goal_status_text(), text)
        self.ls.sleep(0.5)
        self.assertLess(abs(self.position("finger_joint") - before), 1e-4, "a rejected goal moved the finger")

    def test_6_max_effort_below_the_load_cannot_hold_it(self):
        # Unclamped (max_effort 0), the PID lifts the 0.5 kg.
        state, result = self.run_goal(self.lift, goal(0.05, 0.0))
        self.assertEqual(state, GoalStatus.SUCCEEDED, self.lift.get_goal_status_text())
        self.assertTrue(result.reached_goal)
        self.assertTrue(self.comes_to_rest("lift_joint", 0.05, 0.005), self.position("lift_joint"))
        # 2 N against its 4.9 N weight: it sinks to its lower limit, rests there and stalls, pushing 2 N.
        t0 = rospy.get_time()
        state, result = self.run_goal(self.lift, goal(0.08, 2.0))
        self.assertEqual(state, GoalStatus.ABORTED)
        self.assertTrue(result.stalled)
        self.assertLess(result.position, 0.005)
        self.assertAlmostEqual(result.effort, 2.0, places=9)
        self.assertGreater(rospy.get_time() - t0, 1.0)
        # A strong enough goal lifts it again.
        state, result = self.run_goal(self.lift, goal(0.05, 10.0))
        self.assertEqual(state, GoalStatus.SUCCEEDED, self.lift.get_goal_status_text())
        self.assertLessEqual(abs(result.effort), 10.0)

    def test_6b_controller_managers_tool_lists_them(self):
        # controller_manager's command-line tool, through the stand-in package, as a user types it.
        p = subprocess.run(["rosrun", "controller_manager", "controller_manager", "list-types"], capture_output=True,
                           text=True, timeout=60)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("position_controllers/GripperActionController", p.stdout)
        self.assertIn("effort_controllers/GripperActionController", p.stdout)
        p = subprocess.run(["rosrun", "controller_manager", "controller_manager", "list"], capture_output=True,
                           text=True, timeout=60)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("gripper_controller - position_controllers/GripperActionController ( running )", p.stdout)

    def test_7_a_controller_without_its_joint_is_refused_naming_it(self):
        rospy.set_param("/no_joint_gripper", {"type": "position_controllers/GripperActionController"})
        self.assertFalse(self.load(name="no_joint_gripper").ok)
        self.assertIn("/no_joint_gripper/joint", refusal(lambda cm: cm.load("no_joint_gripper")))
        # The lift has no position interface.
        rospy.set_param("/wrong_gripper", {"type": "position_controllers/GripperActionController", "joint": "lift_joint"})
        self.assertFalse(self.load(name="wrong_gripper").ok)
        self.assertIn("lift_joint", refusal(lambda cm: cm.load("wrong_gripper")))
        rospy.set_param("/bad_tolerance_gripper", {"type": "position_controllers/GripperActionController",
                                                   "joint": "finger_joint", "goal_tolerance": -0.01})
        self.assertFalse(self.load(name="bad_tolerance_gripper").ok)
        self.assertIn("/bad_tolerance_gripper/goal_tolerance", refusal(lambda cm: cm.load("bad_tolerance_gripper")))

    def test_8_a_stopped_controller_ends_its_goal_and_takes_none(self):
        self.finger.send_goal(goal(0.04))
        self.assertTrue(self.ls.wait_for(lambda: self.finger.get_state() == GoalStatus.ACTIVE, 2.0), "goal not active")
        res = self.switch(start_controllers=[], stop_controllers=["gripper_controller"], strictness=2)
        self.assertTrue(res.ok)
        self.assertTrue(self.finger.wait_for_result(rospy.Duration(5)))
        self.assertEqual(self.finger.get_state(), GoalStatus.ABORTED)
        self.assertIn("the controller was stopped", self.finger.get_goal_status_text())
        state, _ = self.run_goal(self.finger, goal(0.02), timeout=5.0)
        self.assertEqual(state, GoalStatus.REJECTED)
        self.assertEqual(self.finger.get_goal_status_text(), "the controller is not running")
        res = self.switch(start_controllers=["gripper_controller"], stop_controllers=[], strictness=2)
        self.assertTrue(res.ok)
        state, result = self.run_goal(self.finger, goal(0.02))
        self.assertEqual(state, GoalStatus.SUCCEEDED, self.finger.get_goal_status_text())
        self.assertTrue(self.comes_to_rest("finger_joint", 0.02, 0.0005), self.position("finger_joint"))


if __name__ == "__main__":
    rostest.rosrun("mybot_ros_control", "gripper_action", GripperAction)
