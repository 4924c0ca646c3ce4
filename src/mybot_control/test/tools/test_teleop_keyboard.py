#!/usr/bin/env python3
"""Drive teleop_keyboard through a pseudo-terminal and check what it publishes on cmd_vel."""
import os
import pty
import select
import subprocess
import threading
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist, TwistStamped

TIMEOUT = 15.0


class Collector:
    def __init__(self, topic, kind):
        self.msgs = []
        self.lock = threading.Lock()
        self.sub = rospy.Subscriber(topic, kind, self.cb, queue_size=100)

    def cb(self, msg):
        with self.lock:
            self.msgs.append(msg)

    def wait_for(self, pred, what, start=0, timeout=TIMEOUT):
        """First message at index >= start satisfying pred, as (index, message)."""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            with self.lock:
                for k in range(start, len(self.msgs)):
                    if pred(self.msgs[k]):
                        return k, self.msgs[k]
            time.sleep(0.01)
        raise AssertionError("timed out waiting for %s; got %s" % (what, self.msgs[-3:]))


def twist_of(m):
    t = m.twist if hasattr(m, "twist") else m
    return (t.linear.x, t.linear.y, t.linear.z, t.angular.z)


def close(a, b):
    return all(abs(x - y) < 1e-6 for x, y in zip(a, b))


class TeleopKeyboardTest(unittest.TestCase):
    def spawn(self, name, *params):
        master, slave = pty.openpty()
        proc = subprocess.Popen(["rosrun", "mybot_control", "teleop_keyboard", "__name:=" + name] + list(params),
                                stdin=slave, stdout=slave, stderr=slave, close_fds=True)
        os.close(slave)
        self.addCleanup(self.reap, proc, master)
        return proc, master

    def reap(self, proc, master):
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        os.close(master)

    @staticmethod
    def read_all(master, until=None, timeout=TIMEOUT):
        out = b""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            r, _, _ = select.select([master], [], [], 0.05)
            if r:
                try:
                    chunk = os.read(master, 4096)
                except OSError:
                    break
                if not chunk:
                    break
                out += chunk
                if until is not None and until in out:
                    break
        return out.decode("utf-8", "replace")

    def test_keys_publish_twists_and_ctrl_c_stops(self):
        col = Collector("/k1/cmd_vel", Twist)
        proc, master = self.spawn("teleop_k1", "cmd_vel:=/k1/cmd_vel", "_key_timeout:=0.0")
        # Up to the end of the status line: the pty may hand over "currently:" before the rest.
        banner = self.read_all(master, until=b"turn 1.0")
        self.assertIn("Reading from the keyboard  and Publishing to Twist!", banner)
        self.assertIn("currently:\tspeed 0.5\tturn 1.0", banner)
        col.wait_for(lambda m: close(twist_of(m), (0, 0, 0, 0)), "initial zero twist")
        os.write(master, b"i")
        col.wait_for(lambda m: close(twist_of(m), (0.5, 0, 0, 0)), "forward twist")
        os.write(master, b"J")
        col.wait_for(lambda m: close(twist_of(m), (0, 0.5, 0, 0)), "strafe left (holonomic)")
        os.write(master, b"q")
        col.wait_for(lambda m: close(twist_of(m), (0, 0.55, 0, 0)), "strafe at 110% speed")
        self.assertIn("speed 0.55", self.read_all(master, until=b"0.55"))
        os.write(master, b"u")
        col.wait_for(lambda m: close(twist_of(m), (0.55, 0, 0, 1.1)), "forward-left arc at new speeds")
        n_before = len(col.msgs)
        os.write(master, b"\x03")
        self.assertEqual(proc.wait(timeout=TIMEOUT), 0)
        k, _ = col.wait_for(lambda m: close(twist_of(m), (0, 0, 0, 0)), "zero twist on exit", start=n_before)
        self.assertTrue(close(twist_of(col.msgs[-1]), (0, 0, 0, 0)), "last message must stop the robot")

    def test_key_timeout_repeat_and_stamped(self):
        col = Collector("/k2/cmd_vel", TwistStamped)
        proc, master = self.spawn("teleop_k2", "cmd_vel:=/k2/cmd_vel", "_key_timeout:=0.5",
                                  "_repeat_rate:=20.0", "_stamped:=true", "_frame_id:=base_link")
        self.read_all(master, until=b"currently:")
        # Wall time (no sim time here) before the key exists: the node reads it later, so its stop
        # is stamped key_timeout after this at least, however late either side runs. (Measured
        # from the first twist's stamp, the bound had to leave room for the node's own delay
        # between reading the key and stamping, and for a first twist dropped by a busy writer.)
        typed = rospy.get_time()
        os.write(master, b"l")
        k, m = col.wait_for(lambda m: close(twist_of(m), (0, 0, 0, -1.0)), "turn right")
        self.assertEqual(m.header.frame_id, "base_link")
        # no further key: repeats at 20 Hz, then the key timeout stops the robot
        kz, mz = col.wait_for(lambda m: close(twist_of(m), (0, 0, 0, 0)), "stop after key_timeout",
                              start=k + 1)
        repeats = kz - k - 1
        self.assertGreaterEqual(mz.header.stamp.to_sec() - typed, 0.5 - 1e-6)  # float seconds since 1970
        self.assertGreaterEqual(repeats, 3, "repeat_rate should have re-sent the twist")
        os.write(master, b"\x03")
        self.assertEqual(proc.wait(timeout=TIMEOUT), 0)

    def test_without_terminal_exits_with_message(self):
        p = subprocess.run(["rosrun", "mybot_control", "teleop_keyboard", "__name:=teleop_k3"],
                           stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=TIMEOUT)
        self.assertEqual(p.returncode, 1)
        self.assertIn("not a terminal", p.stderr)

    def test_bad_parameter_names_it(self):
        master, slave = pty.openpty()
        p = subprocess.run(["rosrun", "mybot_control", "teleop_keyboard", "__name:=teleop_k4", "_key_timeout:=-1"],
                           stdin=slave, stdout=slave, stderr=slave, timeout=TIMEOUT)
        os.close(slave)
        out = self.read_all(master, timeout=1.0)
        os.close(master)
        self.assertEqual(p.returncode, 2)
        self.assertIn("~key_timeout", out)


if __name__ == "__main__":
    rospy.init_node("test_teleop_keyboard")
    rostest.rosrun("mybot_control", "teleop_keyboard", TeleopKeyboardTest)
