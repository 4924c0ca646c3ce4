#!/usr/bin/env python3
"""explore's return_to_init: once no frontier is left, the initial pose is its last goal."""
import math
import threading
import unittest

import actionlib
import numpy as np
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import TransformStamped
from move_base_msgs.msg import MoveBaseAction
from nav_msgs.msg import OccupancyGrid
from std_msgs.msg import String

from mybot_lockstep import wait_connected


class FakeMoveBase:
    """Records every goal and reports it reached at once."""

    def __init__(self, ns):
        self.goals = []
        self.statuses = []
        self.got_status = threading.Event()
        self.server = actionlib.SimpleActionServer(ns + "/move_base", MoveBaseAction, self.execute, auto_start=False)
        self.server.start()
        self.status_sub = rospy.Subscriber(ns + "/explore/status", String, self.on_status)

    def execute(self, goal):
        p = goal.target_pose.pose
        self.goals.append((p.position.x, p.position.y, 2.0 * math.atan2(p.orientation.z, p.orientation.w),
                           goal.target_pose.header.frame_id))
        self.server.set_succeeded()

    def on_status(self, msg):
        self.statuses.append(msg.data)
        if msg.data.startswith("exiting"):
            self.got_status.set()

    @property
    def status(self):
        """The last status before the explorer's "exiting with code N"."""
        before = [s for s in self.statuses if not s.startswith("exiting")]
        return before[-1] if before else None


def known_room():
    """A 4 x 4 m room, walls all round, every cell known: no frontier anywhere."""
    m = OccupancyGrid()
    m.header.frame_id = "map"
    m.info.resolution = 0.05
    m.info.width = m.info.height = 80
    m.info.origin.orientation.w = 1.0
    g = np.zeros((80, 80), dtype=np.int8)
    g[0, :] = g[-1, :] = g[:, 0] = g[:, -1] = 100
    m.data = g.ravel().tolist()
    return m


class ReturnToInit(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("return_to_init_test")
        t = TransformStamped()
        t.header.stamp = rospy.Time.now()
        t.header.frame_id, t.child_frame_id = "map", "base_footprint"
        t.transform.translation.x, t.transform.translation.y = 2.0, 1.5
        t.transform.rotation.z, t.transform.rotation.w = math.sin(0.25), math.cos(0.25)
        cls.tf = tf2_ros.StaticTransformBroadcaster()
        cls.tf.sendTransform(t)
        cls.home = FakeMoveBase("/home")
        cls.stay = FakeMoveBase("/stay")
        # The explorers start on the map. Their status is latched, so a subscription that connects
        # after they finished would get only the last one ("exiting ..."): connected first.
        wait_connected([cls.home.status_sub, cls.stay.status_sub])
        cls.maps = [rospy.Publisher(ns + "/map", OccupancyGrid, queue_size=1, latch=True) for ns in ("/home", "/stay")]
        for pub in cls.maps:
            pub.publish(known_room())

    def wait_done(self, fake):
        # The explorer's last status says it exits; the one before, "back at ..." after its
        # return, "done: ..." otherwise.
        deadline = rospy.get_time() + 60.0
        while not rospy.is_shutdown() and rospy.get_time() < deadline:
            if fake.got_status.is_set():
                self.assertEqual(fake.statuses[-1], "exiting with code 0")
                return
            rospy.sleep(0.1)
        self.fail("explore did not finish: statuses %r" % fake.statuses)

    def test_returns_to_the_pose_it_started_from(self):
        self.wait_done(self.home)
        self.assertEqual(len(self.home.goals), 1, self.home.goals)
        x, y, yaw, frame = self.home.goals[0]
        self.assertEqual(frame, "map")
        self.assertAlmostEqual(x, 2.0, places=3)
        self.assertAlmostEqual(y, 1.5, places=3)
        self.assertAlmostEqual(yaw, 0.5, places=3)
        self.assertEqual(self.home.status, "back at the initial pose")

    def test_stays_by_default(self):
        self.wait_done(self.stay)
        self.assertTrue(self.stay.status.startswith("done: no reachable frontier left"), self.stay.status)
        self.assertEqual(self.stay.goals, [])


if __name__ == "__main__":
    rostest.rosrun("mybot_explore", "return_to_init", ReturnToInit)
