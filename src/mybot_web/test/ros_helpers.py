"""Helpers shared by the rostest browser tests."""
import math
import os
import sys
import threading
import unittest

import rospkg
import rospy
from nav_msgs.msg import Odometry

from chromium import Chromium

PKG = "mybot_web"


def now():
    return rospy.get_rostime().to_sec()


def wait_for(predicate, timeout, what):
    """Poll predicate until true or `timeout` s of ROS time pass; returns the ROS time it held."""
    deadline = now() + timeout
    while not rospy.is_shutdown():
        if predicate():
            return now()
        if now() > deadline:
            raise AssertionError("timed out after %.1f s (ROS time) waiting for %s" % (timeout, what))
        rospy.sleep(0.01)
    raise AssertionError("shut down while waiting for %s" % what)


def wait_for_value(fn, timeout, what):
    """Like wait_for, for a function returning None until it has a value; returns the value."""
    seen = []
    wait_for(lambda: seen.append(fn()) or seen[-1] is not None, timeout, what)
    return seen[-1]


def results_dir():
    """Where rostest writes this test's XML (it passes --gtest_output=xml:<file>; catkin test
    points it into the build's test_results), so the screenshot lands beside the results."""
    for arg in sys.argv:
        if arg.startswith("--gtest_output=xml:"):
            return os.path.dirname(os.path.abspath(arg.split(":", 1)[1]))
    return os.path.join(rospkg.get_test_results_dir(), PKG)


class BrowserTest(unittest.TestCase):
    """A rostest case with the simulator's ground truth, the web controller's URL and a
    headless chromium (class-wide)."""

    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_" + cls.__name__.lower())
        cls.lock = threading.Lock()
        cls.odom = None
        rospy.Subscriber("ground_truth/odom", Odometry, cls._on_odom, queue_size=10)
        wait_for(lambda: cls.odom is not None, 30.0, "ground_truth/odom")
        wait_for(lambda: rospy.has_param("/web_controller/url"), 30.0, "/web_controller/url")
        cls.url = rospy.get_param("/web_controller/url")
        cls.chromium = Chromium()
        cls.browser = cls.chromium.driver

    @classmethod
    def tearDownClass(cls):
        cls.chromium.quit()

    @classmethod
    def _on_odom(cls, msg):
        with cls.lock:
            cls.odom = msg

    def ground_truth(self):
        """(x, y, planar speed) of the robot in the world."""
        with self.lock:
            p, v = self.odom.pose.pose.position, self.odom.twist.twist.linear
        return p.x, p.y, math.hypot(v.x, v.y)

    def js(self, script):
        return self.browser.execute_script(script)

    def open_page(self):
        self.browser.get(self.url)
        wait_for(lambda: self.js("return document.getElementById('status').dataset.state") == "connected",
                 20.0, "the page to connect")

    def save_screenshot(self, name):
        path = os.path.join(results_dir(), name)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        self.assertTrue(self.browser.save_screenshot(path), "screenshot %s not written" % path)
        rospy.loginfo("screenshot: %s", path)
