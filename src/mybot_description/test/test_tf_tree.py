#!/usr/bin/env python3
"""rostest: every link of robot_description is reachable in tf from the root frame."""
import sys
import unittest
import xml.etree.ElementTree as ET

import rospy
import rostest
import tf2_ros


class TfTreeTest(unittest.TestCase):
    def test_every_link_reachable(self):
        rospy.init_node("test_tf_tree")
        root = rospy.get_param("~root_frame", "base_footprint")
        timeout = rospy.get_param("~timeout", 20.0)
        robot = ET.fromstring(rospy.get_param("robot_description"))
        links = sorted(link.get("name") for link in robot.findall("link"))
        self.assertIn(root, links)
        self.assertGreater(len(links), 3)

        buf = tf2_ros.Buffer()
        tf2_ros.TransformListener(buf)
        deadline = rospy.Time.now() + rospy.Duration(timeout)
        missing = links
        while not rospy.is_shutdown() and rospy.Time.now() < deadline:
            missing = [l for l in links if not buf.can_transform(root, l, rospy.Time(0))]
            if not missing:
                break
            rospy.sleep(0.1)
        self.assertEqual(missing, [], "links not reachable in tf from %s: %s" % (root, missing))


if __name__ == "__main__":
    rostest.rosrun("mybot_description", "test_tf_tree", TfTreeTest, sys.argv)
