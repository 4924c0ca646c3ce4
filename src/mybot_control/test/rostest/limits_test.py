#!/usr/bin/python3
"""Speed limits through the chain (upstream diff_drive_limits_test with diffbot_limits.yaml,
plus jerk checked step by step on ~cmd_vel_out and a separate deceleration limit)."""
import sys
import threading
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist, TwistStamped

from chain_common import Chain

TOL = 0.05


class LimitsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('diffdrive_limits_test')
        cls.chain = Chain()
        cls.lock = threading.Lock()
        cls.out = []
        cls.chain.subscribe('diffdrive_controller/cmd_vel_out', TwistStamped, cls._on_out, queue_size=100)
        cls.chain.wait_ready()

    @classmethod
    def _on_out(cls, m):
        with cls.lock:
            cls.out.append((m.header.stamp.to_sec(), m.twist.linear.x, m.twist.angular.z))

    def setUp(self):
        self.chain.pub.publish(Twist())
        self.chain.wait_stopped(timeout=10.0)
        self.chain.reset_odom()
        with self.lock:
            del self.out[:]

    def series(self, axis):
        with self.lock:
            return [(t, v[axis]) for t, *v in self.out]

    def check_rates(self, axis, max_acc, max_dec, max_jerk, v_limit):
        s = self.series(axis)
        self.assertGreater(len(s), 20)
        acc = []
        for (t0, v0), (t1, v1) in zip(s, s[1:]):
            if t1 <= t0:
                continue
            a = (v1 - v0) / (t1 - t0)
            braking = abs(v1) < abs(v0)
            self.assertLessEqual(abs(a), (max_dec if braking else max_acc) + 1e-3,
                                 'acceleration %.3f at t=%.3f' % (a, t1))
            acc.append((t1, a, v1))
        # Jerk everywhere, except the single step that lands exactly on the velocity limit or
        # on zero: steps are event-driven and uneven, so the last one of a ramp may be cut by
        # up to j*dt^2 (a few mm/s) to land exactly instead of overshooting.
        for k, ((t0, a0, _), (t1, a1, v1)) in enumerate(zip(acc, acc[1:])):
            if abs(abs(v1) - v_limit) < 1e-9 or abs(v1) < 1e-9:
                continue
            self.assertLessEqual(abs(a1 - a0) / (t1 - t0), max_jerk + 1e-2, 'jerk at t=%.3f: %s' % (
                t1, [(round(t, 4), round(a, 3), round(v, 4)) for t, a, v in acc[max(0, k - 4):k + 4]]))

    def test_linear_acceleration_and_jerk(self):
        # Upstream: a 10 m/s command for 0.5 s under 1 m/s^2 -> at most 0.5 m/s.
        self.chain.drive(10.0, 0.0, 0.5)
        vx = max(v for _, v in self.series(0))
        self.assertLessEqual(vx, 0.5 + TOL)
        self.assertGreater(vx, 0.0)
        self.chain.wait_stopped(timeout=10.0)
        self.check_rates(0, 1.0, 2.0, 5.0, 1.0)

    def test_linear_velocity_and_deceleration(self):
        # Upstream: 10 m/s for 5 s -> capped at 1 m/s, so less than 5 m travelled.
        self.chain.drive(10.0, 0.0, 5.0)
        x_cmd_end = self.chain.pose()[0]
        t_stop = rospy.get_time()
        self.chain.wait_stopped(timeout=10.0)
        x, y, _ = self.chain.pose()
        self.assertLess(x, 5.0 + TOL)
        # Each wheel's command reaches the loopback on its own (a 2 ms tick may fall between
        # them), so during the ramps one wheel can lead by a tick: ~1% of 4 m of heading skew.
        self.assertLess(abs(y), 0.05)
        self.assertLessEqual(max(v for _, v in self.series(0)), 1.0 + 1e-6)
        self.assertLessEqual(max(abs(v) for _, v in self.series(1)), 1e-9)
        # Braking at 2 m/s^2 (not min_acceleration's 0.5): stops within ~0.5 s + jerk ramp.
        stop_time = next(t for t, v in self.series(0) if t > t_stop and abs(v) < 1e-6) - t_stop
        self.assertLess(stop_time, 1.2)
        self.assertLess(x - x_cmd_end, 0.7)
        self.check_rates(0, 1.0, 2.0, 5.0, 1.0)

    def test_angular_limits(self):
        # Upstream: 10 rad/s for 0.5 s under 2 rad/s^2 -> at most 1 rad/s; later at most 2 rad/s.
        self.chain.drive(0.0, 10.0, 0.5)
        self.assertLessEqual(max(v for _, v in self.series(1)), 1.0 + TOL)
        self.chain.drive(0.0, 10.0, 2.0)
        self.assertLessEqual(max(v for _, v in self.series(1)), 2.0 + 1e-6)
        self.assertGreater(max(v for _, v in self.series(1)), 1.9)
        self.assertLessEqual(max(abs(v) for _, v in self.series(0)), 1e-9)
        self.chain.wait_stopped(timeout=10.0)
        self.check_rates(1, 2.0, 2.0, 10.0, 2.0)


if __name__ == '__main__':
    rostest.rosrun('mybot_control', 'diffdrive_limits', LimitsTest, sys.argv)
