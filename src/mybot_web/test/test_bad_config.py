#!/usr/bin/env python3
"""Bad configuration stops web_controller with exit status 1 and one message naming the problem."""
import socket
import subprocess
import sys
import unittest

import roslib.packages
import rospy
import rostest

PKG = "mybot_web"


class TestBadConfig(unittest.TestCase):
    def run_node(self, name, *params):
        node = roslib.packages.find_node(PKG, "web_controller")[0]
        proc = subprocess.run([sys.executable, node, "__name:=" + name] + list(params),
                              capture_output=True, text=True, timeout=60)
        return proc.returncode, proc.stdout + proc.stderr

    def test_out_of_range_port(self):
        code, out = self.run_node("web_bad_port", "_port:=70000")
        self.assertEqual(code, 1, out)
        self.assertIn("~port must be in [0, 65535]", out)

    def test_short_token_on_a_public_address(self):
        code, out = self.run_node("web_bad_token", "_host:=0.0.0.0", "_token:=abc")
        self.assertEqual(code, 1, out)
        self.assertIn("~token must be at least 8", out)

    def test_port_in_use(self):
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            s.listen(1)
            port = s.getsockname()[1]
            code, out = self.run_node("web_busy_port", "_port:=%d" % port)
        self.assertEqual(code, 1, out)
        self.assertIn("cannot listen on ~host 127.0.0.1, ~port %d" % port, out)


if __name__ == "__main__":
    rospy.init_node("test_web_bad_config", anonymous=True)
    rostest.rosrun(PKG, "web_bad_config", TestBadConfig, sys.argv)
