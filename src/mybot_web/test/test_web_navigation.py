#!/usr/bin/env python3
"""Browser test with navigation: the page shows the map in the map frame, a click on it 1 m
ahead of the robot sends a move_base goal (switching to autonomous), the planned path is drawn,
and the simulated robot reaches the goal (ground truth). Screenshot under the test results."""
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
from std_msgs.msg import Bool

from chromium import Chromium
from ros_helpers import PKG, results_dir, wait_for, wait_for_value

GOAL = (1.0, 0.0)  # map frame (= world: the robot starts at the origin, AMCL initial pose 0)
REACHED = 0.3  # m: the planner's goal tolerance plus localisation error


class TestWebNavigation(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_web_navigation")
        cls.lock = threading.Lock()
        cls.odom = None
        cls.nav_lock = None
        rospy.Subscriber("ground_truth/odom", Odometry, cls._on_odom, queue_size=10)
        rospy.Subscriber("nav_lock", Bool, cls._on_lock, queue_size=10)
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

    @classmethod
    def _on_lock(cls, msg):
        cls.nav_lock = msg.data

    def distance_to_goal(self):
        with self.lock:
            p = self.odom.pose.pose.position
        return math.hypot(p.x - GOAL[0], p.y - GOAL[1])

    def test_click_on_the_map_reaches_the_goal(self):
        b = self.browser
        js = b.execute_script
        b.get(rospy.get_param("/web_controller/url"))
        wait_for(lambda: js("const c = window.mybotWeb; return !!(c.mapImage && c.state && c.state.frame === 'map'"
                            " && c.state.pose)"), 60.0, "the page to show the map and a pose in the map frame")
        self.assertNotIn("not shown", b.find_element(By.ID, "frame").text)
        self.assertTrue(self.nav_lock, "manual mode should lock navigation out")
        cx, cy, scale = js("const v = window.mybotWeb.view; return [v.cx, v.cy, v.scale];")
        dx, dy = (GOAL[0] - cx) * scale, -(GOAL[1] - cy) * scale
        ActionChains(b).move_to_element_with_offset(b.find_element(By.ID, "map"), dx, dy).click().perform()
        wait_for(lambda: self.nav_lock is False, 10.0, "the goal to switch to autonomous")
        # The global plan (move_base/GlobalPlanner/plan) is drawn, ending near the goal.
        end = wait_for_value(lambda: js("const p = window.mybotWeb.state.path;"
                                        " return p.length >= 4 ? p.slice(-2) : null"), 20.0, "the planned path")
        self.assertLess(math.hypot(end[0] - GOAL[0], end[1] - GOAL[1]), 0.1, "plan ends at %s" % end)
        wait_for(lambda: "SUCCEEDED" in b.find_element(By.ID, "goal").text, 90.0,
                 "the page to report the goal succeeded")
        self.assertLess(self.distance_to_goal(), REACHED, "the robot stopped %.2f m from the goal"
                        % self.distance_to_goal())
        path = os.path.join(results_dir(), "web_navigation.png")
        os.makedirs(os.path.dirname(path), exist_ok=True)
        self.assertTrue(b.save_screenshot(path))
        rospy.loginfo("screenshot: %s", path)


if __name__ == "__main__":
    rostest.rosrun(PKG, "web_navigation", TestWebNavigation, sys.argv)
