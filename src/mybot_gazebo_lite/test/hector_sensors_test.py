#!/usr/bin/env python3
"""hector_gazebo_plugins' GNSS, IMU, compass and sonar on an outdoor base (hector_sensors.test),
against ground truth: where the antenna is on the WGS84 ellipsoid, the IMU's configured biases,
the compass's heading, the sonar's range to the ground; and a holonomic base pushed by hector's
force-based drive going where it is commanded."""
import math
import threading
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist, Vector3Stamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, MagneticField, NavSatFix, NavSatStatus, Range
from std_srvs.srv import Empty

from mybot_common.geometry import wrap, yaw_of
from gazebo_msgs.srv import GetModelState
from mybot_lockstep import participant
from mybot_lockstep.start_paused import unpause_when

# The fixture's reference (outdoor_bot.urdf): heading 90, so x points east and y north.
LAT0, LON0, ALT0 = 49.9, 8.9, 100.0
ANTENNA = (0.1, 0.0, 0.3)  # navsat_link in base_link
G = 9.8


def wgs84_radii(lat_deg):
    """Metres per radian of latitude (meridian) and of longitude at `lat_deg`, from the
    textbook formulas (a = 6378137 m, f = 1 / 298.257223563)."""
    a, f = 6378137.0, 1 / 298.257223563
    e2 = f * (2 - f)
    s = math.sin(math.radians(lat_deg))
    n = a / math.sqrt(1 - e2 * s * s)
    m = a * (1 - e2) / (1 - e2 * s * s) ** 1.5
    return m, n * math.cos(math.radians(lat_deg))


def twist(vx=0.0, wz=0.0):
    t = Twist()
    t.linear.x, t.angular.z = vx, wz
    return t


def pitch_of(q):
    return math.asin(max(-1.0, min(1.0, 2 * (q.w * q.y - q.z * q.x))))


def roll_of(q):
    return math.atan2(2 * (q.w * q.x + q.y * q.z), 1 - 2 * (q.x * q.x + q.y * q.y))


class HectorSensors(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("hector_sensors_test")
        cls.ls = participant(defer_join=True)
        cls.lock = threading.Lock()
        cls.last = {}
        cls.imus = []
        for topic, cls_ in (("/outdoor/navsat/fix", NavSatFix), ("/outdoor/navsat/vel", Vector3Stamped),
                            ("/outdoor/imu/data/bias", Imu), ("/outdoor/magnetic", MagneticField),
                            ("/outdoor/sonar_down", Range)):
            cls.ls.Subscriber(topic, cls_, cls._store(topic))
        cls.ls.Subscriber("/outdoor/imu/data", Imu, cls._imu)
        cls.ls.Subscriber("/omni/odom", Odometry, cls._store("/omni/odom"))
        cls.cmd = cls.ls.Publisher("/outdoor/cmd_vel", Twist, queue_size=1)
        cls.omni_cmd = cls.ls.Publisher("/omni/cmd_vel", Twist, queue_size=1)
        rospy.wait_for_service("/gazebo/get_model_state", timeout=60)
        cls.model = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)
        unpause_when(cls.ls, lambda: all(cls.model(model_name=m).success for m in ("outdoor", "omni")),
                     "the robots were not spawned")
        cls.ls.sleep(0.5)

    @classmethod
    def _store(cls, topic):
        def cb(m):
            with cls.lock:
                cls.last[topic] = m
        return cb

    @classmethod
    def _imu(cls, m):
        with cls.lock:
            cls.imus.append(m)
            cls.last["/outdoor/imu/data"] = m

    def latest(self, topic):
        self.assertTrue(self.ls.wait_for(lambda: topic in self.last, 5.0), "nothing on " + topic)
        with self.lock:
            return self.last[topic]

    def drive(self, cmd, seconds):
        rate = self.ls.Rate(50)
        t0 = rospy.get_time()
        while rospy.get_time() - t0 < seconds:
            self.cmd.publish(cmd)
            rate.sleep()

    def stop(self):
        """Stops, and waits until every sensor has reported at rest (the GNSS's 10 Hz the slowest)."""
        self.drive(twist(), 0.5)

    def truth(self, model="outdoor"):
        p = self.model(model_name=model).pose
        return p.position.x, p.position.y, p.position.z, yaw_of(p.orientation)

    def drive_omni(self, vx=0.0, vy=0.0, wz=0.0, seconds=3.0, settle=0.5):
        """Commands the omni base; its poses (x, y, yaw) past `settle` and at the end, and the time between."""
        cmd = Twist()
        cmd.linear.x, cmd.linear.y, cmd.angular.z = vx, vy, wz
        rate = self.ls.Rate(50)
        t0 = rospy.get_time()
        start = None
        while rospy.get_time() - t0 < seconds:
            self.omni_cmd.publish(cmd)
            if start is None and rospy.get_time() - t0 >= settle:
                start = (rospy.get_time(), self.truth("omni"))
            rate.sleep()
        end = (rospy.get_time(), self.truth("omni"))
        for _ in range(25):
            self.omni_cmd.publish(Twist())
            rate.sleep()
        return start[1], end[1], end[0] - start[0]

    def test_force_based_move_goes_where_commanded(self):
        # 0.36 m/s towards (0.3, -0.2) in its own axes: within 2 % and 2 degrees, as planar_move.
        a, b, dt = self.drive_omni(vx=0.3, vy=-0.2)
        dx, dy = b[0] - a[0], b[1] - a[1]
        expected = math.hypot(0.3, 0.2) * dt
        self.assertLess(abs(math.hypot(dx, dy) - expected) / expected, 0.02, "moved %.4f m of %.4f" % (
            math.hypot(dx, dy), expected))
        self.assertLess(abs(math.degrees(wrap(math.atan2(dy, dx) - a[3] - math.atan2(-0.2, 0.3)))), 2.0)
        a, b, dt = self.drive_omni(wz=0.5, seconds=2.0)
        self.assertLess(abs(math.degrees(wrap(b[3] - a[3]) - 0.5 * dt)), 2.0, "turned %.2f deg of %.2f" % (
            math.degrees(wrap(b[3] - a[3])), math.degrees(0.5 * dt)))
        # Its odometry is the world pose (upstream's), stamped in odom -> base_footprint.
        self.drive_omni(seconds=0.2, settle=0.0)
        odom = self.latest("/omni/odom")
        x, y, _, yaw = self.truth("omni")
        self.assertEqual((odom.header.frame_id, odom.child_frame_id), ("odom", "base_footprint"))
        self.assertAlmostEqual(odom.pose.pose.position.x, x, delta=1e-3)
        self.assertAlmostEqual(odom.pose.pose.position.y, y, delta=1e-3)
        self.assertAlmostEqual(wrap(yaw_of(odom.pose.pose.orientation) - yaw), 0.0, delta=1e-3)

    def test_gnss_fix_is_where_the_antenna_is_on_the_ellipsoid(self):
        self.drive(twist(vx=0.5, wz=0.3), 4.0)
        self.stop()
        x, y, z, yaw = self.truth()
        ax = x + ANTENNA[0] * math.cos(yaw) - ANTENNA[1] * math.sin(yaw)
        ay = y + ANTENNA[0] * math.sin(yaw) + ANTENNA[1] * math.cos(yaw)
        self.assertGreater(math.hypot(ax, ay), 1.0, "the robot did not move")
        fix = self.latest("/outdoor/navsat/fix")
        m, e = wgs84_radii(LAT0)
        north = math.radians(fix.latitude - LAT0) * m
        east = math.radians(fix.longitude - LON0) * e
        self.assertAlmostEqual(east, ax, delta=0.001)
        self.assertAlmostEqual(north, ay, delta=0.001)
        self.assertAlmostEqual(fix.altitude, ALT0 + z + ANTENNA[2], delta=0.001)
        self.assertEqual(fix.header.frame_id, "navsat_link")
        self.assertEqual(fix.status.status, NavSatStatus.STATUS_FIX)
        self.assertEqual(fix.status.service, NavSatStatus.SERVICE_GPS)
        self.assertEqual(fix.position_covariance_type, NavSatFix.COVARIANCE_TYPE_DIAGONAL_KNOWN)

    def test_gnss_velocity_is_north_west_up(self):
        yaw = self.truth()[3]
        self.drive(twist(vx=0.5), 1.5)
        v = self.latest("/outdoor/navsat/vel").vector
        self.stop()
        # x east, y north: the robot's 0.5 m/s along its heading, as north and west.
        self.assertAlmostEqual(v.x, 0.5 * math.sin(yaw), delta=0.005)
        self.assertAlmostEqual(v.y, -0.5 * math.cos(yaw), delta=0.005)

    def test_imu_reports_its_configured_biases(self):
        self.drive(twist(wz=0.4), 1.0)
        turning = self.latest("/outdoor/imu/data")
        self.stop()
        imu = self.latest("/outdoor/imu/data")
        yaw = self.truth()[3]
        self.assertEqual(imu.header.frame_id, "imu_link")
        # <yawOffset> 0.05 turns the heading; <accelOffset> 0.098 along x tilts it by -0.098 / g.
        self.assertAlmostEqual(wrap(yaw_of(imu.orientation) - yaw), 0.05, delta=1e-3)
        self.assertAlmostEqual(pitch_of(imu.orientation), -0.098 / G, delta=1e-4)
        self.assertAlmostEqual(roll_of(imu.orientation), 0.0, delta=1e-4)
        # At rest the accelerometer feels the ground push up, plus its offset.
        self.assertAlmostEqual(imu.linear_acceleration.x, 0.098, delta=0.01)
        self.assertAlmostEqual(imu.linear_acceleration.z, G, delta=0.01)
        # The gyro: the turn plus its offset and wandering bias (0.005 rad/s spread at most 4 of it).
        self.assertAlmostEqual(turning.angular_velocity.z, 0.4 + 0.01, delta=0.025)
        self.assertAlmostEqual(imu.angular_velocity_covariance[0], 0.02 ** 2)
        self.assertEqual(imu.angular_velocity_covariance[8], 0.0)

    def test_imu_white_noise_has_its_spread(self):
        with self.lock:
            n0 = len(self.imus)
        self.drive(twist(), 5.0)  # 250 samples at 50 Hz
        with self.lock:
            wx = [m.angular_velocity.x for m in self.imus[n0:]]
        self.assertGreater(len(wx), 200)
        mean = sum(wx) / len(wx)
        sd = math.sqrt(sum((w - mean) ** 2 for w in wx) / (len(wx) - 1))
        # The spread's standard error with 250 samples is 4.5 %: 0.02 within 30 % is 6.7 of them.
        self.assertAlmostEqual(sd, 0.02, delta=0.006)

    def test_imu_calibrate_clears_the_gyro_drift(self):
        before = self.latest("/outdoor/imu/data/bias").angular_velocity.z
        # The wandering bias, drawn at load from <rateDrift> 0.005 (seed 0's draw: 0.0055 off).
        self.assertGreater(abs(before - 0.01), 1e-3)
        rospy.wait_for_service("/outdoor/imu/data/calibrate", timeout=30)
        rospy.ServiceProxy("/outdoor/imu/data/calibrate", Empty)()
        with self.lock:
            self.last.pop("/outdoor/imu/data/bias", None)
        bias = self.latest("/outdoor/imu/data/bias")
        # Left: the <rateOffset>, and what the drift wandered since (1e-5 rad/s in a step).
        self.assertAlmostEqual(bias.angular_velocity.z, 0.01, delta=1e-4)
        self.assertAlmostEqual(bias.linear_acceleration.x, 0.098, places=9)

    def test_compass_gives_the_heading(self):
        self.drive(twist(wz=0.5), 1.2)
        self.stop()
        f = self.latest("/outdoor/magnetic").magnetic_field
        yaw = self.truth()[3]
        # The world's x axis points 30 degrees north of east (outdoor.world's spherical
        # coordinates): north is 60 degrees anticlockwise of it, and the field's horizontal part
        # points 60 degrees - yaw from the robot's x axis (inclination 60: half the field).
        self.assertAlmostEqual(wrap(math.radians(60) - math.atan2(f.y, f.x) - yaw), 0.0, delta=1e-4)
        self.assertAlmostEqual(math.hypot(f.x, f.y), 0.5, delta=1e-4)
        self.assertAlmostEqual(f.z, -math.sqrt(3) / 2, delta=1e-4)

    def test_sonar_sees_the_ground_below_it(self):
        r = self.latest("/outdoor/sonar_down")
        self.assertEqual(r.radiation_type, Range.ULTRASOUND)
        self.assertEqual(r.header.frame_id, "sonar_link")  # hector's default frame
        self.assertAlmostEqual(r.field_of_view, 0.1, places=6)  # the lesser span: vertical
        z = self.truth()[2]
        self.assertAlmostEqual(r.range, z + 0.4 + 0.02, delta=0.002)  # its mount's height plus <offset>


if __name__ == "__main__":
    rostest.rosrun("mybot_gazebo_lite", "hector_sensors_test", HectorSensors)
