#!/usr/bin/env python3
"""Timed moves on the simulated mybot: distance and turn measured on ground truth."""
import math
import subprocess
import threading
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import PointStamped
from nav_msgs.msg import Odometry
from std_msgs.msg import Float64

from mybot_control.measurement import yaw_from_quaternion, wrap

TIMEOUT = 90.0  # wall seconds


class NavTimedSimTest(unittest.TestCase):
    def setUp(self):
        self.lock = threading.Lock()
        self.truth = None
        self.absolute = None
        self.pose_err = None
        rospy.Subscriber("ground_truth/odom", Odometry, self.on_truth, queue_size=10)
        rospy.Subscriber("robot/position/absolute", PointStamped, self.on_abs, queue_size=10)
        rospy.Subscriber("pose_error/position", Float64, self.on_err, queue_size=10)

    def on_truth(self, m):
        q = m.pose.pose.orientation
        with self.lock:
            self.truth = (m.pose.pose.position.x, m.pose.pose.position.y,
                          yaw_from_quaternion(q.x, q.y, q.z, q.w), m.header.stamp.to_sec())

    def on_abs(self, m):
        with self.lock:
            self.absolute = m

    def on_err(self, m):
        with self.lock:
            self.pose_err = m.data

    def settled_pose(self):
        """Ground-truth pose once the robot has been still for 0.5 s of sim time."""
        end = time.monotonic() + TIMEOUT
        last, since = None, None
        while time.monotonic() < end:
            with self.lock:
                t = self.truth
            if t is not None:
                if last is not None and math.hypot(t[0] - last[0], t[1] - last[1]) < 1e-4 \
                        and abs(wrap(t[2] - last[2])) < 1e-3:
                    if t[3] - since >= 0.5:
                        return t
                else:
                    since = t[3]
                last = t
            time.sleep(0.02)
        self.fail("robot did not come to rest")

    def run_launch(self, launch, *args):
        # required="true" nodes end the roslaunch when the move is done
        p = subprocess.run(["roslaunch", "mybot_control", launch] + list(args),
                           capture_output=True, text=True, timeout=TIMEOUT)
        self.assertEqual(p.returncode, 0, p.stdout[-2000:] + p.stderr[-2000:])

    def test_forward_then_rotate(self):
        start = self.settled_pose()
        self.run_launch("nav_forward.launch", "distance:=0.5", "speed:=0.25")
        after = self.settled_pose()
        dist = math.hypot(after[0] - start[0], after[1] - start[1])
        rospy.loginfo("nav_forward: %.4f m, heading change %.4f rad", dist, wrap(after[2] - start[2]))
        self.assertAlmostEqual(dist, 0.5, delta=0.05)
        self.assertLess(abs(wrap(after[2] - start[2])), 0.05)
        with self.lock:
            self.assertIsNotNone(self.absolute)
            self.assertAlmostEqual(self.absolute.point.x, after[0], delta=0.02)
            self.assertIsNotNone(self.pose_err)
            self.assertLess(self.pose_err, 0.05, "diff-drive plugin odometry vs ground truth")
        self.run_launch("nav_rotate.launch", "angle:=1.5707963", "rate:=0.5")
        turned = self.settled_pose()
        rospy.loginfo("nav_rotate: %.4f rad", wrap(turned[2] - after[2]))
        self.assertAlmostEqual(wrap(turned[2] - after[2]), math.pi / 2, delta=0.12)
        self.assertLess(math.hypot(turned[0] - after[0], turned[1] - after[1]), 0.05)


if __name__ == "__main__":
    rospy.init_node("test_nav_timed_sim")
    rostest.rosrun("mybot_control", "nav_timed_sim", NavTimedSimTest)
