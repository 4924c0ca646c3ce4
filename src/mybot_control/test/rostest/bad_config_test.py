#!/usr/bin/python3
"""Bad configurations: each node exits non-zero with one message naming the parameter."""
import subprocess
import sys
import unittest

import rospy
import rostest

from mybot_common.node_process import advertised, stop, wait_until_advertising

COV = [0.001, 0.001, 1e6, 1e6, 1e6, 0.03]
ODOM_OK = {'wheel_separation': 0.3, 'wheel_radius': 0.1,
           'pose_covariance_diagonal': COV, 'twist_covariance_diagonal': COV}


class BadConfigTest(unittest.TestCase):
    counter = 0

    @classmethod
    def setUpClass(cls):
        rospy.init_node('bad_config_test')

    def run_node(self, node, params, timeout=30.0):
        BadConfigTest.counter += 1
        name = 'bad_%s_%d' % (node, BadConfigTest.counter)
        for key, value in params.items():
            rospy.set_param('/%s/%s' % (name, key), value)
        proc = subprocess.Popen(['rosrun', 'mybot_control', node, '__name:=' + name],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        try:
            out, _ = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
            out, _ = proc.communicate()
            return None, out
        return proc.returncode, out

    def expect_failure(self, node, params, *words):
        code, out = self.run_node(node, params)
        self.assertIsNotNone(code, '%s did not exit on a bad configuration:\n%s' % (node, out))
        self.assertNotEqual(code, 0, out)
        for w in words:
            self.assertIn(w, out)

    def test_odom_negative_radius(self):
        self.expect_failure('diffdrive_odom', dict(ODOM_OK, wheel_radius=-0.1), 'wheel_radius', 'must be > 0')

    def test_odom_missing_covariance(self):
        p = dict(ODOM_OK)
        del p['pose_covariance_diagonal']
        self.expect_failure('diffdrive_odom', p, 'pose_covariance_diagonal', 'required')

    def test_odom_short_covariance(self):
        self.expect_failure('diffdrive_odom', dict(ODOM_OK, twist_covariance_diagonal=[1.0] * 5),
                            'twist_covariance_diagonal', '6 numbers')

    def test_odom_unknown_joint(self):
        # No geometry given: read from robot_description, which has no such joint.
        p = {'left_wheel': 'no_such_joint', 'pose_covariance_diagonal': COV, 'twist_covariance_diagonal': COV}
        self.expect_failure('diffdrive_odom', p, "no joint 'no_such_joint'")

    def test_controller_bad_acceleration(self):
        p = {'wheel_separation': 0.3, 'linear': {'x': {'has_acceleration_limits': True, 'max_acceleration': -1.0}}}
        self.expect_failure('diffdrive_controller', p, 'linear/x/max_acceleration')

    def test_controller_wrong_type(self):
        self.expect_failure('diffdrive_controller', {'wheel_separation': 0.3, 'publish_rate': 'fast'},
                            'publish_rate', 'number')

    def test_controller_zero_separation(self):
        self.expect_failure('diffdrive_controller', {'wheel_separation': 0.0}, 'wheel_separation')

    def test_wheel_controller_interface(self):
        self.expect_failure('wheel_controller', {'wheel_radius': 0.1, 'command_interface': 'bogus'},
                            'command_interface', 'bogus')

    def test_wheel_controller_pid(self):
        p = {'wheel_radius': 0.1, 'pid': {'p': 1.0, 'i': 0.0, 'd': 0.0, 'output_min': 5.0, 'output_max': -5.0}}
        self.expect_failure('wheel_controller', p, 'pid/output_min')

    def test_twist_mux_no_topics(self):
        self.expect_failure('twist_mux', {}, 'topics', 'required')

    def test_twist_mux_duplicate(self):
        topics = [{'name': 'a', 'topic': 'x', 'timeout': 0.5, 'priority': 1},
                  {'name': 'a', 'topic': 'y', 'timeout': 0.5, 'priority': 2}]
        self.expect_failure('twist_mux', {'topics': topics}, "topics[1].name 'a'")

    def test_twist_mux_priority_not_a_number(self):
        # Aborted with ros::InvalidNameException before: the message named "topics[0].priority".
        topics = [{'name': 'joy', 'topic': 'x', 'timeout': 0.5, 'priority': 'high'}]
        self.expect_failure('twist_mux', {'topics': topics}, 'topics[0].priority', 'integer')

    def test_twist_mux_map_form_key_that_is_no_graph_name(self):
        topics = {'my-joy': {'topic': 'x', 'timeout': 'soon', 'priority': 1}}
        self.expect_failure('twist_mux', {'topics': topics}, 'topics/my-joy.timeout', 'number')

    def test_valid_config_keeps_running(self):
        # The harness itself: a good configuration starts the node (it advertises odom once its
        # parameters are valid, and is still running then), so the failures above are specific.
        name = 'good_diffdrive_odom'
        for key, value in ODOM_OK.items():
            rospy.set_param('/%s/%s' % (name, key), value)
        proc = subprocess.Popen(['rosrun', 'mybot_control', 'diffdrive_odom', '__name:=' + name],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        try:
            wait_until_advertising(proc, '/' + name, topics=['/odom'])
        finally:
            stop(proc)

    def test_odom_tf_disabled_advertises_no_tf(self):
        # enable_odom_tf: false (another node, e.g. an EKF, owns odom -> base_footprint): the node
        # does not even advertise /tf. Its services come last in its start-up, so once set_pose is
        # up every publisher it makes is registered.
        name = 'odom_without_tf'
        for key, value in dict(ODOM_OK, enable_odom_tf=False).items():
            rospy.set_param('/%s/%s' % (name, key), value)
        proc = subprocess.Popen(['rosrun', 'mybot_control', 'diffdrive_odom', '__name:=' + name],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        try:
            wait_until_advertising(proc, '/' + name, topics=['/odom'])
            rospy.wait_for_service('/%s/set_pose' % name, timeout=30.0)
            self.assertEqual(advertised('/' + name), ['/cmd_vel_enc', '/odom'])
        finally:
            stop(proc)


if __name__ == '__main__':
    rostest.rosrun('mybot_control', 'bad_config', BadConfigTest, sys.argv)
