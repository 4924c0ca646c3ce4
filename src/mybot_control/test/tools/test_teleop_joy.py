#!/usr/bin/env python3
"""Recorded joystick events -> FIFO -> joy_reader -> Joy -> teleop_joy -> cmd_vel."""
import math
import os
import subprocess
import tempfile
import threading
import time
import unittest

import rosgraph
import rospy
import rostest
from geometry_msgs.msg import Twist
from sensor_msgs.msg import Joy

from mybot_control import joy
from mybot_lockstep import publisher_has_link, wait_connected

TIMEOUT = 15.0
AXIS, BUTTON = joy.JS_EVENT_AXIS, joy.JS_EVENT_BUTTON


class Collector:
    def __init__(self, topic, kind):
        self.msgs = []
        self.lock = threading.Lock()
        self.sub = rospy.Subscriber(topic, kind, self.cb, queue_size=100)

    def cb(self, msg):
        with self.lock:
            self.msgs.append(msg)

    def wait_for(self, pred, what, start=0, timeout=TIMEOUT):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            with self.lock:
                for k in range(start, len(self.msgs)):
                    if pred(self.msgs[k]):
                        return k, self.msgs[k]
            time.sleep(0.01)
        raise AssertionError("timed out waiting for %s; last: %s" % (what, self.msgs[-2:]))


def connected(publisher, topic, subscriber):
    """Whether the node `publisher` has added its link carrying `topic` to `subscriber`."""
    try:
        uri = rosgraph.Master(rospy.get_name()).lookupNode(publisher)
    except Exception:
        return False
    return publisher_has_link(uri, topic, subscriber)


def tw(m):
    return (m.linear.x, m.linear.y, m.angular.z)


def near(a, b, tol=1e-6):
    return all(abs(x - y) < tol for x, y in zip(a, b))


class TeleopJoyTest(unittest.TestCase):
    def start_reader(self):
        self.tmp = tempfile.mkdtemp(prefix="joy_test_")
        self.fifo = os.path.join(self.tmp, "js0")
        os.mkfifo(self.fifo)
        self.joy = Collector("joy", Joy)
        self.cmd = Collector("cmd_vel", Twist)
        self.proc = subprocess.Popen(["rosrun", "mybot_control", "joy_reader", "__name:=joy_reader",
                                      "_dev:=" + self.fifo, "_deadzone:=0.1"])
        self.addCleanup(self.stop)
        self.t = 50000  # ms, kernel clock of the recorded events

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            self.proc.wait(timeout=TIMEOUT)
        os.remove(self.fifo)
        os.rmdir(self.tmp)

    def send(self, *events, gap=50):
        """Write one burst of events (same kernel time) to the FIFO, like the driver does."""
        self.t += gap
        data = b"".join(joy.encode_event(self.t, v, kind, n, init) for kind, n, v, init in events)
        fd = os.open(self.fifo, os.O_WRONLY)
        try:
            os.write(fd, data)
        finally:
            os.close(fd)

    def test_deadman_sticks_turbo_and_single_stop(self):
        self.start_reader()
        # joy_reader holds the FIFO open; wait until every link is up on its publisher's side
        # (publisher_has_link): a clean clone's gate (2026-11-30) saw this test linked to
        # joy_reader at 22.599 s, joy_reader's link to it added at 22.604 s, and the first Joy
        # never came. teleop_joy's link from joy_reader too: a Joy sent before it is lost to it.
        wait_connected([self.joy.sub, self.cmd.sub], TIMEOUT)
        end = time.monotonic() + TIMEOUT
        while not connected("/joy_reader", "/joy", "/teleop_joy"):
            self.assertLess(time.monotonic(), end, "joy_reader/teleop_joy did not connect")
            time.sleep(0.05)
        # initial-state burst: 6 buttons, 4 axes, all at rest
        self.send(*([(BUTTON, n, 0, True) for n in range(6)] + [(AXIS, n, 0, True) for n in range(4)]))
        k, m = self.joy.wait_for(lambda m: len(m.buttons) == 6 and len(m.axes) == 4, "initial Joy")
        self.assertEqual(m.header.frame_id, self.fifo)
        kc, c = self.cmd.wait_for(lambda m: True, "the single zero twist of a released deadman")
        self.assertEqual(tw(c), (0.0, 0.0, 0.0))
        # stick moved without deadman: nothing
        self.send((AXIS, 1, -32767, False))
        self.joy.wait_for(lambda m: m.axes[1] > 0.99, "stick forward", start=k + 1)
        # deadman + stick forward/left + right stick X (strafe)
        self.send((BUTTON, 4, 1, False))
        kc, c = self.cmd.wait_for(lambda m: m.linear.x > 0, "drive with deadman", start=kc + 1)
        self.assertTrue(near(tw(c), (0.5, 0.0, 0.0)), tw(c))
        self.send((AXIS, 0, -16384, False), (AXIS, 3, 32767, False))
        expect_yaw = (16384 - 0.1 * 32767) / (0.9 * 32767) * math.pi / 2
        kc, c = self.cmd.wait_for(lambda m: m.angular.z > 0, "turn + strafe", start=kc + 1)
        self.assertTrue(near(tw(c), (0.5, -0.3, expect_yaw), 1e-5), tw(c))
        self.send((BUTTON, 5, 1, False))
        kc, c = self.cmd.wait_for(lambda m: m.linear.x > 0.9, "turbo", start=kc + 1)
        self.assertTrue(near(tw(c), (1.0, -0.6, expect_yaw), 1e-5), tw(c))
        # release both: exactly one zero twist, then silence while the stick moves
        self.send((BUTTON, 5, 0, False), (BUTTON, 4, 0, False))
        kz, c = self.cmd.wait_for(lambda m: tw(m) == (0.0, 0.0, 0.0), "stop on release", start=kc + 1)
        kj = len(self.joy.msgs)
        self.send((AXIS, 1, 20000, False))
        self.send((AXIS, 1, 0, False))
        self.joy.wait_for(lambda m: m.axes[1] == 0.0, "stick back", start=kj + 1)
        self.cmd.sub.unregister()
        self.assertEqual(len(self.cmd.msgs), kz + 1, "no twist may follow the stop while the deadman is up")

    def test_missing_device_exits_with_message(self):
        p = subprocess.run(["rosrun", "mybot_control", "joy_reader", "__name:=joy_missing",
                            "_dev:=/dev/input/js_does_not_exist"], capture_output=True, text=True, timeout=TIMEOUT)
        self.assertEqual(p.returncode, 1)
        self.assertIn("/dev/input/js_does_not_exist", p.stdout + p.stderr)

    def test_bad_deadzone_names_parameter(self):
        p = subprocess.run(["rosrun", "mybot_control", "joy_reader", "__name:=joy_bad", "_deadzone:=1.5"],
                           capture_output=True, text=True, timeout=TIMEOUT)
        self.assertEqual(p.returncode, 2)
        self.assertIn("~deadzone", p.stdout + p.stderr)

    def test_bad_axis_map_names_parameter(self):
        p = subprocess.run(["rosrun", "mybot_control", "teleop_joy", "__name:=teleop_joy_bad",
                            "_axis_linear:={x: 1, y: 3}"], capture_output=True, text=True, timeout=TIMEOUT)
        self.assertEqual(p.returncode, 2)
        self.assertIn("~scale_linear", p.stdout + p.stderr)


if __name__ == "__main__":
    rospy.init_node("test_teleop_joy")
    rostest.rosrun("mybot_control", "teleop_joy", TeleopJoyTest)
