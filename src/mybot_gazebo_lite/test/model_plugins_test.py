#!/usr/bin/env python3
"""Model plugins in lockstep (model_plugins.test): gazebo_ros_force pushes a 2 kg crate as Newton
says; gazebo_ros_f3d reports the external wrench on it; gazebo_ros_joint_pose_trajectory poses a
turntable's joint point by point, as upstream times the points; gazebo_ros_ft_sensor reads what
that joint carries; gazebo_ros_triggered_camera and _multicamera render a frame per trigger;
gazebo_ros_vacuum_gripper holds a box up while it is on; roboticsgroup's mimic joint plugin makes a
gripper's fingers follow its driven one; gazebo_ros_p3d's and gazebo_ros_imu's gaussianNoise spreads
their readings as much as it says."""
import math
import threading
import unittest

import rospy
import rostest
from geometry_msgs.msg import Wrench, WrenchStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Image, Imu
from std_msgs.msg import Bool, Empty as EmptyMsg
from geometry_msgs.msg import Pose
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint
from std_srvs.srv import Empty

from gazebo_msgs.srv import (ApplyBodyWrench, ApplyJointEffort, BodyRequest, DeleteModel, GetJointProperties,
                             GetModelState, SpawnModel)
from mybot_lockstep import participant, wait_connected
from mybot_lockstep.start_paused import unpause_when

MASS, G = 2.0, 9.8


def wrench(fx=0.0, fz=0.0, tz=0.0):
    w = Wrench()
    w.force.x, w.force.z, w.torque.z = fx, fz, tz
    return w


class ModelPluginTests(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("model_plugins_test")
        cls.ls = participant(defer_join=True)
        cls.lock = threading.Lock()
        cls.f3d = None
        cls.ft = []
        cls.ls.Subscriber("/crate/wrench", WrenchStamped, cls._f3d)
        cls.ls.Subscriber("/table/turn_wrench", WrenchStamped, cls._ft)
        cls.tip = None
        cls.ls.Subscriber("/table/tip_wrench", WrenchStamped, cls._tip)
        cls.grasping = None
        cls.ls.Subscriber("/suction/grasping", Bool, cls._grasping)
        cls.push = cls.ls.Publisher("/crate/push", Wrench, queue_size=1)
        cls.noisy = {"noisy_truth": [], "imu": []}
        cls.ls.Subscriber("/crate/noisy_truth", Odometry, lambda m: cls._noisy("noisy_truth", m))
        cls.ls.Subscriber("/crate/imu", Imu, lambda m: cls._noisy("imu", m))
        rospy.wait_for_service("/gazebo/get_model_state", timeout=60)
        cls.model = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)
        cls.apply = rospy.ServiceProxy("/gazebo/apply_body_wrench", ApplyBodyWrench)
        cls.reset = rospy.ServiceProxy("/gazebo/reset_world", Empty)
        cls.joint = rospy.ServiceProxy("/gazebo/get_joint_properties", GetJointProperties)
        cls.trajectory = cls.ls.Publisher("/table/set_joint_trajectory", JointTrajectory, queue_size=10)
        cls.frames = {}
        links = []
        for cam in ("snap", "pair/left", "pair/right"):
            cls.frames[cam] = []
            links.append(cls.ls.Subscriber("/cams/%s/image_raw" % cam, Image,
                                           lambda m, cam=cam: cls._frame(cam, m)))
        cls.shutter = {cam: cls.ls.Publisher("/cams/%s/image_trigger" % cam, EmptyMsg, queue_size=10)
                       for cam in ("snap", "pair/left", "pair/right")}
        unpause_when(cls.ls, lambda: all(cls.model(model_name=m).success for m in ("crate", "table", "cams", "suction", "mimic")),
                     "not every model was spawned")
        # A frame is rendered only for a subscriber, and a trigger sent before its connection is
        # lost: both connected before anything is asked (wall time: connections are made in it).
        wait_connected(links + list(cls.shutter.values()))
        cls.ls.sleep(0.5)  # settle on the ground

    @classmethod
    def _f3d(cls, m):
        with cls.lock:
            cls.f3d = m

    @classmethod
    def _noisy(cls, topic, m):
        with cls.lock:
            cls.noisy[topic].append(m)

    @classmethod
    def _frame(cls, cam, m):
        with cls.lock:
            cls.frames[cam].append(m)

    def taken(self):
        """The frames each camera sent since the last call."""
        with self.lock:
            out = {cam: list(f) for cam, f in self.frames.items()}
            for f in self.frames.values():
                del f[:]
        return out

    @classmethod
    def _tip(cls, m):
        with cls.lock:
            cls.tip = m

    @classmethod
    def _grasping(cls, m):
        with cls.lock:
            cls.grasping = m.data

    @classmethod
    def _ft(cls, m):
        with cls.lock:
            cls.ft.append(m)

    def reported(self):
        with self.lock:
            return self.f3d

    def z(self):
        return self.model(model_name="crate").pose.position.z

    def setUp(self):
        self.push.publish(wrench())
        self.reset()
        self.ls.sleep(0.5)

    def test_an_upward_push_above_its_weight_lifts_it_as_newton_says(self):
        z0, t0 = self.z(), rospy.get_time()
        self.push.publish(wrench(fz=1.5 * MASS * G))
        self.ls.sleep(0.5)
        dz, t = self.z() - z0, rospy.get_time() - t0
        # a = F/m - g = 4.9 m/s^2 from the period the push arrives in (lockstep: within 10 ms of
        # t0); 5 mm for the contact's give at the start.
        a = 1.5 * G - G
        self.assertGreater(dz, 0.5 * a * (t - 0.01) ** 2 - 0.005)
        self.assertLess(dz, 0.5 * a * t ** 2 + 0.005)
        w = self.reported()
        self.assertEqual(w.header.frame_id, "world")
        self.assertAlmostEqual(w.wrench.force.z, 1.5 * MASS * G, places=6)
        self.assertAlmostEqual(w.wrench.force.x, 0.0, places=9)

    def test_f3d_adds_apply_body_wrench_and_a_nan_push_is_ignored(self):
        self.push.publish(wrench(tz=0.5))
        self.push.publish(wrench(fx=float("nan")))  # ignored: the torque stays
        res = self.apply(body_name="crate::box", wrench=wrench(fx=3.0), duration=rospy.Duration(-1))
        self.assertTrue(res.success, res.status_message)
        self.ls.sleep(0.1)
        w = self.reported().wrench
        self.assertAlmostEqual(w.force.x, 3.0, places=6)
        self.assertAlmostEqual(w.torque.z, 0.5, places=6)
        rospy.ServiceProxy("/gazebo/clear_body_wrenches", BodyRequest)(body_name="crate::box")

    def test_a_reset_lets_go_of_the_push(self):
        self.push.publish(wrench(fz=1.5 * MASS * G))
        self.ls.sleep(0.2)
        self.assertGreater(self.z(), 0.05)
        self.reset()
        self.ls.sleep(0.5)
        self.assertLess(self.z(), 0.01)  # back on the ground, and staying there
        self.assertAlmostEqual(self.reported().wrench.force.z, 0.0, places=9)

    def spread(self, values, truth, sigma):
        """Checks samples of truth + N(0, sigma): their mean, and their deviation within 20 % (with
        300 samples or more, the estimate's standard error is 4 % or less)."""
        n = len(values)
        mean = sum(values) / n
        std = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1))
        self.assertLess(abs(mean - truth), 5 * sigma / math.sqrt(n), (mean, truth))
        self.assertGreater(std, 0.8 * sigma)
        self.assertLess(std, 1.2 * sigma)

    def test_gaussian_noise_spreads_p3d_and_imu_readings_as_much_as_it_says(self):
        """At rest on the ground: the truth is its resting pose and no motion, the IMU's gravity."""
        for m in self.noisy.values():
            del m[:]
        self.ls.sleep(3.0)  # 300 readings of each at 100 Hz
        rest = self.model(model_name="crate").pose.position
        with self.lock:
            odom, imu = list(self.noisy["noisy_truth"]), list(self.noisy["imu"])
        self.assertGreaterEqual(len(odom), 300)
        self.assertGreaterEqual(len(imu), 300)
        p = [m.pose.pose.position for m in odom]
        self.spread([v.x - rest.x for v in p] + [v.y - rest.y for v in p] + [v.z - rest.z for v in p], 0.0, 0.01)
        for part in ("linear", "angular"):
            v = [getattr(m.twist.twist, part) for m in odom]
            self.spread([a.x for a in v] + [a.y for a in v] + [a.z for a in v], 0.0, 0.01)
        self.assertAlmostEqual(odom[-1].pose.covariance[0], 1e-4, places=12)
        self.assertAlmostEqual(odom[-1].twist.covariance[35], 1e-4, places=12)
        w = [m.angular_velocity for m in imu]
        self.spread([a.x for a in w] + [a.y for a in w] + [a.z for a in w], 0.0, 0.02)
        a = [m.linear_acceleration for m in imu]
        self.spread([v.x for v in a] + [v.y for v in a], 0.0, 0.02)
        self.spread([v.z for v in a], G, 0.02)
        self.assertAlmostEqual(imu[-1].angular_velocity_covariance[0], 4e-4, places=12)

    def turn(self):
        return self.joint(joint_name="table::turn").position[0]

    def send(self, joints, points, frame="world"):
        m = JointTrajectory()
        m.header.frame_id = frame
        m.joint_names = joints
        for positions, after in points:
            m.points.append(JointTrajectoryPoint(positions=positions, time_from_start=rospy.Duration(after)))
        self.trajectory.publish(m)

    def test_a_joint_trajectory_poses_the_joint_point_by_point(self):
        # Upstream's timing: each point's time_from_start is the wait before the next one.
        self.send(["turn"], [([0.5], 1.0), ([1.0], 0.5), ([-0.5], 0.0)])
        for wait, expected in ((0.5, 0.5), (0.75, 1.0), (0.75, -0.5)):  # at 0.5, 1.25 and 2.0 s
            self.ls.sleep(wait)
            self.assertAlmostEqual(self.turn(), expected, delta=1e-3)

    def test_a_bad_trajectory_moves_nothing(self):
        self.send(["turn"], [([0.8], 0.0)])
        self.ls.sleep(0.2)
        self.assertAlmostEqual(self.turn(), 0.8, delta=1e-3)
        for joints, points, frame in ((["turn", "no_such_joint"], [([0.1, 0.1], 0.0)], "world"),
                                      (["turn"], [([float("nan")], 0.0)], "world"),
                                      (["turn"], [([5.0], 0.0)], "world"),  # beyond its limits (-3, 3)
                                      (["turn"], [([0.1, 0.2], 0.0)], "world"),
                                      (["turn"], [([0.1], 0.0)], "plate")):  # keeping another link still
            self.send(joints, points, frame)
            self.ls.sleep(0.2)
            self.assertAlmostEqual(self.turn(), 0.8, delta=1e-3, msg=str((joints, points, frame)))

    def test_the_turntables_joint_carries_the_plates_weight_in_the_plates_axes(self):
        """The 0.5 kg plate's centre of mass is 0.1 m out along its x, the 0.2 kg tip's 0.25 m:
        whatever way the plate points, the joint holds up their weight, (0, 0, 0.7 g) in the
        plate's axes, and the torque that keeps them level, (0, -(0.5 x 0.1 + 0.2 x 0.25) g, 0),
        at the sensor's 50 Hz; the tip's kept fixed mount its own weight and torque."""
        for angle in (0.8, -2.0):
            self.send(["turn"], [([angle], 0.0)])
            self.ls.sleep(0.2)
            with self.lock:
                del self.ft[:]
            self.ls.sleep(0.2)
            with self.lock:
                got = list(self.ft)
            self.assertEqual(len(got), 10)  # 0.2 s at 50 Hz
            for m in got:
                self.assertEqual(m.header.frame_id, "plate")
                w = m.wrench
                for value, expected in ((w.force.x, 0.0), (w.force.y, 0.0), (w.force.z, 0.7 * G),
                                        (w.torque.x, 0.0), (w.torque.y, -0.1 * G), (w.torque.z, 0.0)):
                    self.assertAlmostEqual(value, expected, delta=1e-6, msg=(angle, str(w)))
            with self.lock:
                tip = self.tip
            self.assertEqual(tip.header.frame_id, "tip")
            for value, expected in ((tip.wrench.force.z, 0.2 * G), (tip.wrench.torque.y, -0.2 * G * 0.05),
                                    (tip.wrench.force.x, 0.0), (tip.wrench.torque.z, 0.0)):
                self.assertAlmostEqual(value, expected, delta=1e-6, msg=(angle, str(tip.wrench)))

    def test_a_triggered_camera_renders_one_frame_per_trigger(self):
        self.ls.sleep(0.3)
        self.assertEqual(self.taken(), {"snap": [], "pair/left": [], "pair/right": []},
                         "a triggered camera rendered untriggered (at its sensor's 30 Hz)")
        # Two triggers in one period make one frame, at the step after they arrive.
        t0 = rospy.get_time()
        self.shutter["snap"].publish(EmptyMsg())
        self.shutter["snap"].publish(EmptyMsg())
        self.ls.sleep(0.1)
        got = self.taken()
        self.assertEqual(len(got["snap"]), 1, got)
        self.assertEqual(got["pair/left"] + got["pair/right"], [])
        stamp = got["snap"][0].header.stamp.to_sec()
        self.assertGreater(stamp, t0)
        self.assertLessEqual(stamp, t0 + 0.01 + 1e-9)  # within the period the triggers came in
        self.assertEqual(got["snap"][0].header.frame_id, "post")
        # The stereo pair: a trigger on either camera's topic shutters both, in one instant.
        for cam in ("pair/right", "pair/left"):
            self.shutter[cam].publish(EmptyMsg())
            self.ls.sleep(0.1)
            got = self.taken()
            self.assertEqual((len(got["snap"]), len(got["pair/left"]), len(got["pair/right"])), (0, 1, 1), cam)
            self.assertEqual(got["pair/left"][0].header.stamp, got["pair/right"][0].header.stamp)

    BOX = ('<sdf version="1.6"><model name="parcel"><link name="link"><inertial><mass>0.2</mass><inertia>'
           '<ixx>0.0003</ixx><iyy>0.0003</iyy><izz>0.0003</izz></inertia></inertial><collision name="c">'
           '<geometry><box><size>0.1 0.1 0.1</size></box></geometry></collision></link></model></sdf>')

    def test_a_vacuum_gripper_holds_a_box_up_while_it_is_on(self):
        on = rospy.ServiceProxy("/suction/on", Empty)
        off = rospy.ServiceProxy("/suction/off", Empty)
        cup_z = 0.8  # the post's frame (suction_post.urdf), at (-3, 3)
        on()
        pose = Pose()
        pose.position.x, pose.position.y, pose.position.z = -3.0, 3.0, cup_z - 0.004  # within the 1 cm snap
        pose.orientation.w = 1.0
        res = rospy.ServiceProxy("/gazebo/spawn_sdf_model", SpawnModel)(model_name="parcel", model_xml=self.BOX,
                                                                       initial_pose=pose)
        self.assertTrue(res.success, res.status_message)
        try:
            self.ls.sleep(1.0)
            held = self.model(model_name="parcel").pose.position
            self.assertAlmostEqual(held.z, cup_z, delta=1e-3)  # held up, on the cup, for a second
            self.assertAlmostEqual(held.x, -3.0, delta=1e-3)
            with self.lock:
                self.assertIs(self.grasping, True)
            off()
            self.ls.sleep(1.0)
            self.assertAlmostEqual(self.model(model_name="parcel").pose.position.z, 0.05, delta=0.005)  # dropped
            with self.lock:
                self.assertIs(self.grasping, False)
            on()  # 0.75 m below the cup, out of its 5 cm reach: left alone
            self.ls.sleep(0.5)
            self.assertAlmostEqual(self.model(model_name="parcel").pose.position.z, 0.05, delta=0.005)
            with self.lock:
                self.assertIs(self.grasping, False)
        finally:
            off()
            rospy.ServiceProxy("/gazebo/delete_model", DeleteModel)(model_name="parcel")

    def test_mimic_joints_follow_the_driven_finger(self):
        def position(joint):
            return self.joint(joint_name="mimic::" + joint).position[0]

        def check(servo_tolerance, pid_tolerance):
            lead = position("finger_joint")
            self.assertAlmostEqual(position("mirror_joint"), -lead + 0.1, delta=servo_tolerance)
            self.assertAlmostEqual(position("pid_joint"), 0.5 * lead, delta=pid_tolerance)
            return lead

        check(1e-4, 1e-3)  # at rest, the mirror 0.1 rad off
        # The driven finger turned by a torque against its damping (0.5 rad/s): the servo follows
        # on time (the leader's speed fed forward), the PID behind by what its gains leave.
        res = rospy.ServiceProxy("/gazebo/apply_joint_effort", ApplyJointEffort)(
            joint_name="mimic::finger_joint", effort=0.05, start_time=rospy.Time(0), duration=rospy.Duration(1.0))
        self.assertTrue(res.success, res.status_message)
        self.ls.sleep(0.8)
        moving = check(1e-4, 5e-3)  # measured: 1e-16 and 1.0e-3
        self.assertGreater(moving, 0.3)
        self.ls.sleep(1.2)  # the torque gone, the finger stops; both followers settle on it
        check(1e-4, 1e-3)  # measured: 1e-16 and 2e-4

if __name__ == "__main__":
    rostest.rosrun("mybot_gazebo_lite", "model_plugins_test", ModelPluginTests)
