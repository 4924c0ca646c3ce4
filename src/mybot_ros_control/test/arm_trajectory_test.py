#!/usr/bin/env python3
"""joint_trajectory_controller's three types on an arm, through gazebo_ros_control, measured by the
simulator's joint states: a goal followed through its points and ended SUCCESSFUL at its positions
(the continuous wrist the short way round); the velocity and effort finger controllers at theirs;
bad goals rejected with FollowJointTrajectory's error code and a text naming the joint or the point;
a cancelled goal stopping the arm short of its target; a path that the joints cannot follow aborted
with PATH_TOLERANCE_VIOLATED; a trajectory on `command`; `state` and `query_state`."""
import math

import rospy
import rostest
from std_srvs.srv import Empty
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from control_msgs.msg import (FollowJointTrajectoryAction, FollowJointTrajectoryGoal, FollowJointTrajectoryResult,
                              JointTolerance, JointTrajectoryControllerState)
from control_msgs.srv import QueryTrajectoryState
from mybot_move_base.action_client import SimpleActionClient

from controller_test import ControllerTest
from actionlib_msgs.msg import GoalStatus

ARM = ["shoulder_joint", "elbow_joint", "wrist_joint"]
R = FollowJointTrajectoryResult


def trajectory(names, points):
    """A JointTrajectory starting on receipt: points as (time_from_start, positions[, velocities])."""
    t = JointTrajectory(joint_names=list(names))
    for p in points:
        q = JointTrajectoryPoint(positions=list(p[1]), time_from_start=rospy.Duration(p[0]))
        if len(p) > 2:
            q.velocities = list(p[2])
        t.points.append(q)
    return t


class ArmTrajectory(ControllerTest):
    @classmethod
    def setUpClass(cls):
        cls.join("arm_trajectory_test")
        cls.state = None
        cls.ls.Subscriber("/arm_controller/state", JointTrajectoryControllerState, cls._on_state)
        cls.command = cls.ls.Publisher("/arm_controller/command", JointTrajectory, queue_size=1)
        cls.arm = SimpleActionClient("/arm_controller/follow_joint_trajectory", FollowJointTrajectoryAction, ls=cls.ls)
        cls.left = SimpleActionClient("/left_finger_controller/follow_joint_trajectory", FollowJointTrajectoryAction,
                                      ls=cls.ls)
        cls.right = SimpleActionClient("/right_finger_controller/follow_joint_trajectory",
                                       FollowJointTrajectoryAction, ls=cls.ls)
        rospy.wait_for_service("/arm_controller/query_state", timeout=60)
        cls.query = rospy.ServiceProxy("/arm_controller/query_state", QueryTrajectoryState)
        cls.unpause_when_running(4, (cls.arm, cls.left, cls.right))

    @classmethod
    def _on_state(cls, m):
        with cls.lock:
            cls.state = m

    def test_0_the_action_and_state_speak_control_msgs(self):
        # control_msgs' types, as `rostopic type` shows them (their MD5 sums are upstream's:
        # test/python/test_upstream_messages.py): MoveIt's and rqt's clients connect.
        self.assert_advertises({
            "/arm_controller/follow_joint_trajectory/goal": "control_msgs/FollowJointTrajectoryActionGoal",
            "/arm_controller/follow_joint_trajectory/result": "control_msgs/FollowJointTrajectoryActionResult",
            "/arm_controller/follow_joint_trajectory/feedback": "control_msgs/FollowJointTrajectoryActionFeedback",
            "/arm_controller/state": "control_msgs/JointTrajectoryControllerState"})

    def test_0b_the_arm_starts_where_spawn_model_put_it_and_is_held_there(self):
        # spawn_model -J elbow_joint 0.5 set the elbow after the spawn; the spawner started the
        # controllers while the world stood, before or after that: they start when time moves, from
        # the joints as they are then (upstream's switch waits for the control loop), so they hold
        # the bent elbow instead of pulling it back to where the model was built.
        self.assertTrue(self.ls.wait_for(lambda: self.state is not None, 5.0), "no state")
        with self.lock:
            first = self.history[0][1]
            s = self.state
        self.assertAlmostEqual(first["elbow_joint"], 0.5, delta=1e-6)
        self.assertAlmostEqual(first["shoulder_joint"], 0.0, delta=1e-6)
        self.assertAlmostEqual(s.desired.positions[ARM.index("elbow_joint")], 0.5, delta=1e-6)
        self.ls.sleep(1.0)
        self.assertAlmostEqual(self.position("elbow_joint"), 0.5, delta=0.02)

    def test_1_a_goal_is_followed_through_its_points_to_success(self):
        self.assertTrue(self.ls.wait_for(lambda: self.position("wrist_joint") is not None, 5.0), "no joint_states")
        self.assertEqual({c.name: c.type for c in self.list().controller}["arm_controller"],
                         "position_controllers/JointTrajectoryController")
        t0 = rospy.get_time()
        goal = FollowJointTrajectoryGoal(trajectory=trajectory(
            ARM, [(2.0, [0.6, -0.8, 3.0]), (4.0, [1.0, -1.2, 2.5])]))
        state, result = self.run_goal(self.arm, goal)
        t1 = rospy.get_time()
        self.assertEqual(state, GoalStatus.SUCCEEDED, result.error_string)
        self.assertEqual(result.error_code, R.SUCCESSFUL)
        self.assertGreaterEqual(t1 - t0, 4.0, "succeeded before the trajectory's end")
        for name, want in zip(ARM, [1.0, -1.2, 2.5]):
            self.assertAlmostEqual(self.position(name), want, delta=0.02, msg=name)
        # It passed its first point: at 2 s the shoulder was near 0.6 (the servo lags the setpoint).
        with self.lock:
            at2 = min(self.history, key=lambda h: abs(h[0] - (t0 + 2.0)))[1]
        self.assertAlmostEqual(at2["shoulder_joint"], 0.6, delta=0.1)
        self.assertAlmostEqual(at2["wrist_joint"], 3.0, delta=0.15)
        # state, from past the trajectory's end: desired at rest at the goal, the error within the
        # goal tolerance.
        self.assertTrue(self.ls.wait_for(lambda: self.state is not None and self.state.header.stamp.to_sec() >= t1,
                                         2.0), "no state")
        with self.lock:
            s = self.state
        self.assertEqual(list(s.joint_names), ARM)
        self.assertAlmostEqual(s.desired.positions[0], 1.0, places=9)
        self.assertLess(max(abs(e) for e in s.error.positions), 0.02)
        q = self.query(time=rospy.Time(t1))
        self.assertEqual(list(q.name), ARM)
        self.assertAlmostEqual(q.position[1], -1.2, places=9)
        self.assertEqual(list(q.velocity), [0.0, 0.0, 0.0])

    def test_2_bad_goals_are_rejected_naming_the_joint_or_the_point(self):
        cases = [
            (trajectory(["shoulder_joint", "elbow_joint", "wirst_joint"], [(1.0, [0, 0, 0])]), R.INVALID_JOINTS,
             "wirst_joint"),
            (trajectory(["shoulder_joint", "elbow_joint"], [(1.0, [0, 0])]), R.INVALID_JOINTS, "wrist_joint"),
            (trajectory(ARM, [(1.0, [0, 0])]), R.INVALID_GOAL, "point 0: 2 positions for 3 joints"),
            (trajectory(ARM, [(1.0, [0, 0, 0]), (1.0, [0.1, 0, 0])]), R.INVALID_GOAL, "point 1: time_from_start"),
            (trajectory(ARM, [(1.0, [0, float("nan"), 0])]), R.INVALID_GOAL, "not finite"),
        ]
        self.ls.sleep(0.5)  # the servos close the last of their lag
        before = [self.position(n) for n in ARM]
        for traj, code, text in cases:
            state, result = self.run_goal(self.arm, FollowJointTrajectoryGoal(trajectory=traj))
            self.assertEqual(state, GoalStatus.REJECTED)
            self.assertEqual(result.error_code, code, result.error_string)
            self.assertIn(text, result.error_string)
        goal = FollowJointTrajectoryGoal(trajectory=trajectory(ARM, [(1.0, [0, 0, 0])]))
        goal.goal_tolerance = [JointTolerance(name="knee_joint", position=0.1)]
        state, result = self.run_goal(self.arm, goal)
        self.assertEqual((state, result.error_code), (GoalStatus.REJECTED, R.INVALID_GOAL))
        self.assertIn("knee_joint", result.error_string)
        # Stamped 2 s ago (test 1 ran 4 s) with its one point 0.5 s after that: it ended 1.5 s ago.
        goal = FollowJointTrajectoryGoal(trajectory=trajectory(ARM, [(0.5, [0, 0, 0])]))
        goal.trajectory.header.stamp = rospy.Time(rospy.get_time() - 2.0)
        state, result = self.run_goal(self.arm, goal)
        self.assertEqual((state, result.error_code), (GoalStatus.REJECTED, R.OLD_HEADER_TIMESTAMP))
        self.assertIn("before now", result.error_string)
        # Nothing moved.
        self.ls.sleep(0.5)
        for n, b in zip(ARM, before):
            self.assertAlmostEqual(self.position(n), b, delta=1e-3, msg=n)

    def test_3_a_cancelled_goal_stops_the_arm_short_of_its_target(self):
        start = self.position("shoulder_joint")
        self.arm.send_goal(FollowJointTrajectoryGoal(trajectory=trajectory(ARM, [(4.0, [start - 2.0, 0.0, 0.0])])))
        self.ls.sleep(1.5)
        self.arm.cancel_goal()
        self.assertTrue(self.arm.wait_for_result(rospy.Duration(5)))
        self.assertEqual(self.arm.get_state(), GoalStatus.PREEMPTED)
        # stop_trajectory_duration 0.5: it comes to rest within that (and the servo's lag).
        self.ls.sleep(1.5)
        stopped = self.position("shoulder_joint")
        self.ls.sleep(1.0)
        self.assertAlmostEqual(self.position("shoulder_joint"), stopped, delta=1e-3, msg="still moving")
        self.assertLess(stopped, start - 0.4, "it had not moved")
        self.assertGreater(stopped, start - 1.6, "it went on towards the target")

    def test_4_a_path_the_joints_cannot_follow_aborts(self):
        # 2.5 rad in 0.5 s against the shoulder's 1.5 rad/s limit, with a 0.05 rad path tolerance.
        start = self.position("shoulder_joint")
        goal = FollowJointTrajectoryGoal(trajectory=trajectory(ARM, [(0.5, [start + 2.5, 0.0, 0.0])]))
        goal.path_tolerance = [JointTolerance(name="shoulder_joint", position=0.05)]
        state, result = self.run_goal(self.arm, goal)
        self.assertEqual(state, GoalStatus.ABORTED)
        self.assertEqual(result.error_code, R.PATH_TOLERANCE_VIOLATED, result.error_string)
        self.assertIn("shoulder_joint", result.error_string)
        self.assertIn("path tolerance 0.05", result.error_string)
        self.ls.sleep(1.5)
        stopped = self.position("shoulder_joint")
        self.ls.sleep(1.0)
        self.assertAlmostEqual(self.position("shoulder_joint"), stopped, delta=1e-3, msg="still moving")
        self.assertLess(stopped, start + 1.0, "it went on after the abort")

    def test_4b_a_goal_the_joints_cannot_reach_aborts_after_goal_time(self):
        # The shoulder to 3.4 rad, past its 3.0 rad limit (the servo stops there), with its path
        # tolerance removed (-1): 0.6 s (goal_time) after the end it is still 0.4 rad out.
        goal = FollowJointTrajectoryGoal(trajectory=trajectory(ARM, [(3.0, [3.4, 0.0, 0.0])]))
        goal.path_tolerance = [JointTolerance(name="shoulder_joint", position=-1.0)]
        t0 = rospy.get_time()
        state, result = self.run_goal(self.arm, goal)
        self.assertEqual(state, GoalStatus.ABORTED)
        self.assertEqual(result.error_code, R.GOAL_TOLERANCE_VIOLATED, result.error_string)
        self.assertIn("joint 'shoulder_joint' is 0.4", result.error_string)
        self.assertIn("goal_time 0.6 s", result.error_string)
        self.assertGreater(rospy.get_time() - t0, 3.59)  # the end at 3 s, then goal_time
        self.assertAlmostEqual(self.position("shoulder_joint"), 3.0, delta=0.01)

    def test_4c_a_goal_sets_velocity_tolerances(self):
        # An acceleration tolerance is taken and never fails (the acceleration is not measured;
        # upstream sets its error to 0).
        start = self.position("shoulder_joint")
        goal = FollowJointTrajectoryGoal(trajectory=trajectory(ARM, [(2.0, [start - 0.5, 0.0, 0.0])]))
        goal.path_tolerance = [JointTolerance(name="shoulder_joint", acceleration=1e-6)]
        state, result = self.run_goal(self.arm, goal)
        self.assertEqual(state, GoalStatus.SUCCEEDED, result.error_string)
        # 2.5 rad in 0.5 s asks 5 rad/s of a shoulder limited to 1.5: its path velocity tolerance
        # (0.5 rad/s), its position one removed, aborts the goal.
        goal = FollowJointTrajectoryGoal(trajectory=trajectory(ARM, [(0.5, [start - 3.0, 0.0, 0.0])]))
        goal.path_tolerance = [JointTolerance(name="shoulder_joint", position=-1.0, velocity=0.5)]
        state, result = self.run_goal(self.arm, goal)
        self.assertEqual(state, GoalStatus.ABORTED)
        self.assertEqual(result.error_code, R.PATH_TOLERANCE_VIOLATED, result.error_string)
        self.assertIn("joint 'shoulder_joint' moves at", result.error_string)
        self.assertIn("path velocity tolerance 0.5", result.error_string)
        # A tolerance that is not finite is refused naming the joint.
        goal.path_tolerance = [JointTolerance(name="elbow_joint", velocity=float("nan"))]
        state, result = self.run_goal(self.arm, goal)
        self.assertEqual(state, GoalStatus.REJECTED)
        self.assertEqual(result.error_code, R.INVALID_GOAL)
        self.assertIn("joint 'elbow_joint''s tolerance is not finite", result.error_string)
        self.ls.sleep(1.5)

    def test_5_a_trajectory_on_command_is_followed(self):
        self.command.publish(trajectory(ARM, [(1.5, [0.3, 0.4, 0.5], [0.0, 0.0, 0.0])]))
        self.ls.sleep(2.5)
        for name, want in zip(ARM, [0.3, 0.4, 0.5]):
            self.assertAlmostEqual(self.position(name), want, delta=0.02, msg=name)

    def test_5b_a_trajectory_on_command_replaces_a_running_goal(self):
        self.arm.send_goal(FollowJointTrajectoryGoal(trajectory=trajectory(ARM, [(4.0, [-1.0, -1.0, -1.0])])))
        self.ls.sleep(1.0)
        self.command.publish(trajectory(ARM, [(1.0, [0.2, 0.2, 0.2])]))
        self.assertTrue(self.arm.wait_for_result(rospy.Duration(5)))
        self.assertEqual(self.arm.get_state(), GoalStatus.PREEMPTED)
        self.assertIn("replaced by a trajectory on the command topic", self.arm.get_goal_status_text())
        self.ls.sleep(2.0)
        for name in ARM:
            self.assertAlmostEqual(self.position(name), 0.2, delta=0.02, msg=name)

    def test_5c_a_trajectory_stamped_ahead_starts_then(self):
        # Stamped 1 s ahead: until then the arm holds (the trajectory it had, at rest), then moves.
        self.ls.sleep(0.5)
        before = self.position("shoulder_joint")
        t = trajectory(ARM, [(1.0, [before - 0.5, 0.2, 0.2])])
        t.header.stamp = rospy.Time(rospy.get_time() + 1.0)
        self.command.publish(t)
        self.ls.sleep(0.9)
        self.assertAlmostEqual(self.position("shoulder_joint"), before, delta=1e-3, msg="moved before its start")
        self.ls.sleep(1.6)
        self.assertAlmostEqual(self.position("shoulder_joint"), before - 0.5, delta=0.02)

    def test_6_the_velocity_and_effort_fingers_reach_their_goals(self):
        for client, name in ((self.left, "left_finger_joint"), (self.right, "right_finger_joint")):
            goal = FollowJointTrajectoryGoal(trajectory=trajectory([name], [(1.0, [0.03])]))
            state, result = self.run_goal(client, goal)
            self.assertEqual(state, GoalStatus.SUCCEEDED, "%s: %s" % (name, result.error_string))
            self.assertAlmostEqual(self.position(name), 0.03, delta=0.002, msg=name)

    def test_7_a_continuous_joint_takes_the_short_way_round(self):
        self.command.publish(trajectory(ARM, [(2.0, [0.0, 0.0, 3.0])]))
        self.ls.sleep(2.5)
        self.assertAlmostEqual(self.position("wrist_joint"), 3.0, delta=0.02)
        # To -3.0 rad: on through pi (+0.28 rad), not back 6 rad, as upstream's wraparound offset.
        t0 = rospy.get_time()
        self.command.publish(trajectory(ARM, [(1.0, [0.0, 0.0, -3.0])]))
        self.ls.sleep(1.5)
        self.assertAlmostEqual(math.remainder(self.position("wrist_joint") + 3.0, 2.0 * math.pi), 0.0, delta=0.02)
        with self.lock:
            passed = [h[1]["wrist_joint"] for h in self.history if h[0] > t0]
        self.assertGreater(min(math.remainder(w - 3.0, 2.0 * math.pi) for w in passed), -0.05, "it turned back")


    def test_8_a_reset_aborts_the_goal_and_nothing_moves_after(self):
        # reset_simulation mid-goal: the goal aborts saying why, the joint states flow again from
        # the new time (until 2026-12-01 joint_state_controller stayed silent until sim time came
        # back to the reset's), nothing moves, and a goal runs again, though stamped before a
        # cancel stamped before the reset (actionlib's memory of it is dropped when time goes back).
        self.arm.send_goal(FollowJointTrajectoryGoal(trajectory=trajectory(ARM, [(4.0, [-1.0, 1.0, 1.0])])))
        self.ls.sleep(0.5)
        self.arm.cancel_goals_at_and_before_time(rospy.Time.now())
        self.assertTrue(self.arm.wait_for_result(rospy.Duration(5)))
        self.assertEqual(self.arm.get_state(), GoalStatus.PREEMPTED)
        self.arm.send_goal(FollowJointTrajectoryGoal(trajectory=trajectory(ARM, [(4.0, [1.5, 1.0, 1.0])])))
        self.ls.sleep(1.0)
        before = rospy.Time.now()
        rospy.wait_for_service("/gazebo/reset_simulation", 30)
        rospy.ServiceProxy("/gazebo/reset_simulation", Empty)()
        self.assertTrue(self.ls.wait_for(lambda: self.arm.get_state() == GoalStatus.ABORTED, 5.0),
                        "the goal was not aborted")
        self.assertIn("restarted by a simulation reset", self.arm.get_goal_status_text())
        self.assertLess(rospy.Time.now(), before, "time did not go back")
        # The checks below read joint states from after the reset.
        back_to = rospy.get_time()
        self.assertTrue(self.ls.wait_for(lambda: self.history[-1][0] <= back_to + 1.0, 5.0),
                        "no joint states after the reset")
        self.ls.sleep(0.5)
        rest = [self.position(n) for n in ARM]
        self.ls.sleep(1.0)
        for n, r in zip(ARM, rest):
            self.assertAlmostEqual(self.position(n), r, delta=1e-3, msg="%s moved after the reset" % n)
        state, result = self.run_goal(self.arm, FollowJointTrajectoryGoal(
            trajectory=trajectory(ARM, [(1.5, [0.4, 0.3, 0.2])])))
        self.assertEqual(state, GoalStatus.SUCCEEDED, result.error_string)
        for name, want in zip(ARM, [0.4, 0.3, 0.2]):
            self.assertAlmostEqual(self.position(name), want, delta=0.02, msg=name)


if __name__ == "__main__":
    rostest.rosrun("mybot_ros_control", "arm_trajectory", ArmTrajectory)
