#!/usr/bin/env python3
"""Browser test on the swerve robot: holding A (strafe left) in the page moves the simulated
robot sideways (+y in its frame, ground truth) with every module turned to +-90 degrees as the
page's module panel shows; letting go stops it. Screenshot under the test results."""
import math
import sys

import rospy
import rostest
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By

from ros_helpers import PKG, BrowserTest, now, wait_for

STOPPED = 0.02  # m/s


class TestWebSwerve(BrowserTest):
    def test_strafe_from_the_keyboard(self):
        b = self.browser
        self.open_page()
        self.assertTrue(b.find_element(By.ID, "rotate").is_displayed(), "no rotation strip for swerve")
        wait_for(lambda: len(b.find_elements(By.CSS_SELECTOR, "#modules figure")) == 4, 10.0,
                 "the four module views")
        self.js("const s = document.getElementById('speed'); s.value = 60; s.dispatchEvent(new Event('input'));")
        b.find_element(By.ID, "keys").click()  # focus the page, away from the map (a click there is a goal)
        x0, y0, _ = self.ground_truth()
        ActionChains(b).key_down("a").perform()
        wait_for(lambda: self.ground_truth()[1] > y0 + 0.25, 15.0, "the robot to strafe 0.25 m left")
        x1 = self.ground_truth()[0]
        self.assertLess(abs(x1 - x0), 0.08, "strafing drifted %.2f m along x" % (x1 - x0))

        def modules_sideways():
            mods = self.js("return window.mybotWeb.state.modules")
            return len(mods) == 4 and all(
                m["angle"] is not None and abs(abs(m["angle"]) - math.pi / 2) < 0.15 for m in mods)
        wait_for(modules_sideways, 5.0, "the page to show all modules at +-90 degrees")
        self.save_screenshot("web_swerve.png")

        ActionChains(b).key_up("a").perform()
        t0 = now()
        # The swerve controller ramps down at its configured deceleration (1 m/s^2 from 0.3 m/s).
        t1 = wait_for(lambda: self.ground_truth()[2] < STOPPED, 5.0, "the robot to stop after the key is released")
        rospy.loginfo("key released: stopped %.3f s after", t1 - t0)


if __name__ == "__main__":
    rostest.rosrun(PKG, "web_swerve", TestWebSwerve, sys.argv)
