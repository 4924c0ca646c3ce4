#!/usr/bin/env python3
"""Timed moves in simulated time: the test publishes /clock and stamps what it receives with it."""
import math
import subprocess
import threading
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from rosgraph_msgs.msg import Clock

TIMEOUT = 30.0  # wall seconds
STEP = 0.005    # s of simulated time per /clock message


class SimClockTest(unittest.TestCase):
    def setUp(self):
        self.lock = threading.Lock()
        self.now = 0.0
        self.got = {ns: [] for ns in ("fwd", "sq", "kb")}
        self.clock = rospy.Publisher("/clock", Clock, queue_size=10)
        self.subs = [rospy.Subscriber("/%s/cmd_vel" % ns, Twist, self.cb, callback_args=ns, queue_size=1000)
                     for ns in self.got]

    def cb(self, msg, ns):
        with self.lock:
            self.got[ns].append((self.now, msg.linear.x, msg.linear.y, msg.angular.z))

    def publish_clock(self, t):
        with self.lock:
            self.now = t
        self.clock.publish(Clock(clock=rospy.Time.from_sec(t)))

    def stopped(self, ns):
        """True once the node moved, then sent a zero twist and has been silent for 1 s of sim time
        (longer than any pause inside a profile)."""
        with self.lock:
            msgs = list(self.got[ns])
            now = self.now
        return (any(any(m[1:]) for m in msgs) and not any(msgs[-1][1:]) and now - msgs[-1][0] > 1.0)

    def test_profiles_in_sim_time(self):
        end = time.monotonic() + TIMEOUT
        while any(s.get_num_connections() == 0 for s in self.subs) or self.clock.get_num_connections() < 3:
            self.assertLess(time.monotonic(), end, "nodes did not connect")
            time.sleep(0.05)
        t = 1.0
        # advance simulated time until every profile has finished (time-limit bounds the wall time)
        while not all(self.stopped(ns) for ns in self.got):
            self.assertLess(time.monotonic(), end + TIMEOUT, "profiles did not finish: %s" % self.got)
            self.assertLess(t, 60.0, "profiles did not finish in 60 s of sim time")
            t += STEP
            self.publish_clock(t)
            time.sleep(0.002)  # pacing only: lets the nodes see each tick
        for _ in range(100):  # a little more time: nothing may follow the stop
            t += STEP
            self.publish_clock(t)
            time.sleep(0.001)
        self.check_forward(self.got["fwd"])
        self.check_square(self.got["sq"])
        self.check_kbot(self.got["kb"])

    def moving_span(self, msgs):
        moving = [m for m in msgs if any(m[1:])]
        stop = [m for m in msgs if not any(m[1:]) and m[0] >= moving[-1][0]]
        self.assertTrue(stop, "no zero twist after the move")
        self.assertFalse(any(any(m[1:]) for m in msgs if m[0] > stop[0][0]), "motion after the stop")
        return moving, stop[0][0] - moving[0][0]

    def check_forward(self, msgs):
        moving, duration = self.moving_span(msgs)
        self.assertTrue(all(m[1:] == (0.25, 0.0, 0.0) for m in moving))
        self.assertAlmostEqual(duration, 2.0, delta=0.05)  # 0.5 m at 0.25 m/s
        # 10 Hz for 2 s; a loaded machine may let a node miss a tick, never add one
        self.assertTrue(10 <= len(moving) <= 21, "10 Hz for 2 s, got %d" % len(moving))

    def check_square(self, msgs):
        moving, duration = self.moving_span(msgs)
        # 4 sides of 0.5 s, 4 turns of 0.5 s, 7 pauses of 0.1 s
        self.assertAlmostEqual(duration, 4.7, delta=0.05)
        kinds = []
        for m in msgs:
            k = "side" if m[1] > 0 else "turn" if m[3] > 0 else "stop"
            if not kinds or kinds[-1] != k:
                kinds.append(k)
        self.assertEqual(kinds[-8:], ["side", "stop", "turn", "stop"] * 2)
        self.assertEqual([k for k in kinds if k != "stop"], ["side", "turn"] * 4)
        self.assertTrue(all(abs(m[3] - math.pi) < 1e-6 for m in moving if m[3]))

    def check_kbot(self, msgs):
        moving, duration = self.moving_span(msgs)
        self.assertTrue(all(m[1:] == (0.3, 0.0, 0.2) for m in moving))
        self.assertAlmostEqual(duration, 1.5, delta=0.05)

    def test_unknown_mode_names_parameter(self):
        p = subprocess.run(["rosrun", "mybot_control", "nav_timed", "__name:=nav_bad", "_mode:=spiral"],
                           capture_output=True, text=True, timeout=TIMEOUT)
        self.assertEqual(p.returncode, 2)
        self.assertIn("~mode", p.stdout + p.stderr)


if __name__ == "__main__":
    rospy.init_node("test_nav_timed")
    rostest.rosrun("mybot_control", "nav_timed", SimClockTest)
