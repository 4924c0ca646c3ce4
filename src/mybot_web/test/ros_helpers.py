"""Helpers shared by the rostest browser tests."""
import os
import sys

import rospkg
import rospy

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
