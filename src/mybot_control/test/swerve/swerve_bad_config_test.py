#!/usr/bin/python3
"""Bad swerve configurations: each node exits non-zero with one message naming the problem."""
import subprocess
import sys
import unittest

import rospy
import rostest

from mybot_common.node_process import stop, wait_until_advertising

PID = {'p': 1.0, 'i': 0.0, 'd': 0.0}
COV = [0.001, 0.001, 1e6, 1e6, 1e6, 0.03]


class SwerveBadConfigTest(unittest.TestCase):
    counter = 0

    def run_node(self, node, params, timeout=30.0, command=None):
        SwerveBadConfigTest.counter += 1
        name = 'bad_%s_%d' % (node, SwerveBadConfigTest.counter)
        for key, value in params.items():
            rospy.set_param('/%s/%s' % (name, key), value)
        proc = subprocess.Popen((command or ['rosrun', 'mybot_control', node]) + ['__name:=' + name],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        try:
            out, _ = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
            out, _ = proc.communicate()
            self.fail('%s did not exit on a bad configuration:\n%s' % (node, out))
        return proc.returncode, out

    def expect_failure(self, node, params, *words):
        code, out = self.run_node(node, params)
        self.assertNotEqual(code, 0, out)
        for w in words:
            self.assertIn(w, out)

    def test_controller_two_modules_at_the_same_offset(self):
        self.expect_failure('swerve_controller', {'b': {'offset': [0.25, 0.2]}, 'a': {'offset': [0.25, 0.2]},
                                                  'c': {'offset': [-0.25, 0.2]}, 'd': {'offset': [-0.25, -0.2]}},
                            'same offset', 'modules 0 and 1')

    def test_controller_unknown_pivot_joint(self):
        self.expect_failure('swerve_controller', {'modules': ['a', 'x']}, "no joint 'swerve_x_pivot_joint'")

    def test_module_zero_wheel_radius(self):
        self.expect_failure('swerve_module', {'wheel_radius': 0.0, 'pivot_pid': PID, 'drive_pid': PID},
                            'wheel_radius', 'must be > 0')

    def test_module_missing_gains(self):
        self.expect_failure('swerve_module', {'wheel_radius': 0.05, 'pivot_pid': PID}, 'drive_pid', 'required')

    def test_module_bad_interface(self):
        self.expect_failure('swerve_module', {'interface': 'bogus', 'pivot_pid': PID, 'drive_pid': PID},
                            'interface', 'bogus')

    def test_odom_zero_wheel_radius(self):
        self.expect_failure('swerve_odom', {'wheel_radius': 0.0, 'pose_covariance_diagonal': COV,
                                            'twist_covariance_diagonal': COV}, 'wheel_radius')

    def test_nodelet_refuses_a_bad_configuration(self):
        """The nodelet build of a node (swerve_control.launch's default) fails to load with the same message."""
        code, out = self.run_node('swerve_module', {'wheel_radius': 0.05, 'pivot_pid': PID},
                                  command=['rosrun', 'nodelet', 'nodelet', 'standalone', 'mybot_control/SwerveModule'])
        self.assertNotEqual(code, 0, out)
        self.assertIn('drive_pid', out)
        self.assertIn('required', out)

    def test_good_configuration_starts(self):
        """The same node with sane parameters starts (it advertises its modules' requests once its
        parameters are valid, and is still running then), so the failures above are specific."""
        proc = subprocess.Popen(['rosrun', 'mybot_control', 'swerve_controller', '__name:=good_controller'],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        try:
            wait_until_advertising(proc, '/good_controller', topics=['/swerve_a/rqst_pivot_angle'])
        finally:
            stop(proc)


if __name__ == '__main__':
    rospy.init_node('swerve_bad_config_test')
    rostest.rosrun('mybot_control', 'swerve_bad_config', SwerveBadConfigTest, sys.argv)
