"""rosrun mybot_control twin: a simulated twin follows a real robot from its own sensors.

Subscribes (the report's form) `wheel_left`, `wheel_right` (rad/s) and `gyro_z` (deg/s) as
std_msgs/Float32 (~scalar_type: Float32 | Int32), or with ~input:=ros `joint_states`
(sensor_msgs/JointState: ~left_joint, ~right_joint velocities, rad/s) and `imu`
(sensor_msgs/Imu: angular_velocity.z, rad/s). Publishes `cmd_vel` for the twin at ~rate (50 Hz):
linear = ~wheel_radius * mean wheel speed, angular = the gyro less ~gyro_bias (deg/s) with
|rate| <= ~gyro_deadband (deg/s) taken as 0, and wheel speeds within ~wheel_deadband (0.02 rad/s)
of 0 taken as 0; input older than ~timeout (0.5 s) stops the twin.
~calibrate:=N: keep the robot still; the node reads the gyro for N s, prints the bias and the dead
band to use, and exits."""
import math

import rospy
from geometry_msgs.msg import Twist
from sensor_msgs.msg import Imu, JointState
from std_msgs.msg import Float32, Int32

from mybot_common import params
from mybot_control.nodes import common
from mybot_control.twin import TwinMapper, propose_deadband
from mybot_lockstep import participant


class Node:
    def __init__(self):
        # Joins at its first sleep, its subscriptions made: the simulator then opens their
        # connections before time moves on, and no sensor message is lost at the start.
        self.ls = participant(defer_join=True)
        radius = common.get("wheel_radius", 0.1, params.number, low=0, low_open=True)
        deadband = common.get("gyro_deadband", 0.5, params.number, low=0)
        bias = common.get("gyro_bias", 0.0, params.number)
        timeout = common.get("timeout", 0.5, params.number, low=0, low_open=True)
        wheel_deadband = common.get("wheel_deadband", 0.02, params.number, low=0)
        self.rate = common.get("rate", 50.0, params.number, low=0, low_open=True)
        self.calibrate = common.get("calibrate", 0.0, params.number, low=0)
        self.input = common.get("input", "scalars", params.string, choices=("scalars", "ros"))
        scalar = {"Float32": Float32, "Int32": Int32}[
            common.get("scalar_type", "Float32", params.string, choices=("Float32", "Int32"))]
        self.mapper = TwinMapper(radius, deadband, bias, timeout, wheel_deadband)
        self.samples = []
        self.wheel = [None, None]
        if self.input == "scalars":
            self.ls.Subscriber("wheel_left", scalar, lambda m: self.on_wheel(0, m.data))
            self.ls.Subscriber("wheel_right", scalar, lambda m: self.on_wheel(1, m.data))
            self.ls.Subscriber("gyro_z", scalar, lambda m: self.on_gyro(float(m.data)))
        else:
            self.joints = (common.get("left_joint", "left_wheel_hinge", params.string),
                           common.get("right_joint", "right_wheel_hinge", params.string))
            self.ls.Subscriber("joint_states", JointState, self.on_joints)
            self.ls.Subscriber("imu", Imu, lambda m: self.on_gyro(math.degrees(m.angular_velocity.z)))
        self.pub = self.ls.Publisher("cmd_vel", Twist, queue_size=1)
        rospy.loginfo("twin: wheel radius %.3f m, gyro bias %.3f deg/s, dead band %.3f deg/s, input %s",
                      radius, bias, deadband, self.input)

    def on_wheel(self, k, value):
        self.wheel[k] = float(value)
        if None not in self.wheel:
            self.mapper.wheels(rospy.Time.now().to_sec(), *self.wheel)

    def on_joints(self, msg):
        speeds = dict(zip(msg.name, msg.velocity))
        if all(j in speeds for j in self.joints):
            self.mapper.wheels(rospy.Time.now().to_sec(), speeds[self.joints[0]], speeds[self.joints[1]])

    def on_gyro(self, dps):
        self.mapper.gyro(rospy.Time.now().to_sec(), dps)
        if self.calibrate > 0:
            self.samples.append(dps)

    def spin(self):
        if self.calibrate > 0:
            rospy.loginfo("twin: calibrating: keep the robot still for %.0f s", self.calibrate)
            self.ls.sleep(self.calibrate)
            bias, band = propose_deadband(self.samples)
            rospy.loginfo("twin: %d gyro readings at rest: use gyro_bias:=%.3f gyro_deadband:=%.3f (deg/s)",
                          len(self.samples), bias, band)
            print("gyro_bias: %.3f\ngyro_deadband: %.3f" % (bias, band))
            return 0
        rate = self.ls.Rate(self.rate)
        while not rospy.is_shutdown():
            v, w = self.mapper.twist(rospy.Time.now().to_sec())
            cmd = Twist()
            cmd.linear.x, cmd.angular.z = v, w
            self.pub.publish(cmd)
            try:
                rate.sleep()
            except rospy.ROSTimeMovedBackwardsException:
                pass  # stale input is dropped by the mapper's clock check
        return 0


def main():
    common.run("twin", lambda: Node().spin())
