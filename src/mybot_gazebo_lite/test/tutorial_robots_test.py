#!/usr/bin/env python3
"""Tutorial-style robots driven through their standard plugins, measured by ground truth:
2 % of the commanded distance, 2 degrees of heading."""
import math
import sys
import threading
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState, PointCloud, Range

from mybot_common.geometry import wrap, yaw_of
from gazebo_msgs.msg import ContactsState
from gazebo_msgs.srv import GetModelState
from mybot_lockstep import participant
from mybot_lockstep.start_paused import unpause_when


def twist(vx=0.0, vy=0.0, wz=0.0):
    t = Twist()
    t.linear.x, t.linear.y, t.angular.z = vx, vy, wz
    return t


class TutorialRobots(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("tutorial_robots_test")
        cls.ls = participant(defer_join=True)  # joins with everything below set up
        cls.lock = threading.Lock()
        cls.sonar = None
        cls.bumper = None
        cls.skid_joints = None
        cls.cloud = None
        cls.tricycle_odom = None
        cls.tricycle_joints = None
        cls.ls.Subscriber("/tricycle/odom", Odometry, cls._store("tricycle_odom"))
        cls.sixwheel_odom = None
        cls.ls.Subscriber("/sixwheel/odom", Odometry, cls._store("sixwheel_odom"))
        cls.ls.Subscriber("/tricycle/joint_states", JointState, cls._store("tricycle_joints"))
        cls.ls.Subscriber("/planar/points3d", PointCloud, cls._store("cloud"))
        cls.ls.Subscriber("/skid/joint_states", JointState, cls._store("skid_joints"))
        cls.ls.Subscriber("/skid/sonar", Range, cls._store("sonar"))
        cls.ls.Subscriber("/skid/bumper", ContactsState, cls._store("bumper"))
        cls.pubs = {n: cls.ls.Publisher("/%s/cmd_vel" % n, Twist, queue_size=1) for n in ("fourwheel", "skid", "planar", "tricycle", "sixwheel")}
        rospy.wait_for_service("/gazebo/get_model_state", timeout=60)
        cls.model = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)
        # The world starts paused: the spawners start in wall time, so time starts once the three
        # robots stand in it (the same moment every run); this joins (named in lockstep_wait_for)
        # and holds the first period after the unpause.
        unpause_when(cls.ls, lambda: all(cls.model(model_name=n).success for n in cls.pubs),
                     "the five robots were not spawned")
        cls.ls.sleep(1.0)  # settle on the ground

    @classmethod
    def _store(cls, name):
        def cb(m):
            with cls.lock:
                setattr(cls, name, m)
        return cb

    def pose(self, name):
        p = self.model(model_name=name).pose
        return p.position.x, p.position.y, yaw_of(p.orientation)

    def drive(self, name, cmd, seconds, settle=1.0):
        """Commands `cmd` for `seconds`; returns the poses at `settle` s (past the spin-up) and at the end, and the time between."""
        rate = self.ls.Rate(50)
        t0 = rospy.get_time()
        start = None
        while rospy.get_time() - t0 < seconds:
            self.pubs[name].publish(cmd)
            if start is None and rospy.get_time() - t0 >= settle:
                start = (rospy.get_time(), self.pose(name))
            rate.sleep()
        end = (rospy.get_time(), self.pose(name))
        for _ in range(25):
            self.pubs[name].publish(twist())
            rate.sleep()
        return start[1], end[1], end[0] - start[0]

    def check_straight(self, name, v):
        a, b, dt = self.drive(name, twist(vx=v), 5.0)
        dist, expected = math.hypot(b[0] - a[0], b[1] - a[1]), v * dt
        self.assertLess(abs(dist - expected) / expected, 0.02, "%s drove %.4f m of %.4f" % (name, dist, expected))
        self.assertLess(abs(math.degrees(wrap(b[2] - a[2]))), 2.0, "%s heading moved %.2f deg" % (name, math.degrees(b[2] - a[2])))

    def test_fourwheel_diff_drive_drives_straight(self):
        self.check_straight("fourwheel", 0.3)

    def test_skid_steer_drives_straight(self):
        self.check_straight("skid", 0.3)

    def test_skid_steer_turns_the_commanded_way(self):
        wheels = {}

        def sample():
            with self.lock:
                js = self.skid_joints
            if js is not None:
                wheels.update(zip(js.name, js.velocity))
        rate = self.ls.Rate(50)
        t0 = rospy.get_time()
        a = self.pose("skid")
        while rospy.get_time() - t0 < 3.0:
            self.pubs["skid"].publish(twist(wz=0.5))
            rate.sleep()
        sample()
        b = self.pose("skid")
        for _ in range(25):
            self.pubs["skid"].publish(twist())
            rate.sleep()
        # The wheels turn at the plugin's speeds: each side at -/+ w * separation / 2, over the
        # wheel radius (0.05 m, separation 0.34 m) ...
        expected = 0.5 * 0.34 / 2 / 0.05
        for name, sign in (("left_front_joint", -1), ("left_rear_joint", -1), ("right_front_joint", 1),
                           ("right_rear_joint", 1)):
            self.assertIn(name, wheels)
            self.assertLess(abs(wheels[name] - sign * expected) / expected, 0.02, "%s at %.3f rad/s, commanded %.3f" % (
                name, wheels[name], sign * expected))
        # ... and the body turns the commanded way, slower: four wheels skid sideways when they
        # turn, by an amount that depends on stick and slip at each contact (29.5 % of the command
        # here, 27-40 % when the robots came in other orders; README, known limits), so only the
        # direction is asserted.
        turned = wrap(b[2] - a[2])
        self.assertGreater(turned, 0.05, "turned %.3f rad" % turned)
        self.assertLess(turned, 0.5 * 3.0, "turned %.3f rad" % turned)

    def test_planar_move_goes_where_commanded(self):
        a, b, dt = self.drive("planar", twist(vx=0.3, vy=-0.2), 4.0, settle=0.5)
        dx, dy = b[0] - a[0], b[1] - a[1]
        expected = math.hypot(0.3, 0.2) * dt
        self.assertLess(abs(math.hypot(dx, dy) - expected) / expected, 0.02, "moved %.4f m of %.4f" % (math.hypot(dx, dy), expected))
        self.assertLess(abs(math.degrees(wrap(math.atan2(dy, dx) - math.atan2(-0.2, 0.3)))), 2.0)
        a, b, dt = self.drive("planar", twist(wz=0.5), 3.0, settle=0.5)
        self.assertLess(abs(math.degrees(wrap(b[2] - a[2]) - 0.5 * dt)), 2.0, "turned %.2f deg of %.2f" % (
            math.degrees(wrap(b[2] - a[2])), math.degrees(0.5 * dt)))

    def test_tricycle_drives_steers_and_counts_its_rear_wheels(self):
        """gazebo_ros_tricycle_drive: linear.x is the front wheel's speed, angular.z its steering
        angle; the rear wheels' odometry follows ground truth."""
        spawn = self.pose("tricycle")
        self.check_straight("tricycle", 0.3)
        # Steered 0.4 rad, the front wheel at 0.3 m/s: the body turns at v sin(0.4) / 0.45 m.
        delta = 0.4
        a, b, dt = self.drive("tricycle", twist(vx=0.3, wz=delta), 4.0)
        expected = 0.3 * math.sin(delta) / 0.45 * dt
        turned = wrap(b[2] - a[2])
        self.assertLess(abs(turned - expected) / expected, 0.05, "turned %.4f rad of %.4f" % (turned, expected))
        with self.lock:
            odom = self.tricycle_odom
        # Standing, steered by a command of no speed: the steering joint goes to the angle.
        rate = self.ls.Rate(50)
        for _ in range(10):
            self.pubs["tricycle"].publish(twist(wz=-0.3))
            rate.sleep()
        with self.lock:
            js = self.tricycle_joints
        self.assertAlmostEqual(dict(zip(js.name, js.position))["front_steering_joint"], -0.3, delta=0.01)
        self.pubs["tricycle"].publish(twist())
        # The odometry counts the rear wheels: it follows the point between them, 0.2 m behind
        # base_link, from where that point was at the spawn (the spawn's heading is 0).
        end = self.pose("tricycle")

        def axle(p):
            return p[0] - 0.2 * math.cos(p[2]), p[1] - 0.2 * math.sin(p[2])
        (x0, y0), (x1, y1) = axle(spawn), axle(end)
        o = odom.pose.pose
        err = math.hypot(o.position.x - (x1 - x0), o.position.y - (y1 - y0))
        self.assertLess(err, 0.01, "odometry %.4f m from the truth after %.2f m" % (err, math.hypot(x1 - x0, y1 - y0)))
        self.assertLess(abs(math.degrees(wrap(yaw_of(o.orientation) - wrap(end[2] - spawn[2])))), 1.0)

    def test_six_wheels_drive_straight_and_turn_the_commanded_way(self):
        """hector's multi-wheel drive: three wheels a side at the side's speed."""
        self.check_straight("sixwheel", 0.3)
        a, b, _ = self.drive("sixwheel", twist(wz=0.5), 3.0, settle=0.5)
        turned = wrap(b[2] - a[2])
        self.assertGreater(turned, 0.05, "turned %.3f rad" % turned)  # skid steering: the direction
        self.assertLess(turned, 0.5 * 2.5, "turned %.3f rad" % turned)
        with self.lock:
            o = self.sixwheel_odom
        self.assertEqual((o.header.frame_id, o.child_frame_id), ("odom", "base_link"))
        x, y, yaw = self.pose("sixwheel")  # its odometry is its world pose, as upstream's
        self.assertAlmostEqual(o.pose.pose.position.x, x, delta=0.01)
        self.assertAlmostEqual(o.pose.pose.position.y, y, delta=0.01)

    def test_sonar_sees_the_ground(self):
        self.assertTrue(self.ls.wait_for(lambda: self.sonar is not None, 5.0), "no /skid/sonar")
        with self.lock:
            m = self.sonar
        self.assertEqual(m.radiation_type, Range.ULTRASOUND)
        self.assertAlmostEqual(m.field_of_view, 0.2, places=5)
        # 45 degrees down from 0.16 m (wheel radius 0.05 + 0.06 + 0.05 mount); the steepest ray (0.1 rad more) hits first.
        z = self.pose("skid") and self.model(model_name="skid").pose.position.z + 0.05
        self.assertAlmostEqual(m.range, z / math.sin(math.pi / 4 + 0.1), delta=0.01)

    def test_block_laser_sees_the_ground(self):
        self.assertTrue(self.ls.wait_for(lambda: self.cloud is not None, 5.0), "no /planar/points3d")
        with self.lock:
            m = self.cloud
        self.assertEqual(m.header.frame_id, "planar/laser3d" if m.header.frame_id.startswith("planar/") else "laser3d")
        self.assertEqual(len(m.points), 15)
        self.assertEqual(m.channels[0].name, "intensity")
        # Every ray looks down at the flat ground: every point lies the sensor's height below it.
        h = self.model(model_name="planar").pose.position.z + 0.3
        for p in m.points:
            self.assertAlmostEqual(p.z, -h, delta=0.002)

    def test_bumper_reports_the_wheel_on_the_ground(self):
        self.assertTrue(self.ls.wait_for(lambda: self.bumper is not None and self.bumper.states, 5.0), "no contact on /skid/bumper")
        # And still after 3 s at rest, when the physics engine would have put the robot to sleep
        # (and stopped looking for its contacts) had the bumper not kept it awake.
        self.ls.sleep(3.0)
        with self.lock:
            m = self.bumper
        self.assertGreater(m.header.stamp.to_sec(), rospy.get_time() - 0.1)
        self.assertEqual(len(m.states), 1, "no contact on /skid/bumper after 3 s at rest")
        s = m.states[0]
        self.assertEqual(s.collision2_name, "ground_plane")
        self.assertIn("left_front", s.collision1_name)
        # It carries a quarter of the 7 kg robot, give or take how the four wheels share it.
        self.assertGreater(s.total_wrench.force.z, 0.1 * 7 * 9.8)


if __name__ == "__main__":
    rostest.rosrun("mybot_gazebo_lite", "tutorial_robots", TutorialRobots, sys.argv)
