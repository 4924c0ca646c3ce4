#!/usr/bin/python3
"""Frame parameters, tf on/off, covariance, set_pose, and geometry read from the URDF."""
import math
import sys
import threading
import unittest

import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import Twist
from mybot_control.srv import SetPose
from nav_msgs.msg import Odometry
from std_msgs.msg import Float32

from chain_common import Chain, yaw_of


class FramesTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('diffdrive_frames_test')
        cls.tf_buffer = tf2_ros.Buffer()
        cls.tf_listener = tf2_ros.TransformListener(cls.tf_buffer)
        cls.chain = Chain()
        cls.notf = None
        cls.chain.subscribe('notf/odom', Odometry, cls._on_notf)
        cls.lock = threading.Lock()
        cls.last = {}
        for topic in ('lwheel_tangent_vel_target', 'rwheel_tangent_vel_target',
                      'lwheel_angular_vel_target', 'rwheel_angular_vel_target'):
            cls.chain.subscribe(topic, Float32, cls._on_float, callback_args=topic)
        cls.chain.wait_ready()

    @classmethod
    def _on_notf(cls, msg):
        cls.notf = msg

    @classmethod
    def _on_float(cls, msg, topic):
        with cls.lock:
            cls.last[topic] = msg.data

    def test_frame_ids_and_covariance(self):
        o = self.chain.odom
        self.assertEqual(o.header.frame_id, 'my_odom')
        self.assertEqual(o.child_frame_id, 'my_base')
        self.assertEqual([o.pose.covariance[7 * k] for k in range(6)], [0.001, 0.002, 1e6, 1e6, 1e6, 0.03])
        self.assertEqual([o.twist.covariance[7 * k] for k in range(6)], [0.004, 0.005, 1e6, 1e6, 1e6, 0.06])

    def test_tf_published(self):
        # Polled through the chain's sleeps, not can_transform's own timeout: that sleeps in sim
        # time while this test holds the period, so time would never come to pass it.
        self.chain.wait_for(lambda: self.tf_buffer.can_transform('my_odom', 'my_base', rospy.Time(0)), 5.0,
                            'tf my_odom -> my_base')

    def test_tf_disabled(self):
        self.chain.wait_for(lambda: self.notf is not None, 10.0, 'notf/odom')
        self.assertEqual(self.notf.header.frame_id, 'notf_odom')
        self.chain.ls.sleep(1.0)  # sim time: tf would have been broadcast with every odom message by now
        self.assertNotIn('notf_odom', self.tf_buffer.all_frames_as_string())
        self.assertIn('my_odom', self.tf_buffer.all_frames_as_string())

    def test_geometry_from_urdf(self):
        # mybot.xacro: wheel radius 0.1 m, separation 0.30 m.
        def got(topic, value):
            with self.lock:
                return topic in self.last and abs(self.last[topic] - value) < 1e-4
        msg = Twist()
        msg.linear.x = 0.1
        self.chain.wait_for(lambda: (self.chain.pub.publish(msg), got('lwheel_angular_vel_target', 1.0))[1],
                            5.0, 'lwheel_angular_vel_target = 0.1 / 0.1')
        msg.linear.x = 0.0
        msg.angular.z = 1.0
        # The two wheels' targets come on two topics: wait for both, not for the left one alone
        # (the right one's message may still be on its way when the left one arrives).
        self.chain.wait_for(lambda: (self.chain.pub.publish(msg), got('lwheel_tangent_vel_target', -0.15)
                                     and got('rwheel_tangent_vel_target', 0.15))[1],
                            5.0, 'lwheel_tangent_vel_target = -1.0 * 0.30 / 2 and rwheel_tangent_vel_target = +0.15')
        self.chain.pub.publish(Twist())

    def test_set_pose(self):
        rospy.wait_for_service('diffdrive_odom/set_pose', 10.0)
        res = rospy.ServiceProxy('diffdrive_odom/set_pose', SetPose)(1.0, 2.0, 0.5)
        self.assertTrue(res.success)
        self.chain.wait_for(lambda: abs(self.chain.pose()[1] - 2.0) < 0.05, 5.0, 'the new pose')
        x, y, yaw = self.chain.pose()
        self.assertAlmostEqual(x, 1.0, delta=0.05)
        self.assertAlmostEqual(yaw, 0.5, delta=0.05)
        bad = rospy.ServiceProxy('diffdrive_odom/set_pose', SetPose)(float('nan'), 0.0, 0.0)
        self.assertFalse(bad.success)
        self.assertTrue(math.isfinite(self.chain.pose()[0]))
        self.assertTrue(math.isfinite(yaw_of(self.chain.odom.pose.pose.orientation)))


if __name__ == '__main__':
    rostest.rosrun('mybot_control', 'diffdrive_frames', FramesTest, sys.argv)
