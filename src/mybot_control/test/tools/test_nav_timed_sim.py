#!/usr/bin/env python3
"""Timed moves on the simulated mybot: distance and turn measured on ground truth.

In lockstep: this test joins with its subscriptions made (named in lockstep_wait_for), and starts
each move while the simulation is paused (mybot_lockstep.start_paused), so every move begins in
the same period on every run and the figures repeat exactly."""
import math
import subprocess
import threading
import unittest

import rospy
import rostest
from geometry_msgs.msg import PointStamped, Twist
from nav_msgs.msg import Odometry
from std_msgs.msg import Float64

from mybot_control.measurement import yaw_from_quaternion, wrap
from mybot_lockstep import participant
from mybot_lockstep.start_paused import finish, start_paused

TIMEOUT = 90.0  # s of sim time


class NavTimedSimTest(unittest.TestCase):
    def setUp(self):
        self.lock = threading.Lock()
        self.truth = None
        self.absolute = None
        self.pose_err = None
        self.history = []  # ground truth (x, y, yaw, stamp), each sample in its period
        self.cmds = []  # (stamp of the period, moving) of every cmd_vel the moves sent
        self.procs = []
        self.ls = participant(defer_join=True)
        self.ls.Subscriber("ground_truth/odom", Odometry, self.on_truth, queue_size=50)
        self.ls.Subscriber("cmd_vel", Twist, self.on_cmd, queue_size=50)
        # Not participants (their nodes are plain rospy): they arrive whenever their nodes get to
        # them, so the test reads them only once one stamped (or received) after the robot came to
        # rest is in (fresh_readings).
        rospy.Subscriber("robot/position/absolute", PointStamped, self.on_abs, queue_size=10)
        rospy.Subscriber("pose_error/position", Float64, self.on_err, queue_size=10)
        self.ls.hold_next_period()  # joins; from here on period by period

    def tearDown(self):
        # The moves' processes end in wall time (nav_timed lingers after its last twist).
        self.ls.release()
        for proc, launch in self.procs:
            code, out = finish(proc)
            self.assertEqual(code, 0, "%s: %s" % (launch, out[-3000:]))

    def on_truth(self, m):
        q = m.pose.pose.orientation
        with self.lock:
            self.truth = (m.pose.pose.position.x, m.pose.pose.position.y,
                          yaw_from_quaternion(q.x, q.y, q.z, q.w), m.header.stamp.to_sec())
            self.history.append(self.truth)

    def on_cmd(self, m):
        self.cmds.append((rospy.get_time(), abs(m.linear.x) + abs(m.angular.z) > 1e-9))

    def on_abs(self, m):
        with self.lock:
            self.absolute = m

    def on_err(self, m):
        with self.lock:
            self.pose_err = (rospy.get_time(), m.data)

    def fresh_readings(self, since):
        """Waits until robot/position/absolute is stamped at or after `since` (s of sim time) and a
        pose_error/position has been received after it; returns (absolute point, pose error)."""
        def fresh():
            with self.lock:
                return (self.absolute is not None and self.absolute.header.stamp.to_sec() >= since
                        and self.pose_err is not None and self.pose_err[0] > since)
        if not self.ls.wait_for(fresh, TIMEOUT):
            with self.lock:
                self.fail("no robot/position/absolute stamped and pose_error/position received after "
                          "%.3f s in %.0f s of sim time (last: %s, %s)" % (since, TIMEOUT, self.absolute,
                                                                         self.pose_err))
        with self.lock:
            return self.absolute.point, self.pose_err[1]

    def still(self):
        """Whether ground truth has moved less than 0.1 mm and 1 mrad between successive samples
        over the last 0.5 s of sim time."""
        with self.lock:
            h = self.history
            if not h or h[-1][3] - h[0][3] < 0.5:
                return False
            i = len(h) - 1
            while i > 0 and h[-1][3] - h[i - 1][3] <= 0.5:
                i -= 1
            window = h[max(i - 1, 0):]
        return all(math.hypot(b[0] - a[0], b[1] - a[1]) < 1e-4 and abs(wrap(b[2] - a[2])) < 1e-3
                   for a, b in zip(window, window[1:]))

    def settled_pose(self):
        """Ground-truth pose once the robot has been still for 0.5 s of sim time."""
        if not self.ls.wait_for(self.still, TIMEOUT):
            self.fail("robot did not come to rest in %.0f s of sim time" % TIMEOUT)
        with self.lock:
            return self.truth

    def run_launch(self, launch, node, *args):
        """roslaunch mybot_control `launch` (a nav_timed move), started while the simulation is
        paused; returns once the move has sent its last twist (a zero after moving)."""
        t0 = rospy.get_time()
        proc = start_paused(self.ls, ["roslaunch", "mybot_control", launch] + list(args), node,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.procs.append((proc, launch))
        done = lambda: any(m for t, m in self.cmds if t >= t0) and not self.cmds[-1][1]  # noqa: E731
        if not self.ls.wait_for(done, TIMEOUT):
            self.fail("%s did not move and stop in %.0f s of sim time" % (launch, TIMEOUT))

    def test_forward_then_rotate(self):
        start = self.settled_pose()
        self.run_launch("nav_forward.launch", "/nav_forward", "distance:=0.5", "speed:=0.25")
        after = self.settled_pose()
        dist = math.hypot(after[0] - start[0], after[1] - start[1])
        rospy.loginfo("nav_forward: %.4f m, heading change %.4f rad", dist, wrap(after[2] - start[2]))
        self.assertAlmostEqual(dist, 0.5, delta=0.05)
        self.assertLess(abs(wrap(after[2] - start[2])), 0.05)
        absolute, pose_err = self.fresh_readings(after[3])
        self.assertAlmostEqual(absolute.x, after[0], delta=0.02)
        self.assertLess(pose_err, 0.05, "diff-drive plugin odometry vs ground truth")
        self.run_launch("nav_rotate.launch", "/nav_rotate", "angle:=1.5707963", "rate:=0.5")
        turned = self.settled_pose()
        rospy.loginfo("nav_rotate: %.4f rad", wrap(turned[2] - after[2]))
        self.assertAlmostEqual(wrap(turned[2] - after[2]), math.pi / 2, delta=0.12)
        self.assertLess(math.hypot(turned[0] - after[0], turned[1] - after[1]), 0.05)


if __name__ == "__main__":
    rospy.init_node("test_nav_timed_sim")
    rostest.rosrun("mybot_control", "nav_timed_sim", NavTimedSimTest)
