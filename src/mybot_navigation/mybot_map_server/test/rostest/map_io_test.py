#!/usr/bin/env python3
"""map_server serves hand-made fixtures with ROS's cell values; map_saver -> map_server is exact;
bad configuration exits non-zero naming the field and file."""
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import rospkg
import rospy
import rostest
from nav_msgs.msg import MapMetaData, OccupancyGrid
from nav_msgs.srv import GetMap

PKG = "mybot_map_server"
# Values worked out by hand from map_server's image_loader rules. Grid rows bottom-up:
# image row {100,150,255} first, then {0,254,205}.
EXPECTED = {
    "trinary": [-1, -1, 0, 100, 0, -1],
    "scale": [89, 47, 0, 100, 0, 1],
    "negate": [-1, -1, 100, 0, 100, 100],
}


def wait_map(topic, timeout=20.0):
    return rospy.wait_for_message(topic, OccupancyGrid, timeout=timeout)


class MapIoTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("map_io_test")
        cls.tmp = tempfile.mkdtemp(prefix="mybot_map_io_")
        cls.fixtures = os.path.join(rospkg.RosPack().get_path(PKG), "test", "fixtures")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_fixtures_match_ros_values(self):
        for ns, expected in EXPECTED.items():
            m = wait_map("/%s/map" % ns)
            self.assertEqual(list(m.data), expected, ns)
            self.assertEqual((m.info.width, m.info.height), (3, 2))
            self.assertAlmostEqual(m.info.resolution, 0.1, places=6)
            self.assertAlmostEqual(m.info.origin.position.x, -1.0)
            self.assertAlmostEqual(m.info.origin.position.y, 2.0)
        self.assertEqual(wait_map("/trinary/map").header.frame_id, "fixture_map")
        self.assertEqual(wait_map("/scale/map").header.frame_id, "map")
        meta = rospy.wait_for_message("/scale/map_metadata", MapMetaData, timeout=20.0)
        self.assertEqual(meta.width, 3)
        rospy.wait_for_service("/negate/static_map", timeout=20.0)
        srv = rospy.ServiceProxy("/negate/static_map", GetMap)
        self.assertEqual(list(srv().map.data), EXPECTED["negate"])

    def test_saver_server_round_trip_is_exact(self):
        original = wait_map("/trinary/map")
        base = os.path.join(self.tmp, "saved")
        subprocess.run(["rosrun", PKG, "map_saver", "-f", base, "map:=/trinary/map", "--timeout", "30"],
                       check=True, timeout=60)
        with open(base + ".yaml") as f:
            self.assertEqual(f.readline().strip(), "image: saved.pgm")
        server = subprocess.Popen(["rosrun", PKG, "map_server", base + ".yaml", "__ns:=roundtrip",
                                   "__name:=map_server_rt"])
        try:
            back = wait_map("/roundtrip/map")
        finally:
            server.terminate()
            server.wait(timeout=20)
        self.assertEqual(list(back.data), list(original.data))
        self.assertEqual((back.info.width, back.info.height), (original.info.width, original.info.height))
        self.assertAlmostEqual(back.info.resolution, original.info.resolution, places=6)
        self.assertAlmostEqual(back.info.origin.position.x, original.info.origin.position.x, places=6)
        self.assertAlmostEqual(back.info.origin.position.y, original.info.origin.position.y, places=6)

    def test_bad_mode_exits_naming_field_and_file(self):
        r = subprocess.run(["rosrun", PKG, "map_server", os.path.join(self.fixtures, "bad_mode.yaml"),
                            "__name:=map_server_bad"], capture_output=True, text=True, timeout=30)
        self.assertNotEqual(r.returncode, 0)
        out = r.stdout + r.stderr
        self.assertIn("mode", out)
        self.assertIn("bad_mode.yaml", out)

    def test_saver_times_out_without_a_map(self):
        start = time.monotonic()
        r = subprocess.run(["rosrun", PKG, "map_saver", "-f", os.path.join(self.tmp, "never"),
                            "map:=/no_such_map", "--timeout", "1"], capture_output=True, text=True, timeout=30)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("no map received", r.stdout + r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.tmp, "never.pgm")))
        self.assertLess(time.monotonic() - start, 25)


if __name__ == "__main__":
    rostest.rosrun(PKG, "map_io", MapIoTest, sys.argv)
