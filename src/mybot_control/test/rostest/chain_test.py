#!/usr/bin/python3
"""Diff-drive chain against the loopback wheels (upstream diff_drive_controller's tests)."""
import math
import sys
import threading
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from std_msgs.msg import Float32

from chain_common import Chain, wrap


class DiffDriveChainTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('diffdrive_chain_test')
        cls.chain = Chain()
        cls.chain.wait_ready(subscribed=('cmd_vel', 'lwheel_tangent_vel_target', 'rwheel_tangent_vel_target'))

    def setUp(self):
        self.chain.pub.publish(Twist())
        self.chain.wait_stopped()
        self.chain.reset_odom()

    def test_forward(self):
        # Upstream testForward: 0.1 m/s for 10 s -> 1 m.
        self.chain.drive(0.1, 0.0, 10.0)
        self.chain.wait_stopped()
        x, y, yaw = self.chain.pose()
        self.assertAlmostEqual(x, 1.0, delta=0.01)
        self.assertLess(abs(y), 0.01)
        self.assertLess(abs(yaw), 0.01)

    def test_turn(self):
        # Upstream testTurn: pi/10 rad/s for 10 s -> pi rad, no translation.
        self.chain.drive(0.0, math.pi / 10.0, 10.0)
        self.chain.wait_stopped()
        x, y, yaw = self.chain.pose()
        self.assertLess(abs(wrap(yaw - math.pi)), 0.03)
        self.assertLess(math.hypot(x, y), 0.01)

    def test_timeout_stops(self):
        # A single 1 m/s message then silence: cmd_vel_timeout (0.5 s) stops the robot.
        msg = Twist()
        msg.linear.x = 1.0
        self.chain.pub.publish(msg)
        self.chain.wait_for(lambda: self.chain.speed()[0] > 0.5, 5.0, 'motion')
        self.chain.wait_stopped(timeout=10.0)
        x, _, _ = self.chain.pose()
        self.assertGreater(x, 0.1)
        self.assertLess(x, 0.8)

    def test_nan(self):
        # NaN/inf commands are ignored: no NaN anywhere in the chain.
        values = []
        lock = threading.Lock()
        recording = [True]

        def record(m):
            with lock:
                if recording[0]:
                    values.append(m.data)
        for t in ('lwheel_tangent_vel_target', 'rwheel_tangent_vel_target',
                  'lwheel_angular_vel_motor', 'rwheel_angular_vel_motor'):
            self.chain.subscribe(t, Float32, record)
        self.chain.wait_connected()
        self.chain.drive(0.1, 0.0, 1.0)
        bad = Twist()
        bad.linear.x = float('nan')
        bad.angular.z = float('inf')
        for _ in range(20):
            self.chain.pub.publish(bad)
            self.chain.ls.sleep(0.02)  # sim time; under lockstep it waits for this test
        self.chain.wait_stopped(timeout=10.0)
        self.chain.drive(0.1, 0.0, 1.0)
        self.chain.wait_stopped()
        with lock:
            recording[0] = False  # kept subscribed: a lockstep subscription ends with the test
        x, y, yaw = self.chain.pose()
        vx, wz = self.chain.speed()
        for v in (x, y, yaw, vx, wz):
            self.assertTrue(math.isfinite(v))
        with lock:
            self.assertGreater(len(values), 50)
            self.assertTrue(all(math.isfinite(v) for v in values))
        self.assertAlmostEqual(x, 0.2, delta=0.02)


if __name__ == '__main__':
    rostest.rosrun('mybot_control', 'diffdrive_chain', DiffDriveChainTest, sys.argv)
