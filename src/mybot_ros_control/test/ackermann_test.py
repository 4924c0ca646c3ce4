#!/usr/bin/env python3
"""A car-like robot driven by ackermann_steering_controller (ackermann.test), measured by ground
truth: it drives the commanded distance straight; angular.z steers the front wheel to that angle,
and the robot turns at v tan(angle) / L, its odometry with it; it stops once cmd_vel stops; a
steering joint without a position interface is refused naming the parameter."""
import math
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry

from mybot_common.geometry import wrap, yaw_of
from mybot_lockstep import wait_connected

from controller_test import DriveTest, refusal

WHEELBASE, RADIUS = 0.5, 0.1  # the fixture's, which the controller reads from the URDF


def twist(v, steer):
    t = Twist()
    t.linear.x, t.angular.z = v, steer
    return t


class Ackermann(DriveTest):
    @classmethod
    def setUpClass(cls):
        cls.join("ackermann_test")
        cls.watch("car", "/ackermann_steering_controller/odom")
        cls.cmd = cls.ls.Publisher("/ackermann_steering_controller/cmd_vel", Twist, queue_size=1)
        cls.unpause_when_running(2, [])
        cls.ls.sleep(0.5)  # settle on its wheels

    def drive(self, v, steer, seconds):
        """Sends the command at 50 Hz for `seconds` of sim time."""
        rate = self.ls.Rate(50)
        t0 = rospy.get_time()
        while rospy.get_time() - t0 < seconds:
            self.cmd.publish(twist(v, steer))
            rate.sleep()

    def stop(self):
        self.drive(0.0, 0.0, 1.0)

    def test_1_listed_with_its_two_joints_on_their_interfaces(self):
        c = {c.name: c for c in self.list().controller}["ackermann_steering_controller"]
        self.assertEqual(c.type, "ackermann_steering_controller/AckermannSteeringController")
        self.assertEqual(c.state, "running")
        res = {r.hardware_interface: list(r.resources) for r in c.claimed_resources}
        self.assertEqual(res, {"hardware_interface/VelocityJointInterface": ["rear_wheel_joint"],
                               "hardware_interface/PositionJointInterface": ["front_steer_joint"]})

    def test_2_drives_straight_the_commanded_distance(self):
        self.drive(0.5, 0.0, 1.0)  # past the 0.25 s acceleration ramp
        x0, y0, th0 = self.truth()
        ox0, oy0, _ = self.odometry()
        t0 = rospy.get_time()
        self.drive(0.5, 0.0, 3.0)
        x1, y1, th1 = self.truth()
        ox1, oy1, _ = self.odometry()
        commanded = 0.5 * (rospy.get_time() - t0)
        self.stop()
        dist = math.hypot(x1 - x0, y1 - y0)
        self.assertLess(abs(dist - commanded) / commanded, 0.02, "drove %.4f m of %.4f" % (dist, commanded))
        self.assertLess(abs(math.degrees(wrap(th1 - th0))), 2.0)
        odom_dist = math.hypot(ox1 - ox0, oy1 - oy0)
        self.assertLess(abs(odom_dist - dist), 0.01, "odometry %.4f m, truth %.4f m" % (odom_dist, dist))

    def test_3_angular_z_steers_and_the_robot_turns_as_the_bicycle_model_says(self):
        v, steer = 0.4, 0.3
        self.drive(v, steer, 1.5)  # the wheel steered and up to speed
        self.assertAlmostEqual(self.position("front_steer_joint"), steer, delta=0.005)
        th0, oth0 = self.truth()[2], self.odometry()[2]
        t0 = rospy.get_time()
        turned = odom_turned = 0.0
        rate = self.ls.Rate(50)
        last, olast = th0, oth0
        while rospy.get_time() - t0 < 4.0:
            self.cmd.publish(twist(v, steer))
            rate.sleep()
            th, oth = self.truth()[2], self.odometry()[2]
            turned += wrap(th - last)
            odom_turned += wrap(oth - olast)
            last, olast = th, oth
        expected = v * math.tan(steer) / WHEELBASE * (rospy.get_time() - t0)
        self.stop()
        rospy.loginfo("ackermann: turned %.4f rad, odometry %.4f, the bicycle model %.4f", turned, odom_turned, expected)
        self.assertGreater(turned, 0.9)  # a real turn, left for a positive angle
        self.assertLess(abs(turned - expected) / expected, 0.05)
        self.assertLess(abs(odom_turned - turned), 0.02)

    def test_4_it_stops_once_cmd_vel_stops(self):
        self.drive(0.5, 0.0, 1.0)
        self.ls.sleep(0.25 + 0.5)  # cmd_vel_timeout, then the 2 m/s^2 ramp down from 0.5 m/s
        x0, y0, _ = self.truth()
        self.ls.sleep(0.5)
        x1, y1, _ = self.truth()
        self.assertLess(math.hypot(x1 - x0, y1 - y0), 0.005)

    def test_5_a_steer_without_a_position_interface_is_refused_naming_the_parameter(self):
        rospy.set_param("/bad_car_controller", {"type": "ackermann_steering_controller/AckermannSteeringController",
                                                "rear_wheel": "rear_wheel_joint", "front_steer": "rear_wheel_joint"})
        self.assertFalse(self.load(name="bad_car_controller").ok)
        why = refusal(lambda cm: cm.load("bad_car_controller"))
        self.assertIn("bad_car_controller", why)
        self.assertIn("front_steer", why)
        self.assertIn("PositionJointInterface", why)

    def test_6_open_loop_odometry_turns_at_the_commands_bicycle_rate(self):
        params = dict(rospy.get_param("/ackermann_steering_controller"), open_loop=True)
        rospy.set_param("/open_loop_controller", params)
        self.assertTrue(self.load(name="open_loop_controller").ok)
        odom = []
        sub = self.ls.Subscriber("/open_loop_controller/odom", Odometry, odom.append)
        pub = self.ls.Publisher("/open_loop_controller/cmd_vel", Twist, queue_size=1)
        self.assertTrue(self.switch(start_controllers=["open_loop_controller"],
                                    stop_controllers=["ackermann_steering_controller"], strictness=2).ok)
        wait_connected([sub, pub])
        v, steer = 0.4, 0.3
        rate = self.ls.Rate(50)
        t0 = rospy.get_time()
        while rospy.get_time() - t0 < 1.0:  # past the ramps
            pub.publish(twist(v, steer))
            rate.sleep()
        start = odom[-1]
        while rospy.get_time() - t0 < 3.0:
            pub.publish(twist(v, steer))
            rate.sleep()
        end = odom[-1]
        for _ in range(50):
            pub.publish(twist(0.0, 0.0))
            rate.sleep()
        self.assertTrue(self.switch(start_controllers=["ackermann_steering_controller"],
                                    stop_controllers=["open_loop_controller"], strictness=2).ok)
        elapsed = (end.header.stamp - start.header.stamp).to_sec()
        turned = wrap(yaw_of(end.pose.pose.orientation) - yaw_of(start.pose.pose.orientation))
        self.assertGreater(elapsed, 1.5)
        # The command's own rate: exact but for the odometry publications' 20 ms grid.
        self.assertAlmostEqual(turned, v * math.tan(steer) / WHEELBASE * elapsed, delta=1e-6)
        self.assertAlmostEqual(end.twist.twist.angular.z, v * math.tan(steer) / WHEELBASE, delta=1e-9)


if __name__ == "__main__":
    rostest.rosrun("mybot_ros_control", "ackermann_test", Ackermann)
