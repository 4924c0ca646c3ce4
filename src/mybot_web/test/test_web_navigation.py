#!/usr/bin/env python3
"""Browser test with navigation: the page shows the map in the map frame, a click on it 1 m
ahead of the robot sends a move_base goal (switching to autonomous), the planned path is drawn,
and the simulated robot reaches the goal (ground truth). Screenshot under the test results."""
import math
import sys

import rospy
import rostest
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By
from std_msgs.msg import Bool

from ros_helpers import PKG, BrowserTest, wait_for, wait_for_value

GOAL = (1.0, 0.0)  # map frame (= world: the robot starts at the origin, AMCL initial pose 0)
REACHED = 0.3  # m: the planner's goal tolerance plus localisation error


class TestWebNavigation(BrowserTest):
    nav_lock = None

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        rospy.Subscriber("nav_lock", Bool, cls._on_lock, queue_size=10)

    @classmethod
    def _on_lock(cls, msg):
        cls.nav_lock = msg.data

    def distance_to_goal(self):
        x, y, _ = self.ground_truth()
        return math.hypot(x - GOAL[0], y - GOAL[1])

    def test_click_on_the_map_reaches_the_goal(self):
        b = self.browser
        self.open_page()
        wait_for(lambda: self.js("const c = window.mybotWeb; return !!(c.mapImage && c.state"
                                 " && c.state.frame === 'map' && c.state.pose)"), 60.0,
                 "the page to show the map and a pose in the map frame")
        self.assertNotIn("not shown", b.find_element(By.ID, "frame").text)
        wait_for(lambda: self.nav_lock is True, 10.0, "manual mode to lock navigation out")
        cx, cy, scale = self.js("const v = window.mybotWeb.view; return [v.cx, v.cy, v.scale];")
        dx, dy = (GOAL[0] - cx) * scale, -(GOAL[1] - cy) * scale
        ActionChains(b).move_to_element_with_offset(b.find_element(By.ID, "map"), dx, dy).click().perform()
        wait_for(lambda: self.nav_lock is False, 10.0, "the goal to switch to autonomous")
        # The global plan (move_base/GlobalPlanner/plan) is drawn, ending near the goal.
        end = wait_for_value(lambda: self.js("const p = window.mybotWeb.state.path;"
                                             " return p.length >= 4 ? p.slice(-2) : null"), 20.0, "the planned path")
        self.assertLess(math.hypot(end[0] - GOAL[0], end[1] - GOAL[1]), 0.1, "plan ends at %s" % end)
        wait_for(lambda: "SUCCEEDED" in b.find_element(By.ID, "goal").text, 90.0,
                 "the page to report the goal succeeded")
        self.assertLess(self.distance_to_goal(), REACHED, "the robot stopped %.2f m from the goal"
                        % self.distance_to_goal())
        self.save_screenshot("web_navigation.png")


if __name__ == "__main__":
    rostest.rosrun(PKG, "web_navigation", TestWebNavigation, sys.argv)
