#!/usr/bin/env python3
"""Timed moves in simulated time, in lockstep with gazebo_lite's clock: the test takes part and
stamps each twist with the period in which it handles it, so the profile's timing is exact on an
idle and on a busy machine."""
import math
import subprocess
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist

from mybot_lockstep import participant

TIMEOUT = 30.0  # wall seconds


class SimClockTest(unittest.TestCase):
    def subscribe(self):
        self.ls = participant()
        self.got = {ns: [] for ns in ("fwd", "sq", "kb")}
        for ns in self.got:
            self.ls.Subscriber("/%s/cmd_vel" % ns, Twist, lambda m, ns=ns: self.cb(m, ns), queue_size=1000)

    def cb(self, msg, ns):
        # Under lockstep, a twist published in period k is handed over in period k+1: every
        # stamp is one period late, durations are exact.
        self.got[ns].append((rospy.get_time(), msg.linear.x, msg.linear.y, msg.angular.z))

    def stopped(self, ns):
        """True once the node moved, then sent a zero twist and has been silent for 1 s of sim time
        (longer than any pause inside a profile)."""
        msgs = self.got[ns]
        return (any(any(m[1:]) for m in msgs) and not any(msgs[-1][1:])
                and rospy.get_time() - msgs[-1][0] > 1.0)

    def test_profiles_in_sim_time(self):
        # Time starts once the three nodes and this test take part (lockstep_wait_for); each
        # node starts its profile once this test's subscription is connected.
        self.subscribe()
        self.assertTrue(self.ls.wait_for(lambda: all(self.stopped(ns) for ns in self.got), timeout=60.0),
                        "profiles did not finish in 60 s of sim time: %s" % self.got)
        self.ls.wait_for(lambda: False, timeout=0.5)  # a little more time: nothing may follow the stop
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
        self.assertAlmostEqual(duration, 2.0, delta=1e-6)  # 0.5 m at 0.25 m/s
        self.assertEqual(len(moving), 20, "10 Hz for 2 s")

    def check_square(self, msgs):
        moving, duration = self.moving_span(msgs)
        # 4 sides of 0.5 s, 4 turns of 0.5 s, 7 pauses of 0.1 s
        self.assertAlmostEqual(duration, 4.7, delta=1e-6)
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
        self.assertAlmostEqual(duration, 1.5, delta=1e-6)

    def test_unknown_mode_names_parameter(self):
        p = subprocess.run(["rosrun", "mybot_control", "nav_timed", "__name:=nav_bad", "_mode:=spiral"],
                           capture_output=True, text=True, timeout=TIMEOUT)
        self.assertEqual(p.returncode, 2)
        self.assertIn("~mode", p.stdout + p.stderr)


if __name__ == "__main__":
    rospy.init_node("test_nav_timed")
    rostest.rosrun("mybot_control", "nav_timed", SimClockTest)
