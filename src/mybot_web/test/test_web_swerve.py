#!/usr/bin/env python3
"""Browser test on the swerve robot: holding A (strafe left) in the page moves the simulated
robot sideways (+y in its frame, ground truth) with every module turned to +-90 degrees as the
page's module panel shows; letting go stops it. Screenshot under the test results."""
import math
import os
import sys
import threading
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By

from chromium import Chromium
from ros_helpers import PKG, now, results_dir, wait_for

STOPPED = 0.02  # m/s


class TestWebSwerve(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_web_swerve")
        cls.lock = threading.Lock()
        cls.odom = None
        rospy.Subscriber("ground_truth/odom", Odometry, cls._on_odom, queue_size=10)
        wait_for(lambda: cls.odom is not None, 30.0, "ground_truth/odom")
        wait_for(lambda: rospy.has_param("/web_controller/url"), 30.0, "/web_controller/url")
        cls.chromium = Chromium()
        cls.browser = cls.chromium.driver

    @classmethod
    def tearDownClass(cls):
        cls.chromium.quit()

    @classmethod
    def _on_odom(cls, msg):
        with cls.lock:
            cls.odom = msg

    def pose(self):
        with self.lock:
            p = self.odom.pose.pose.position
            v = self.odom.twist.twist.linear
            return p.x, p.y, math.hypot(v.x, v.y)

    def test_strafe_from_the_keyboard(self):
        b = self.browser
        b.get(rospy.get_param("/web_controller/url"))
        wait_for(lambda: b.execute_script("return document.getElementById('status').dataset.state")
                 == "connected", 20.0, "the page to connect")
        self.assertTrue(b.find_element(By.ID, "rotate").is_displayed(), "no rotation strip for swerve")
        wait_for(lambda: len(b.find_elements(By.CSS_SELECTOR, "#modules figure")) == 4, 10.0,
                 "the four module views")
        b.execute_script("const s = document.getElementById('speed'); s.value = 60;"
                         "s.dispatchEvent(new Event('input'));")
        b.find_element(By.ID, "keys").click()  # focus the page, away from the map (a click there is a goal)
        x0, y0, _ = self.pose()
        ActionChains(b).key_down("a").perform()
        wait_for(lambda: self.pose()[1] > y0 + 0.25, 15.0, "the robot to strafe 0.25 m left")
        x1, _, _ = self.pose()
        self.assertLess(abs(x1 - x0), 0.08, "strafing drifted %.2f m along x" % (x1 - x0))

        def modules_sideways():
            mods = b.execute_script("return window.mybotWeb.state.modules")
            return len(mods) == 4 and all(
                m["angle"] is not None and abs(abs(m["angle"]) - math.pi / 2) < 0.15 for m in mods)
        wait_for(modules_sideways, 5.0, "the page to show all modules at +-90 degrees")
        path = os.path.join(results_dir(), "web_swerve.png")
        os.makedirs(os.path.dirname(path), exist_ok=True)
        self.assertTrue(b.save_screenshot(path))
        rospy.loginfo("screenshot: %s", path)

        ActionChains(b).key_up("a").perform()
        t0 = now()
        # The swerve controller ramps down at its configured deceleration (1 m/s^2 from 0.3 m/s).
        t1 = wait_for(lambda: self.pose()[2] < STOPPED, 5.0, "the robot to stop after the key is released")
        rospy.loginfo("key released: stopped %.3f s after", t1 - t0)


if __name__ == "__main__":
    rostest.rosrun(PKG, "web_swerve", TestWebSwerve, sys.argv)
