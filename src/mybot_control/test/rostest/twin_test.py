#!/usr/bin/env python3
"""The twin follows the source robot from its emulated sensors: still (< 1 mm, < 0.1 deg over 60 s)
while the source rests with a noisy, biased gyro; within 5 % of the distance over a 10 m drive."""
import math
import random
import sys
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32

from gazebo_msgs.srv import GetModelState

from mybot_lockstep import participant
from mybot_lockstep.start_paused import unpause_when
from mybot_common.geometry import yaw_of

GYRO_BIAS, GYRO_NOISE = 0.3, 0.05  # deg/s: an MPU6050 at rest


def pose(odom):
    p = odom.pose.pose
    return p.position.x, p.position.y, yaw_of(p.orientation)


def relative(start, end):
    """end in start's frame."""
    dx, dy = end[0] - start[0], end[1] - start[1]
    c, s = math.cos(start[2]), math.sin(start[2])
    return c * dx + s * dy, -s * dx + c * dy, math.atan2(math.sin(end[2] - start[2]), math.cos(end[2] - start[2]))


class TwinTest(unittest.TestCase):
    def setUp(self):
        rospy.init_node("twin_test")
        self.ls = participant(defer_join=True)  # joins with everything below set up
        self.rng = random.Random(7)
        self.truth = {}
        self.wheels = None
        for robot in ("source", "twin"):
            self.ls.Subscriber("/%s/ground_truth/odom" % robot, Odometry,
                               lambda m, r=robot: self.truth.__setitem__(r, m))
        self.ls.Subscriber("/source/joint_states", JointState, self.on_joints)
        self.cmd = self.ls.Publisher("/source/cmd_vel", Twist, queue_size=1)
        self.sensors = {k: self.ls.Publisher("/real/" + k, Float32, queue_size=1)
                        for k in ("wheel_left", "wheel_right", "gyro_z")}
        # The world starts paused: time starts once both robots stand in it, the same moment every run.
        get_state = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)
        rospy.wait_for_service("/gazebo/get_model_state", 60.0)
        # Joins (named in lockstep_wait_for) and holds the first period after the unpause: the
        # drive starts in that period on every run.
        unpause_when(self.ls, lambda: all(get_state(model_name=m).success for m in ("source", "twin")),
                     "the robots were not spawned")
        self.assertTrue(self.ls.wait_for(lambda: len(self.truth) == 2 and self.wheels is not None, 60.0),
                        "no ground truth or joint states")

    def on_joints(self, msg):
        v = dict(zip(msg.name, msg.velocity))
        if "left_wheel_hinge" in v and "right_wheel_hinge" in v:
            self.wheels = (v["left_wheel_hinge"], v["right_wheel_hinge"])

    def run_for(self, seconds, v, w):
        """Drives the source for `seconds` of sim time, sending its sensors every 20 ms."""
        rate = self.ls.Rate(50)
        end = rospy.Time.now() + rospy.Duration(seconds)
        while rospy.Time.now() < end:
            cmd = Twist()
            cmd.linear.x, cmd.angular.z = v, w
            self.cmd.publish(cmd)
            gyro = math.degrees(self.truth["source"].twist.twist.angular.z) + GYRO_BIAS + self.rng.gauss(0, GYRO_NOISE)
            self.sensors["wheel_left"].publish(Float32(self.wheels[0]))
            self.sensors["wheel_right"].publish(Float32(self.wheels[1]))
            self.sensors["gyro_z"].publish(Float32(gyro))
            rate.sleep()

    def test_twin_rests_then_follows(self):
        self.run_for(2.0, 0.0, 0.0)
        twin0, source0 = pose(self.truth["twin"]), pose(self.truth["source"])
        self.run_for(60.0, 0.0, 0.0)
        dx, dy, dyaw = relative(twin0, pose(self.truth["twin"]))
        sx, sy, syaw = relative(source0, pose(self.truth["source"]))
        rospy.loginfo("at rest for 60 s: twin moved %.5f m, turned %.4f deg; source moved %.5f m, turned %.4f deg",
                      math.hypot(dx, dy), math.degrees(dyaw), math.hypot(sx, sy), math.degrees(syaw))
        self.assertLess(math.hypot(dx, dy), 0.001)
        self.assertLess(abs(math.degrees(dyaw)), 0.1)

        source0, twin0 = pose(self.truth["source"]), pose(self.truth["twin"])
        travelled, last = 0.0, source0
        for seconds, v, w in ((9.0, 0.5, 0.0), (4.0, 0.4, 0.35), (9.0, 0.5, -0.15)):
            end = rospy.Time.now() + rospy.Duration(seconds)
            while rospy.Time.now() < end:
                self.run_for(0.2, v, w)
                now = pose(self.truth["source"])
                travelled += math.hypot(now[0] - last[0], now[1] - last[1])
                last = now
        self.run_for(1.0, 0.0, 0.0)
        s = relative(source0, pose(self.truth["source"]))
        t = relative(twin0, pose(self.truth["twin"]))
        gap = math.hypot(s[0] - t[0], s[1] - t[1])
        rospy.loginfo("10 m drive: source travelled %.2f m; twin %.3f m from it (%.1f %%), heading %.2f deg apart",
                      travelled, gap, 100 * gap / travelled, math.degrees(abs(s[2] - t[2])))
        self.assertGreater(travelled, 10.0)
        self.assertLess(gap, 0.05 * travelled)


if __name__ == "__main__":
    rostest.rosrun("mybot_control", "twin", TwinTest, sys.argv)
