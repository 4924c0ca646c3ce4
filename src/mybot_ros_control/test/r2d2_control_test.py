#!/usr/bin/env python3
"""The r2d2 of the ROS tutorial driven through gazebo_ros_control, measured by ground truth:
controllers listed running, wheels driven by diff_drive_controller, head and gripper at their
commanded positions, a bad controller refused with a message naming it and the field."""
import math
import os
import signal
import subprocess
import sys
import threading
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64, Float64MultiArray

from mybot_common.geometry import wrap, yaw_of
from control_msgs.msg import JointControllerState
from controller_manager_msgs.srv import ListControllers, LoadController, SwitchController
from gazebo_msgs.srv import GetModelState
from mybot_lockstep import participant
from mybot_lockstep.start_paused import unpause_when

from controller_test import refusal

CM = "/controller_manager/"


def wall_wait(predicate, timeout):
    """Polls `predicate` for up to `timeout` s of wall time (if this test holds its period, sim time
    stands meanwhile): for a process that is no lockstep participant. True once it holds."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.02)
    return predicate()


class R2d2Control(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("r2d2_control_test")
        # Joins at its first sleep, with everything below set up (named in lockstep_wait_for).
        cls.ls = participant(defer_join=True)
        cls.lock = threading.Lock()
        cls.joints = None
        cls.odom = None
        cls.ext_state = None
        cls.ls.Subscriber("/joint_states", JointState, cls._store("joints"))
        cls.ls.Subscriber("/diff_drive_controller/odom", Odometry, cls._store("odom"))
        cls.ls.Subscriber("/extension_controller/state", JointControllerState, cls._store("ext_state"))
        cls.cmd = cls.ls.Publisher("/diff_drive_controller/cmd_vel", Twist, queue_size=1)
        cls.head = cls.ls.Publisher("/head_controller/command", Float64, queue_size=1)
        cls.gripper = cls.ls.Publisher("/gripper_controller/command", Float64MultiArray, queue_size=1)
        cls.extension = cls.ls.Publisher("/extension_controller/command", Float64, queue_size=1)
        for s in ("list_controllers", "load_controller", "switch_controller"):
            rospy.wait_for_service(CM + s, timeout=60)
        rospy.wait_for_service("/gazebo/get_model_state", timeout=60)
        cls.list = rospy.ServiceProxy(CM + "list_controllers", ListControllers)
        cls.load = rospy.ServiceProxy(CM + "load_controller", LoadController)
        cls.switch = rospy.ServiceProxy(CM + "switch_controller", SwitchController)
        cls.model = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)
        # The world starts paused and stays so until the spawner has started the five controllers
        # (the manager switches them in its service call, time standing): the robot is dropped
        # with its controllers running, at the same period on every run.
        unpause_when(cls.ls, lambda: sum(c.state == "running" for c in cls.list().controller) == 5,
                     "the spawner did not start the five controllers")
        # Until the dropped robot rests (ground truth still to 1 mm for 0.5 s of sim time), its
        # height included: a fall or a bounce moves it along z alone.
        last = [None, None]

        def resting():
            s = cls.model(model_name="r2d2", relative_entity_name="world")
            t, p = s.header.stamp.to_sec(), s.pose.position
            if last[0] is None or math.dist((p.x, p.y, p.z), last[0][1:]) > 0.001:
                last[0], last[1] = (t, p.x, p.y, p.z), t
            return t - last[1] >= 0.5
        assert cls.ls.wait_for(resting, 30.0, period=0.1), "the robot did not come to rest"

    @classmethod
    def _store(cls, name):
        def cb(m):
            with cls.lock:
                setattr(cls, name, m)
        return cb

    def pose(self):
        return self.stamped_pose()[1:]

    def stamped_pose(self):
        """(sim time of the pose, x, y, yaw): the simulator's own stamp, not this process's clock,
        which follows /clock on another thread and can be periods off the pose it is paired with."""
        s = self.model(model_name="r2d2", relative_entity_name="world")
        p = s.pose
        return s.header.stamp.to_sec(), p.position.x, p.position.y, yaw_of(p.orientation)

    def joint(self, name):
        with self.lock:
            js = self.joints
        return None if js is None or name not in js.name else js.position[js.name.index(name)]

    def test_1_controllers_are_listed_running_with_their_joints(self):
        cs = {c.name: c for c in self.list().controller}
        self.assertEqual(cs["diff_drive_controller"].type, "diff_drive_controller/DiffDriveController")
        self.assertEqual(cs["head_controller"].state, "running")
        res = {r.hardware_interface: list(r.resources) for r in cs["gripper_controller"].claimed_resources}
        self.assertEqual(res, {"hardware_interface/PositionJointInterface": ["left_gripper_joint", "right_gripper_joint"]})
        self.assertEqual(cs["joint_state_controller"].claimed_resources, [])
        self.assertTrue(self.ls.wait_for(lambda: self.joint("head_swivel") is not None, 5.0), "no joint_states")
        with self.lock:
            self.assertEqual(len(self.joints.name), 8)

    def test_2_drives_straight_the_commanded_distance(self):
        x0, y0, th0 = self.pose()
        rate = self.ls.Rate(50)
        t0 = rospy.get_time()
        start = None
        while rospy.get_time() - t0 < 6.0:
            self.cmd.publish(self._twist(0.2, 0.0))
            if start is None and rospy.get_time() - t0 >= 1.0:  # past the 0.33 s acceleration ramp
                start = self.stamped_pose()
            rate.sleep()
        end = self.stamped_pose()
        self._stop()
        dist = math.hypot(end[1] - start[1], end[2] - start[2])
        expected = 0.2 * (end[0] - start[0])
        rospy.loginfo("r2d2: drove %.4f m in %.2f s of sim time, commanded %.4f m", dist, end[0] - start[0], expected)
        self.assertLess(abs(dist - expected) / expected, 0.02, "drove %.4f m, commanded %.4f m" % (dist, expected))
        self.assertLess(abs(math.degrees(wrap(end[3] - th0))), 2.0, "heading drifted %.2f deg" % math.degrees(end[3] - th0))
        self.assertGreater(math.hypot(end[1] - x0, end[2] - y0), 1.0)
        with self.lock:
            self.assertEqual(self.odom.header.frame_id, "odom")
            self.assertEqual(self.odom.child_frame_id, "base_link")

    def test_3_turns_as_commanded(self):
        def odom_yaw():
            with self.lock:
                return yaw_of(self.odom.pose.pose.orientation)
        rate = self.ls.Rate(50)
        t0 = rospy.get_time()
        start = None
        turned = odom_turned = 0.0
        while rospy.get_time() - t0 < 4.0:
            self.cmd.publish(self._twist(0.0, 0.5))
            th, oth = self.pose()[2], odom_yaw()
            if start is None and rospy.get_time() - t0 >= 1.0:  # past the acceleration ramp
                start, last, olast = rospy.get_time(), th, oth
            elif start is not None:
                turned += wrap(th - last)
                odom_turned += wrap(oth - olast)
                last, olast = th, oth
            rate.sleep()
        commanded = 0.5 * (rospy.get_time() - start)
        self._stop()
        # The wheels turn as commanded (the encoders' odometry within 2 %) ...
        self.assertLess(abs(odom_turned - commanded) / commanded, 0.02,
                        "odometry turned %.3f rad of %.3f" % (odom_turned, commanded))
        # ... and the body less: four wheels on a diff drive skid sideways when they turn (67 %
        # here; in Gazebo too, which is what wheel_separation_multiplier is for).
        self.assertGreater(turned, 0.5 * commanded, "turned %.3f rad of %.3f" % (turned, commanded))
        self.assertLess(turned, commanded, "turned %.3f rad of %.3f" % (turned, commanded))

    def test_4_head_and_gripper_reach_their_commands(self):
        rate = self.ls.Rate(20)
        ok = False
        t0 = rospy.get_time()
        while rospy.get_time() - t0 < 5.0 and not ok:
            self.head.publish(Float64(1.0))
            self.gripper.publish(Float64MultiArray(data=[0.3, 0.3]))
            self.extension.publish(Float64(-0.2))
            rate.sleep()
            ok = all(self.joint(j) is not None for j in ("head_swivel", "left_gripper_joint", "gripper_extension")) and \
                abs(self.joint("head_swivel") - 1.0) < 0.01 and abs(self.joint("left_gripper_joint") - 0.3) < 0.01 and \
                abs(self.joint("right_gripper_joint") - 0.3) < 0.01 and abs(self.joint("gripper_extension") + 0.2) < 0.01
        self.assertTrue(ok, "head %s, grippers %s %s, extension %s" % (
            self.joint("head_swivel"), self.joint("left_gripper_joint"), self.joint("right_gripper_joint"),
            self.joint("gripper_extension")))
        with self.lock:
            self.assertAlmostEqual(self.ext_state.set_point, -0.2)
            self.assertAlmostEqual(self.ext_state.p, 2000.0)

    def test_5_bad_controllers_are_refused_naming_controller_and_field(self):
        rospy.set_param("/bad_joint_controller", {"type": "position_controllers/JointPositionController", "joint": "head_swivl"})
        self.assertFalse(self.load(name="bad_joint_controller").ok)
        why = refusal(lambda cm: cm.load("bad_joint_controller"))
        self.assertIn("bad_joint_controller", why)
        self.assertIn("/bad_joint_controller/joint", why)
        self.assertIn("head_swivl", why)
        rospy.set_param("/bad_type_controller", {"type": "effort_controllers/JointTrajectoryController", "joint": "head_swivel"})
        self.assertFalse(self.load(name="bad_type_controller").ok)
        why = refusal(lambda cm: cm.load("bad_type_controller"))
        self.assertIn("bad_type_controller", why)
        self.assertIn("JointTrajectoryController", why)
        rospy.set_param("/bad_pid_controller", {"type": "effort_controllers/JointPositionController", "joint": "gripper_extension",
                                                "pid": {"i": 1.0}})
        self.assertFalse(self.load(name="bad_pid_controller").ok)
        self.assertIn("/bad_pid_controller/pid/p", refusal(lambda cm: cm.load("bad_pid_controller")))
        # The spawner says it too, and fails (controller_manager's, as launch files run it).
        p = self.run_tool("spawner", "bad_joint_controller")
        self.assertNotEqual(p.returncode, 0)
        self.assertIn("/bad_joint_controller/joint", p.stdout + p.stderr)

    def test_6_a_joint_has_one_commanding_controller(self):
        rospy.set_param("/head_too", {"type": "position_controllers/JointPositionController", "joint": "head_swivel"})
        self.assertTrue(self.load(name="head_too").ok)
        self.assertFalse(self.switch(start_controllers=["head_too"], stop_controllers=[], strictness=2).ok)
        why = refusal(lambda cm: cm.switch(start=["head_too"]))
        self.assertIn("head_swivel", why)
        self.assertIn("head_controller", why)
        # Swapping them in one switch is fine.
        res = self.switch(start_controllers=["head_too"], stop_controllers=["head_controller"], strictness=2)
        self.assertTrue(res.ok)
        states = {c.name: c.state for c in self.list().controller}
        self.assertEqual((states["head_too"], states["head_controller"]), ("running", "stopped"))

    def states(self):
        return {c.name: c.state for c in self.list().controller}

    def run_tool(self, *argv):
        """`rosrun controller_manager ARGV...` as a launch file runs it; its exit code and output.
        Released first: a tool takes seconds to start, and a period held that long drops this
        test from lockstep (10 s)."""
        self.ls.release()
        return subprocess.run(["rosrun", "controller_manager"] + list(argv), capture_output=True, text=True,
                              timeout=60, env=dict(os.environ))

    def test_7_controller_groups_switch_as_one(self):
        # After test 6: head_too runs, head_controller is stopped.
        rospy.set_param("/controller_groups", {"head_a": ["head_controller"], "head_b": ["head_too"],
                                               "drive": ["diff_drive_controller"]})
        p = self.run_tool("controller_group", "list")
        self.assertIn("Number of groups: 3", p.stdout)
        p = self.run_tool("controller_group", "switch", "head_a")
        self.assertEqual(p.returncode, 0, p.stderr)
        s = self.states()
        # The other groups' running controllers stop: head_too, and the drive too.
        self.assertEqual((s["head_controller"], s["head_too"], s["diff_drive_controller"]),
                         ("running", "stopped", "stopped"))
        p = self.run_tool("controller_group", "spawn", "drive")  # spawn leaves the other groups be
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual((self.states()["diff_drive_controller"], self.states()["head_controller"]),
                         ("running", "running"))
        p = self.run_tool("controller_group", "switch", "head_c")
        self.assertEqual(p.returncode, 1)
        self.assertIn("/controller_groups/head_c", p.stderr)
        self.assertEqual(self.states()["head_controller"], "running")  # nothing switched

    def test_8_the_unspawner_keeps_controllers_stopped_until_killed(self):
        self.assertEqual(self.states()["head_controller"], "running")
        stopped = lambda: self.states()["head_controller"] == "stopped"  # noqa: E731
        self.ls.release()  # the tool takes seconds to start (see run_tool)
        tool = subprocess.Popen(["rosrun", "controller_manager", "unspawner", "head_controller"], env=dict(os.environ),
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        try:
            self.assertTrue(wall_wait(stopped, 60.0), "the unspawner did not stop head_controller")
            # Started behind its back, it is stopped again at a next look, a second of sim time on.
            # The unspawner is no lockstep participant and looks on its own clock: time runs a
            # second at a time, and the test holds each second until it has looked.
            self.assertTrue(self.switch(start_controllers=["head_controller"], stop_controllers=[], strictness=2).ok)
            self.assertEqual(self.states()["head_controller"], "running")
            again = False
            for _ in range(30):
                self.ls.sleep(1.0)
                again = wall_wait(stopped, 5.0)
                if again:
                    break
            self.assertTrue(again, "the unspawner let head_controller run")
        finally:
            tool.send_signal(signal.SIGINT)  # as roslaunch stops it
            out, _ = tool.communicate(timeout=60)
        self.assertEqual(tool.returncode, 0, out)
        self.assertEqual(self.states()["head_controller"], "running", out)

    @staticmethod
    def _twist(v, w):
        t = Twist()
        t.linear.x = v
        t.angular.z = w
        return t

    def _stop(self):
        rate = self.ls.Rate(50)
        for _ in range(50):
            self.cmd.publish(self._twist(0.0, 0.0))
            rate.sleep()


if __name__ == "__main__":
    rostest.rosrun("mybot_ros_control", "r2d2_control", R2d2Control, sys.argv)
