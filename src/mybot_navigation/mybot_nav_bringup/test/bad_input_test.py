#!/usr/bin/env python3
"""Bad input to the navigation nodes, no simulator: a LaserScan whose number of ranges contradicts
its angles, or whose range_max is NaN, is dropped by slam_node, amcl and move_base, each warning
with the topic and the numbers, and a consistent scan is still used; an initial pose with NaN, 1e30 or a zero quaternion
is refused by amcl naming the field, and its pose stays where it was."""
import math
import sys
import time
import unittest

import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import PoseWithCovarianceStamped, TransformStamped
from nav_msgs.msg import OccupancyGrid
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import LaserScan

WALL_TIMEOUT = 30.0
# 361 beams over 180 degrees by their angles.
ANGLE_MIN, ANGLE_MAX, INCREMENT = -math.pi / 2, math.pi / 2, math.pi / 360


def scan(n, rng=2.0):
    s = LaserScan()
    s.header.frame_id = "hokuyo"
    s.header.stamp = rospy.Time.now()
    s.angle_min, s.angle_max, s.angle_increment = ANGLE_MIN, ANGLE_MAX, INCREMENT
    s.range_min, s.range_max = 0.1, 30.0
    s.ranges = [rng] * n
    return s


class BadInput(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("bad_scans_test")
        transforms = []
        for parent, child, x, z in (("odom", "base_footprint", 0.0, 0.0), ("base_footprint", "hokuyo", 0.1, 0.2)):
            t = TransformStamped()
            t.header.stamp = rospy.Time.now()
            t.header.frame_id, t.child_frame_id = parent, child
            t.transform.translation.x, t.transform.translation.z = x, z
            t.transform.rotation.w = 1.0
            transforms.append(t)
        cls.static_tf = tf2_ros.StaticTransformBroadcaster()
        cls.static_tf.sendTransform(transforms)
        cls.logs = []
        cls.slam_maps = []
        rospy.Subscriber("/rosout", Log, lambda m: cls.logs.append((m.name, m.msg)))
        rospy.Subscriber("/slam_ns/map", OccupancyGrid, cls.slam_maps.append)
        cls.pub = rospy.Publisher("/scan", LaserScan, queue_size=10)
        cls.amcl_poses = []
        rospy.Subscriber("/amcl_pose", PoseWithCovarianceStamped, cls.amcl_poses.append)
        # Every node up and connected to /scan before the first scan goes out.
        deadline = time.monotonic() + WALL_TIMEOUT
        while cls.pub.get_num_connections() < 3 and time.monotonic() < deadline:
            time.sleep(0.05)
        assert cls.pub.get_num_connections() >= 3, "slam, amcl and move_base did not all subscribe to /scan"

    def wait_for(self, cond, what):
        deadline = time.monotonic() + WALL_TIMEOUT
        while not cond():
            if time.monotonic() > deadline:
                self.fail("timed out waiting for " + what)
            time.sleep(0.05)

    def test_initial_pose_that_is_not_finite_or_has_a_negative_variance_is_refused_naming_the_field(self):
        pub = rospy.Publisher("/initialpose", PoseWithCovarianceStamped, queue_size=10)
        self.wait_for(lambda: pub.get_num_connections() > 0, "amcl to subscribe to /initialpose")
        cases = [("position.x", float("nan"), "pose.pose.position.x is nan"),
                 ("position.y", 1e30, "pose.pose.position.y is 1e+30, beyond"),
                 ("orientation.w", 0.0, "pose.pose.orientation is a zero quaternion"),
                 ("covariance", float("inf"), "pose.covariance[0] is inf"),
                 ("covariance", -0.25, "pose.covariance[0] is -0.25, a negative variance")]
        for field, value, message in cases:
            msg = PoseWithCovarianceStamped()
            msg.header.frame_id = "map"
            msg.pose.pose.orientation.w = 1.0
            if field == "covariance":
                cov = list(msg.pose.covariance)
                cov[0] = value
                msg.pose.covariance = cov
            else:
                part, attr = field.split(".")
                setattr(getattr(msg.pose.pose, part), attr, value)
            pub.publish(msg)
            self.wait_for(lambda: any(n == "/amcl" and "ignoring initial pose: " + message in m for n, m in self.logs),
                          "amcl to refuse %s = %r" % (field, value))
        self.assertFalse(any(n == "/amcl" and "setting pose" in m for n, m in self.logs))

    def test_contradicting_scans_are_dropped_naming_topic_and_numbers(self):
        no_range = scan(361)
        no_range.range_max = float("nan")  # it put every no-return beam's free space at NaN metres
        cases = [(scan(100), "has 100 ranges where its angles (angle_min -1.5708, angle_max 1.5708, "
                             "angle_increment 0.00872665) make 361"),
                 (no_range, "has range_min 0.1, range_max nan: not a range")]
        rate = rospy.Rate(10)
        for bad, want in cases:
            warned = lambda node: any(n == node and "/scan" in m and want in m for n, m in self.logs)  # noqa: E731
            deadline = time.monotonic() + WALL_TIMEOUT  # the warnings are throttled to one in 5 s
            while not all(warned(n) for n in ("/slam_ns/slam", "/amcl", "/move_base")):
                self.assertLess(time.monotonic(), deadline,
                                "warnings so far: %s" % [l for l in self.logs if "dropping" in l[1]])
                bad.header.stamp = rospy.Time.now()
                self.pub.publish(bad)
                rate.sleep()
        # Nothing of them reached SLAM's map: it has not published one yet.
        self.assertEqual(self.slam_maps, [])
        # A consistent scan is used: SLAM makes its first map from it.
        self.wait_for(lambda: self.pub.publish(scan(361)) or rate.sleep() or self.slam_maps, "SLAM's map from a good scan")
        occupied = sum(1 for v in self.slam_maps[-1].data if v > 50)
        self.assertGreater(occupied, 50)


if __name__ == "__main__":
    rostest.rosrun("mybot_nav_bringup", "bad_input", BadInput, sys.argv)
