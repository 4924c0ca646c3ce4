#!/usr/bin/python3
"""Lockstep with the simulator in the loop. This node is a participant that takes 20 ms of
wall time over every 10 ms period (a starved node): sim time must wait for it, period by
period, and every period it must see the newest joint states published by then. A second
participant (lockstep_quitter.py) dies without a word: the simulation must go on."""
import sys
import time
import unittest

import rospy
import rostest
from sensor_msgs.msg import JointState

from mybot_lockstep import participant

PERIOD_NS = 10 * 1000 * 1000
JS_PERIOD_NS = 20 * 1000 * 1000  # mybot's joint state publisher at 50 Hz


class LockstepTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('lockstep_test')
        cls.ls = participant()
        cls.js_stamp = None
        cls.ls.Subscriber('joint_states', JointState, cls.on_js, queue_size=10)

    @classmethod
    def on_js(cls, msg):
        cls.js_stamp = msg.header.stamp.to_nsec()

    def test_a_starved_participant_slows_the_simulation(self):
        self.assertTrue(self.ls.active, 'lockstep is not on')
        self.assertTrue(self.ls.wait_for(lambda: self.js_stamp is not None, 30.0), 'no joint_states')
        times, stale = [], []
        t0 = time.monotonic()
        rate = self.ls.Rate(100)
        for _ in range(100):
            now = rospy.get_rostime().to_nsec()
            times.append(now)
            # joint_states come at 50 Hz: the newest must be of this period or the one before.
            if not 0 <= now - self.js_stamp < JS_PERIOD_NS:
                stale.append((now, self.js_stamp))
            time.sleep(0.02)  # busy for two periods' worth of wall time
            rate.sleep()
        wall = time.monotonic() - t0
        steps = sorted(set(b - a for a, b in zip(times, times[1:])))
        rospy.loginfo('lockstep: 100 periods of %s ns in %.2f s of wall time; stale joint states %d',
                      steps, wall, len(stale))
        self.assertEqual(steps, [PERIOD_NS], 'sim time skipped periods while this node was busy')
        self.assertEqual(stale, [], 'saw joint states of an earlier period')
        self.assertGreater(wall, 100 * 0.02)  # it waited for us

    def test_b_a_dead_participant_does_not_stop_the_simulation(self):
        # The quitter exits at 1 s of sim time; time must then keep going without it.
        self.assertTrue(self.ls.wait_for(lambda: rospy.get_time() > 3.0, 60.0), 'sim time stopped after the quitter died')


if __name__ == '__main__':
    rostest.rosrun('mybot_gazebo_lite', 'lockstep', LockstepTest, sys.argv)
