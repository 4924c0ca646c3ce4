#!/usr/bin/env python3
"""A four-wheel-steering robot driven by four_wheel_steering_controller (four_wheel_steering.test),
measured by ground truth: cmd_vel drives it straight the commanded distance, turns it at the
commanded rate with its front and rear wheels steered opposite ways, and crabs it along linear.y
without turning; cmd_four_wheel_steering steers its virtual front and rear wheels and odom_steer
reports them back; its odometry follows the ground truth; it stops once the commands stop; a
joint list of the wrong length or a steering joint without a position interface is refused
naming the parameter."""
import math
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist

from four_wheel_steering_msgs.msg import FourWheelSteering, FourWheelSteeringStamped
from mybot_common.geometry import wrap

from controller_test import DriveTest, refusal

WHEEL_BASE, STEERING_TRACK = 0.6, 0.4  # the fixture's steering joints apart, read from the URDF
CTRL = "/four_wheel_steering_controller/"
WHEELS = ["%s_%s_wheel_joint" % (a, s) for a in ("front", "rear") for s in ("left", "right")]
STEERS = ["%s_%s_steering_joint" % (a, s) for a in ("front", "rear") for s in ("left", "right")]


def twist(vx, vy, wz):
    t = Twist()
    t.linear.x, t.linear.y, t.angular.z = vx, vy, wz
    return t


def four_ws(speed, front, rear):
    return FourWheelSteering(speed=speed, front_steering_angle=front, rear_steering_angle=rear)


class FourWheelSteeringTest(DriveTest):
    @classmethod
    def setUpClass(cls):
        cls.join("four_wheel_steering_test")
        cls.steer = None
        cls.watch("fws", CTRL + "odom")
        cls.ls.Subscriber(CTRL + "odom_steer", FourWheelSteeringStamped, cls._on_steer)
        cls.cmd = cls.ls.Publisher(CTRL + "cmd_vel", Twist, queue_size=1)
        cls.cmd_4ws = cls.ls.Publisher(CTRL + "cmd_four_wheel_steering", FourWheelSteering, queue_size=1)
        cls.unpause_when_running(2, [])
        cls.ls.sleep(0.5)  # settle on its wheels

    @classmethod
    def _on_steer(cls, m):
        with cls.lock:
            cls.steer = m

    def drive(self, msg, seconds, pub=None):
        """Sends `msg` at 50 Hz for `seconds` of sim time; returns (truth, odometry) turned (rad),
        summed step by step."""
        pub = pub or self.cmd
        rate = self.ls.Rate(50)
        t0 = rospy.get_time()
        turned = odom_turned = 0.0
        last, olast = self.truth()[2], self.odometry()[2]
        while rospy.get_time() - t0 < seconds:
            pub.publish(msg)
            rate.sleep()
            th, oth = self.truth()[2], self.odometry()[2]
            turned += wrap(th - last)
            odom_turned += wrap(oth - olast)
            last, olast = th, oth
        return turned, odom_turned

    def stop(self):
        self.drive(twist(0.0, 0.0, 0.0), 1.0)

    def moved(self, before, after):
        """The motion from pose `before` to `after`, in `before`'s frame."""
        dx, dy = after[0] - before[0], after[1] - before[1]
        c, s = math.cos(before[2]), math.sin(before[2])
        return c * dx + s * dy, -s * dx + c * dy

    def test_1_listed_with_its_eight_joints_on_their_interfaces(self):
        c = {c.name: c for c in self.list().controller}["four_wheel_steering_controller"]
        self.assertEqual(c.type, "four_wheel_steering_controller/FourWheelSteeringController")
        self.assertEqual(c.state, "running")
        res = {r.hardware_interface: sorted(r.resources) for r in c.claimed_resources}
        self.assertEqual(res, {"hardware_interface/VelocityJointInterface": sorted(WHEELS),
                               "hardware_interface/PositionJointInterface": sorted(STEERS)})
        self.assert_advertises({CTRL + "odom": "nav_msgs/Odometry",
                                CTRL + "odom_steer": "four_wheel_steering_msgs/FourWheelSteeringStamped"})

    def test_2_cmd_vel_drives_straight_the_commanded_distance(self):
        self.drive(twist(0.5, 0.0, 0.0), 1.0)  # past the 0.25 s acceleration ramp
        before, obefore = self.truth(), self.odometry()
        t0 = rospy.get_time()
        self.drive(twist(0.5, 0.0, 0.0), 3.0)
        after, oafter = self.truth(), self.odometry()
        commanded = 0.5 * (rospy.get_time() - t0)
        self.stop()
        along, across = self.moved(before, after)
        self.assertLess(abs(along - commanded) / commanded, 0.02, "drove %.4f m of %.4f" % (along, commanded))
        self.assertLess(abs(across), 0.02)
        self.assertLess(abs(math.degrees(wrap(after[2] - before[2]))), 2.0)
        odom_dist = math.hypot(oafter[0] - obefore[0], oafter[1] - obefore[1])
        self.assertLess(abs(odom_dist - along), 0.01, "odometry %.4f m, truth %.4f m" % (odom_dist, along))

    def test_3_cmd_vel_turns_with_the_front_and_rear_wheels_steered_opposite_ways(self):
        v, w = 0.4, 0.6
        self.drive(twist(v, 0.0, w), 1.5)  # steered and up to speed
        front_left = math.atan(w * WHEEL_BASE / (2 * v - w * STEERING_TRACK))  # upstream's twist mode
        self.assertAlmostEqual(self.position("front_left_steering_joint"), front_left, delta=0.01)
        self.assertAlmostEqual(self.position("rear_left_steering_joint"), -front_left, delta=0.01)
        t0 = rospy.get_time()
        turned, odom_turned = self.drive(twist(v, 0.0, w), 4.0)
        expected = w * (rospy.get_time() - t0)
        self.stop()
        rospy.loginfo("four_wheel_steering: turned %.4f rad, odometry %.4f, commanded %.4f", turned, odom_turned,
                      expected)
        self.assertLess(abs(turned - expected) / expected, 0.05)
        self.assertLess(abs(odom_turned - turned), 0.03)

    def test_4_linear_y_crabs_without_turning(self):
        vx, vy = 0.3, 0.3
        self.drive(twist(vx, vy, 0.0), 1.0)
        for j in STEERS:
            self.assertAlmostEqual(self.position(j), math.atan2(vy, vx), delta=0.01, msg=j)
        before, obefore = self.truth(), self.odometry()
        t0 = rospy.get_time()
        self.drive(twist(vx, vy, 0.0), 3.0)
        after, oafter = self.truth(), self.odometry()
        elapsed = rospy.get_time() - t0
        self.stop()
        along, across = self.moved(before, after)
        oalong, oacross = self.moved(obefore, oafter)
        rospy.loginfo("four_wheel_steering: crabbed %.4f, %.4f m; odometry %.4f, %.4f m", along, across, oalong, oacross)
        self.assertAlmostEqual(along, vx * elapsed, delta=0.03 * vx * elapsed)
        self.assertAlmostEqual(across, vy * elapsed, delta=0.03 * vy * elapsed)
        self.assertLess(abs(math.degrees(wrap(after[2] - before[2]))), 2.0)
        self.assertLess(math.hypot(oalong - along, oacross - across), 0.02)

    def test_5_cmd_four_wheel_steering_turns_on_its_virtual_wheels_and_odom_steer_reports_them(self):
        speed, front, rear = 0.4, 0.3, -0.2
        self.drive(four_ws(speed, front, rear), 1.5, self.cmd_4ws)
        with self.lock:
            steer = self.steer
        self.assertAlmostEqual(steer.data.front_steering_angle, front, delta=0.01)
        self.assertAlmostEqual(steer.data.rear_steering_angle, rear, delta=0.01)
        t0 = rospy.get_time()
        turned, odom_turned = self.drive(four_ws(speed, front, rear), 3.0, self.cmd_4ws)
        elapsed = rospy.get_time() - t0
        self.stop()
        # The bicycle model: the centre at `speed`, its direction between the two virtual wheels'.
        a = math.atan((math.tan(front) + math.tan(rear)) / 2)
        expected = speed * math.cos(a) * (math.tan(front) - math.tan(rear)) / WHEEL_BASE * elapsed
        rospy.loginfo("four_wheel_steering: 4ws turned %.4f rad, odometry %.4f, the bicycle model %.4f", turned,
                      odom_turned, expected)
        self.assertLess(abs(turned - expected) / expected, 0.05)
        self.assertLess(abs(odom_turned - turned), 0.03)

    def test_6_it_stops_once_the_commands_stop(self):
        self.drive(twist(0.5, 0.0, 0.0), 1.0)
        self.ls.sleep(0.25 + 0.5)  # cmd_vel_timeout, then the 2 m/s^2 ramp down from 0.5 m/s
        before = self.truth()
        self.ls.sleep(0.5)
        after = self.truth()
        self.assertLess(math.hypot(after[0] - before[0], after[1] - before[1]), 0.005)

    def test_7_bad_joint_lists_are_refused_naming_the_parameter(self):
        good = rospy.get_param(CTRL.rstrip("/"))
        rospy.set_param("/one_wheel_controller", dict(good, front_wheel=["front_left_wheel_joint"]))
        why = refusal(lambda cm: cm.load("one_wheel_controller"))
        self.assertIn("front_wheel", why)
        self.assertIn("two joints", why)
        rospy.set_param("/wheel_steer_controller", dict(good, front_steering=WHEELS[:2]))
        self.assertFalse(self.load(name="wheel_steer_controller").ok)
        why = refusal(lambda cm: cm.load("wheel_steer_controller"))
        self.assertIn("front_steering", why)
        self.assertIn("PositionJointInterface", why)


if __name__ == "__main__":
    rostest.rosrun("mybot_ros_control", "four_wheel_steering_test", FourWheelSteeringTest)
