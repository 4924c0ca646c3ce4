#!/usr/bin/python3
"""twist_mux: priority override, timeout fall-back, lock, one zero twist on timeout, diagnostics."""
import sys
import threading
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import Twist
from std_msgs.msg import Bool, String

from mybot_lockstep import participant, wait_connected


class Source:
    """Publishes a constant twist at 20 Hz of sim time while running."""

    def __init__(self, ls, topic, vx):
        self.pub = ls.Publisher(topic, Twist, queue_size=10)
        self.msg = Twist()
        self.msg.linear.x = vx
        self.running = False
        ls.Timer(0.05, self._tick)

    def _tick(self, _):
        if self.running:
            self.pub.publish(self.msg)


class TwistMuxTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('twist_mux_test')
        # A lockstep participant (named in lockstep_wait_for): time starts once it has joined,
        # set up and connected, and each period's messages are in before the period ends.
        cls.ls = participant(defer_join=True)
        cls.lock = threading.Lock()
        cls.out = []
        cls.active = None
        cls.diag = None
        subs = [cls.ls.Subscriber('cmd_vel', Twist, cls._on_out),
                cls.ls.Subscriber('twist_mux/active', String, cls._on_active),
                cls.ls.Subscriber('/diagnostics', DiagnosticArray, cls._on_diag)]
        cls.nav = Source(cls.ls, 'nav_vel', 0.1)
        cls.key = Source(cls.ls, 'key_vel', 0.2)
        cls.joy = Source(cls.ls, 'joy_vel', 0.3)
        cls.pause = cls.ls.Publisher('pause_navigation', Bool, latch=True)
        # A message on a connection not yet open is lost: every one open before time starts.
        wait_connected(subs + [s.pub for s in (cls.nav, cls.key, cls.joy)] + [cls.pause])

    @classmethod
    def _on_out(cls, m):
        with cls.lock:
            cls.out.append((rospy.get_time(), m.linear.x))

    @classmethod
    def _on_active(cls, m):
        cls.active = m.data

    @classmethod
    def _on_diag(cls, m):
        for s in m.status:
            if 'twist mux' in s.name:
                cls.diag = s

    def setUp(self):
        for s in (self.nav, self.key, self.joy):
            s.running = False
        self.pause.publish(Bool(False))
        self.wait(lambda: self.active == 'idle', 'idle')
        with self.lock:
            del self.out[:]

    def wait(self, cond, what, timeout=5.0):
        """Until cond(), within `timeout` s of sim time (joins lockstep on the first call)."""
        if not self.ls.wait_for(cond, timeout):
            self.fail('timed out waiting for ' + what)

    def last(self):
        with self.lock:
            return self.out[-1][1] if self.out else None

    def since(self, t):
        with self.lock:
            return [v for s, v in self.out if s >= t]

    def after_last(self, value, t):
        """What was forwarded after the last `value` received since t: a source's message
        published just before it stopped may still be on its way at t."""
        out = self.since(t)
        while value in out:
            out = out[out.index(value) + 1:]
        return out

    def test_priority_override_and_fall_back(self):
        self.nav.running = True
        self.wait(lambda: self.last() == 0.1 and self.active == 'navigation', 'navigation')
        self.joy.running = True
        self.wait(lambda: self.last() == 0.3 and self.active == 'joystick', 'joystick override')
        t = rospy.get_time()
        self.ls.sleep(0.5)
        self.assertNotIn(0.1, self.since(t))  # navigation is not forwarded meanwhile
        self.joy.running = False
        t = rospy.get_time()
        self.wait(lambda: self.last() == 0.1, 'fall back to navigation')
        self.assertIn(0.0, self.since(t))  # one stop between the two sources

    def test_zero_once_on_timeout(self):
        self.key.running = True
        self.wait(lambda: self.last() == 0.2, 'keyboard')
        self.key.running = False
        t = rospy.get_time()
        self.wait(lambda: self.active == 'idle', 'timeout')
        self.ls.sleep(1.0)
        self.assertEqual(self.after_last(0.2, t), [0.0])  # exactly one zero twist, then silence

    def test_lock(self):
        self.nav.running = True
        self.joy.running = True
        self.wait(lambda: self.last() == 0.3, 'joystick')
        t = rospy.get_time()
        self.pause.publish(Bool(True))
        self.wait(lambda: self.active == 'idle', 'lock to stop everything up to priority 100')
        self.ls.sleep(0.5)
        self.assertEqual(self.after_last(0.3, t), [0.0])
        self.pause.publish(Bool(False))
        self.wait(lambda: self.last() == 0.3, 'joystick after unlock')

    def test_diagnostics(self):
        self.key.running = True
        self.wait(lambda: self.diag is not None and 'keyboard' in self.diag.message, 'diagnostics', timeout=5.0)
        self.assertIn('active', [kv.key for kv in self.diag.values])


if __name__ == '__main__':
    rostest.rosrun('mybot_control', 'twist_mux_rostest', TwistMuxTest, sys.argv)
