#!/usr/bin/env python3
"""Cameras in the loop (camera.test): mybot's 800x800 camera and a depth-camera cube.

Rates are measured on the message stamps (sim time); waits are conditions with timeouts.
"""
import math
import threading
import time
import unittest

import numpy as np
import rospy
import rostest
from sensor_msgs.msg import CameraInfo, Image
from std_srvs.srv import Empty

from gazebo_msgs.srv import GetModelState

WALL_TIMEOUT = 60.0


class Collector:
    def __init__(self, topic, cls):
        self.lock = threading.Lock()
        self.msgs = []
        self.sub = rospy.Subscriber(topic, cls, self._cb, queue_size=50, buff_size=1 << 24)

    def _cb(self, m):
        with self.lock:
            self.msgs.append(m)

    def wait(self, cond, what, timeout=WALL_TIMEOUT):
        end = time.time() + timeout
        while time.time() < end and not rospy.is_shutdown():
            with self.lock:
                if cond(self.msgs):
                    return list(self.msgs)
            time.sleep(0.01)
        raise AssertionError('timed out waiting for ' + what)


class CameraTests(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('camera_test')
        cls.image = Collector('/mybot/camera1/image_raw', Image)
        cls.info = Collector('/mybot/camera1/camera_info', CameraInfo)
        cls.depth = Collector('/depth_cam/depth/image_raw', Image)
        cls.rgb = Collector('/depth_cam/rgb/image_raw', Image)
        # The world starts paused (camera.test) and the three models are spawned one after the
        # other: time starts once all three stand, so every frame shows all of them. (When time ran
        # from mybot's spawn, a state read before a model stood was success=false with a zero pose:
        # the crate's expected depth came out 2.05 m off, and the clean-clone gate timed out at
        # 8c82706.)
        for model in ('mybot', 'depth_cam', 'crate'):
            cls.spawned(model)
        rospy.ServiceProxy('/gazebo/unpause_physics', Empty)()

    @staticmethod
    def spawned(model):
        """The state of `model` once it is spawned (wall-time bound: the spawners' start-up)."""
        get_state = rospy.ServiceProxy('/gazebo/get_model_state', GetModelState)
        rospy.wait_for_service('/gazebo/get_model_state', WALL_TIMEOUT)
        end = time.time() + WALL_TIMEOUT
        while True:
            st = get_state(model_name=model)
            if st.success:
                return st
            if time.time() > end:
                raise AssertionError('the model %s was never spawned' % model)
            time.sleep(0.05)

    def test_image_and_info_sizes_rate(self):
        # From the first frame received: the camera renders only while someone listens, on its
        # period's grid, so that the stream's first gap is a period too (a grid started at the first
        # frame wanted gave 0.010 and 0.033 s when this test subscribed in the first period).
        t0 = self.image.wait(lambda m: len(m) > 0, 'a camera image')[0].header.stamp.to_sec()
        msgs = self.image.wait(lambda m: m[-1].header.stamp.to_sec() >= t0 + 2.0, '2 sim-seconds of images')
        stamps = [m.header.stamp.to_sec() for m in msgs if t0 <= m.header.stamp.to_sec() <= t0 + 2.0]
        # The rate from camera_info, published with every frame: small messages this subscriber
        # keeps up with. (A loaded machine may drop images here, 800x800 at 5x real time being
        # ~300 MB/s, which says nothing of the rate the camera publishes at: measured on the
        # images' shortest gap, every other frame dropped throughout would have read 15 Hz.)
        infos = self.info.wait(lambda m: m and m[-1].header.stamp.to_sec() >= t0 + 2.0, '2 sim-seconds of camera_info')
        info_stamps = [i.header.stamp.to_sec() for i in infos if t0 <= i.header.stamp.to_sec() <= t0 + 2.0]
        gaps = np.diff(info_stamps)
        period = (info_stamps[-1] - info_stamps[0]) / len(gaps)
        self.assertAlmostEqual(1.0 / period, 30.0, delta=3.0)
        # Every frame a period after the one before, to within a fifth of one (a frame is
        # stamped at the first physics step after it is due).
        self.assertLess(float(np.abs(gaps - period).max()), 0.2 * period, 'gaps %s' % gaps)
        # Each image received is one of those frames.
        self.assertGreaterEqual(len(stamps), 10)
        self.assertLessEqual(set(stamps), set(info_stamps))
        m = msgs[-1]
        self.assertEqual((m.width, m.height, m.encoding, m.step), (800, 800, 'rgb8', 2400))
        self.assertEqual(len(m.data), 800 * 800 * 3)
        self.assertEqual(m.header.frame_id, 'camera')
        img = np.frombuffer(m.data, dtype=np.uint8).reshape(800, 800, 3).astype(int)
        sky, wall = img[20:40, 380:420].mean(axis=(0, 1)), img[370:390, 380:420].mean(axis=(0, 1))
        self.assertGreater(sky[2], sky[0] + 20)  # bluish sky at the top
        self.assertLess(abs(wall[0] - wall[2]), 10)  # grey wall straight ahead

        info = self.info.wait(lambda m: len(m) > 0, 'camera_info')[-1]
        f = 800 / (2 * math.tan(1.3962634 / 2))
        self.assertEqual((info.width, info.height, info.header.frame_id), (800, 800, 'camera'))
        np.testing.assert_allclose(info.K, [f, 0, 400.5, 0, f, 400.5, 0, 0, 1], rtol=1e-9)
        np.testing.assert_allclose(info.P, [f, 0, 400.5, -f * 0.07, 0, f, 400.5, 0, 0, 0, 1, 0], rtol=1e-9)
        self.assertEqual(info.distortion_model, 'plumb_bob')
        self.assertEqual(len(info.D), 5)

    def test_depth_to_wall_matches_ground_truth(self):
        msgs = self.depth.wait(lambda m: len(m) >= 3, 'depth images')
        m = msgs[-1]
        self.assertEqual((m.width, m.height, m.encoding, m.step), (160, 120, '32FC1', 640))
        d = np.frombuffer(m.data, dtype=np.float32).reshape(120, 160)
        st = self.spawned('depth_cam')
        # The cube faces +y; its camera sits 5 cm ahead of its centre; the wall face is at y = 5.
        truth = 5.0 - (st.pose.position.y + 0.05)
        centre = d[30:60, 70:90]  # the wall spans rows 18..65 (camera 10 cm above the floor)
        self.assertAlmostEqual(float(np.median(centre)), truth, delta=0.005)
        self.assertLess(abs(float(np.std(centre)) - 0.005), 0.002)  # the configured noise
        self.assertTrue(np.isnan(d[0:5, :]).all())  # sky: no reading

    def test_gazebo_ros_depth_camera_publishes_under_its_own_default_names(self):
        """The cube's second depth sensor, libgazebo_ros_depth_camera.so given no topic names: as
        upstream, its colour image on ir/image_raw and ir/camera_info, its depth on depth/image_raw
        and depth/camera_info, its cloud on points."""
        depth = Collector('/ir_cam/depth/image_raw', Image)
        ir = Collector('/ir_cam/ir/image_raw', Image)
        info = Collector('/ir_cam/ir/camera_info', CameraInfo)
        m = depth.wait(lambda m: len(m) > 0, 'ir_cam depth images')[-1]
        self.assertEqual((m.width, m.height, m.encoding, m.header.frame_id), (32, 24, '32FC1', 'depth_camera'))
        d = np.frombuffer(m.data, dtype=np.float32).reshape(24, 32)
        truth = 5.0 - (self.spawned('depth_cam').pose.position.y + 0.05)  # the wall ahead, as above
        self.assertAlmostEqual(float(np.median(d[6:12, 14:18])), truth, delta=0.005)
        self.assertEqual(ir.wait(lambda m: len(m) > 0, 'ir_cam colour images')[-1].encoding, 'rgb8')
        self.assertEqual(info.wait(lambda m: len(m) > 0, 'ir_cam camera_info')[-1].width, 32)
        topics = dict(rospy.get_published_topics())
        self.assertEqual((topics.get('/ir_cam/points'), topics.get('/ir_cam/depth/camera_info')),
                         ('sensor_msgs/PointCloud2', 'sensor_msgs/CameraInfo'))

    def test_depth_camera_sees_another_robot_in_its_colour(self):
        # The crate (another robot, spawned by the launch file) 1.5 m ahead and 0.5 m to the
        # right: its near face, 0.2 m wide and high, covers columns 118-135 and rows 52-69.
        crate = self.spawned('crate').pose.position
        cam = self.spawned('depth_cam').pose.position
        truth = (crate.y - 0.1) - (cam.y + 0.05)

        def face(msgs):
            d = np.frombuffer(msgs[-1].data, dtype=np.float32).reshape(120, 160)[56:66, 122:132]
            return float(np.median(d))
        msgs = self.depth.wait(lambda m: len(m) > 0 and abs(face(m) - truth) < 0.02, 'the crate in the depth image')
        self.assertAlmostEqual(face(msgs), truth, delta=0.02)
        # Beside it, the wall 2.9 m ahead is still there.
        d = np.frombuffer(msgs[-1].data, dtype=np.float32).reshape(120, 160)
        self.assertAlmostEqual(float(np.median(d[30:50, 70:90])), 5.0 - (cam.y + 0.05), delta=0.01)
        # In Gazebo/Orange (1, 0.51, 0.05), shaded by the angle it is seen at.
        def orange(msgs):
            img = np.frombuffer(msgs[-1].data, dtype=np.uint8).reshape(120, 160, 3)[56:66, 122:132]
            r, g, b = img.reshape(-1, 3).mean(axis=0)
            return r > 150 and 0.4 < g / r < 0.6 and b < 25
        self.rgb.wait(lambda m: len(m) > 0 and orange(m), 'the orange crate in the colour image')

    def test_stereo_pair_sees_the_crate_with_the_disparity_of_its_depth(self):
        """gazebo_ros_multicamera: left and right under stereo/, the right camera 7 cm to the right,
        so the crate's face shifts left in its image by fx * 0.07 / depth pixels."""
        left = Collector('/stereo/left/image_raw', Image)
        right = Collector('/stereo/right/image_raw', Image)
        left_info = Collector('/stereo/left/camera_info', CameraInfo)
        right_info = Collector('/stereo/right/camera_info', CameraInfo)
        crate = self.spawned('crate').pose.position
        cam = self.spawned('depth_cam').pose.position
        depth = (crate.y - 0.1) - (cam.y + 0.05)

        def orange_columns(msg):
            img = np.frombuffer(msg.data, dtype=np.uint8).reshape(120, 160, 3)[56:66].astype(int)
            r, g, b = img[..., 0], img[..., 1], img[..., 2]
            mask = (r > 150) & (g > 0.4 * r) & (g < 0.6 * r) & (b < 25)
            return np.nonzero(mask.any(axis=0))[0]

        def pair(lefts):
            # A left and a right image of one instant, both showing the crate (wait() holds left's lock).
            with right.lock:
                stamps = {m.header.stamp: m for m in right.msgs}
                for m in reversed(lefts):
                    if m.header.stamp in stamps and len(orange_columns(m)) and len(orange_columns(stamps[m.header.stamp])):
                        self.pair = (m, stamps[m.header.stamp])
                        return True
            return False
        left.wait(pair, 'a left and a right image of one instant showing the crate')
        l, r = self.pair
        info_l = left_info.wait(lambda m: len(m) > 0, 'left camera_info')[-1]
        info_r = right_info.wait(lambda m: len(m) > 0, 'right camera_info')[-1]
        self.assertEqual(l.header.frame_id, 'stereo_optical')
        self.assertEqual(r.header.frame_id, 'stereo_optical')
        fx = info_l.K[0]
        self.assertEqual(info_l.P[3], 0.0)
        self.assertAlmostEqual(info_r.P[3], -fx * 0.07, places=6)
        # The face's columns (edges included) in each: their centres differ by the disparity.
        cl, cr = orange_columns(l), orange_columns(r)
        disparity = (cl.min() + cl.max()) / 2.0 - (cr.min() + cr.max()) / 2.0
        self.assertAlmostEqual(disparity, fx * 0.07 / depth, delta=1.0)
        for c in (left, right, left_info, right_info):
            c.sub.unregister()


if __name__ == '__main__':
    rostest.rosrun('mybot_gazebo_lite', 'sim_camera', CameraTests)
