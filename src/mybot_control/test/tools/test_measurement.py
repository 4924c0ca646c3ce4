#!/usr/bin/env python3
"""Measurement nodes: CPU load/temperature, goal latch, absolute position, pose error."""
import math
import threading
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import PointStamped, PoseStamped
from nav_msgs.msg import Odometry
from std_msgs.msg import Float32, Float64

from mybot_lockstep import wait_connected

TIMEOUT = 15.0


class Collector:
    def __init__(self, topic, kind):
        self.msgs = []
        self.lock = threading.Lock()
        self.sub = rospy.Subscriber(topic, kind, self.cb, queue_size=100)

    def cb(self, msg):
        with self.lock:
            self.msgs.append(msg)

    def wait_count(self, n, what):
        end = time.monotonic() + TIMEOUT
        while time.monotonic() < end:
            with self.lock:
                if len(self.msgs) >= n:
                    return list(self.msgs)
            time.sleep(0.01)
        raise AssertionError("timed out waiting for %d x %s (got %d)" % (n, what, len(self.msgs)))


def wait_subscribers(pub, n=1):
    """Wait until a publisher has n subscribers connected (subscriptions: mybot_lockstep's
    wait_connected, which waits for the publisher's side of the link)."""
    end = time.monotonic() + TIMEOUT
    while pub.get_num_connections() < n:
        if time.monotonic() > end:
            raise AssertionError("not connected: %s" % pub.resolved_name)
        time.sleep(0.02)


def odom(t, x, y, yaw, frame):
    m = Odometry()
    m.header.stamp = rospy.Time.from_sec(t)
    m.header.frame_id = frame
    m.pose.pose.position.x, m.pose.pose.position.y = x, y
    m.pose.pose.orientation.z, m.pose.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return m


class MeasurementTest(unittest.TestCase):
    def test_cpu_monitor_with_fake_thermal_zone(self):
        temp = Collector("/pi/cpu_temperature", Float32)
        load = Collector("/pi/cpu_load", Float32)
        self.assertAlmostEqual(temp.wait_count(1, "temperature")[0].data, 42.5, places=3)  # cpu-thermal zone
        for m in load.wait_count(3, "cpu load"):
            self.assertTrue(0.0 <= m.data <= 100.0)

    def test_cpu_monitor_without_thermal_zone_keeps_running(self):
        temp = Collector("/container/cpu_temperature", Float32)
        load = Collector("/container/cpu_load", Float32)
        load.wait_count(5, "cpu load without a thermal zone")
        self.assertEqual(temp.msgs, [])

    def test_goal_latch_republishes(self):
        out = Collector("/clamped_goal_pose", PoseStamped)
        pub = rospy.Publisher("/move_base_simple/goal", PoseStamped, queue_size=1)
        wait_subscribers(pub)
        g = PoseStamped()
        g.header.frame_id = "map"
        g.pose.position.x, g.pose.position.y, g.pose.orientation.w = 1.5, -2.0, 1.0
        pub.publish(g)
        msgs = out.wait_count(4, "republished goals")
        for m in msgs:
            self.assertEqual((m.header.frame_id, m.pose.position.x, m.pose.position.y), ("map", 1.5, -2.0))
        self.assertGreater(msgs[-1].header.stamp, msgs[0].header.stamp)  # restamped each time

    def test_absolute_position_and_pose_error(self):
        absolute = Collector("/robot/position/absolute", PointStamped)
        pos_err = Collector("/pose_error/position", Float64)
        yaw_err = Collector("/pose_error/yaw", Float64)
        gt = rospy.Publisher("/ground_truth/odom", Odometry, queue_size=100)
        od = rospy.Publisher("/odom", Odometry, queue_size=100)
        wait_subscribers(gt, 2)
        wait_subscribers(od, 1)
        # The first pose error is published once, in answer to the first pair below.
        wait_connected([absolute.sub, pos_err.sub, yaw_err.sub], TIMEOUT)
        # robot starts at (2, 1) facing +y; odometry under-reads distance by 10 % and drifts in yaw
        t0 = rospy.get_time() + 1.0
        for k in range(21):
            t = t0 + 0.1 * k
            d = 0.05 * k
            gt.publish(odom(t, 2.0, 1.0 + d, math.pi / 2 + 0.01 * k, "world"))
            od.publish(odom(t, 0.9 * d, 0.0, 0.0, "odom"))
            if k == 0:  # the node aligns odom to the world on its first pair: let it see this one alone
                pos_err.wait_count(1, "first pose error")
        # the last ground-truth pose comes through (a loaded machine may drop some of the burst)
        end = time.monotonic() + TIMEOUT
        while time.monotonic() < end and not (absolute.msgs and abs(absolute.msgs[-1].point.y - 2.0) < 1e-9):
            time.sleep(0.02)
        p = absolute.msgs[-1]
        self.assertEqual(p.header.frame_id, "world")
        self.assertAlmostEqual(p.point.y, 2.0, places=6)
        self.assertAlmostEqual(p.point.x, 2.0, places=6)
        # position and yaw are two topics: the yaw of the last pair may arrive after its position
        end = time.monotonic() + TIMEOUT
        while time.monotonic() < end and not (pos_err.msgs and abs(pos_err.msgs[-1].data - 0.1) < 1e-6
                                              and yaw_err.msgs and abs(yaw_err.msgs[-1].data + 0.2) < 1e-6):
            time.sleep(0.02)
        self.assertAlmostEqual(pos_err.msgs[-1].data, 0.1, places=6)  # 1.0 m true vs 0.9 m odometry
        self.assertAlmostEqual(yaw_err.msgs[-1].data, -0.2, places=6)
        self.assertAlmostEqual(pos_err.msgs[0].data, 0.0, places=6)   # aligned on the first pair


if __name__ == "__main__":
    rospy.init_node("test_measurement")
    rostest.rosrun("mybot_control", "measurement", MeasurementTest)
