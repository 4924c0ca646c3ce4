#!/usr/bin/env python3
"""Simulator-in-the-loop SLAM test: drives a scripted route through the world on ground truth,
records the SLAM pose (tf map -> base) against ground truth, and scores the final map against the
world rendered by mybot_gazebo_lite's world_to_map.

~mode: accuracy      -> occupied precision/recall >= ~min_precision/~min_recall, ATE < ~max_ate
       loop_closure  -> the SLAM node with loop closure (`slam`) meets ~min_precision, ~min_recall
                        and ~max_ate, and where the one without (`open/slam`) drifted below
                        ~min_precision it beats it: its keyframe trajectory (`~trajectory`, after
                        optimisation) has the smaller ATE and its map the better precision (and
                        recall, where the open loop's recall missed ~min_recall too), each map
                        placed by its own trajectory's best fit to ground truth;
                        where the open loop did not drift, it is no worse within ~ate_tolerance
                        and ~precision_tolerance
~drive: plugin (cmd_vel) | joints (wheel velocity commands)
~base_frame: frame whose map pose is recorded (base_footprint)"""
import bisect
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry, Path
from nav_msgs.srv import GetMap
from std_msgs.msg import Float64
from std_srvs.srv import Trigger

from mybot_map_server.map_saver import save_map, yaw_from_quaternion
from mybot_common.geometry import wrap as normalize
from mybot_lockstep import participant

PKG = "mybot_nav_bringup"


class SlamSimTest(unittest.TestCase):
    def setUp(self):
        rospy.init_node("slam_sim_test")
        self.tmp = tempfile.mkdtemp(prefix="mybot_slam_")
        self.mode = rospy.get_param("~mode", "accuracy")
        self.drive = rospy.get_param("~drive", "plugin")
        self.world = rospy.get_param("~world")
        self.waypoints = rospy.get_param("~waypoints")
        self.speed = rospy.get_param("~speed", 0.4)
        self.base_frame = rospy.get_param("~base_frame", "base_footprint")
        self.truth = None
        self.tf = tf2_ros.Buffer(cache_time=rospy.Duration(600))
        self.listener = tf2_ros.TransformListener(self.tf)
        # A lockstep participant (mybot_lockstep): the route is driven period by period on
        # ground truth, so the run is the same on an idle and on a busy machine.
        # It joins at its first sleep (sleep_until below), set up: joined here, time would run
        # from its first tick until that sleep, a wall-time stretch, and the drive would start at
        # a moment that depends on the load.
        self.ls = participant(defer_join=True)
        self.ls.Subscriber("ground_truth/odom", Odometry, self.on_truth, queue_size=50)
        self.cmd = self.ls.Publisher("cmd_vel", Twist, queue_size=1)
        self.left = self.ls.Publisher("left_wheel_hinge/command", Float64, queue_size=1)
        self.right = self.ls.Publisher("right_wheel_hinge/command", Float64, queue_size=1)
        self.to_sample = []  # (stamp, truth (x,y,yaw)) every 0.2 s of the route
        self.samples = []  # (stamp, est (x,y,yaw), truth (x,y,yaw))
        self.truth_history = []  # (stamp s, x, y, yaw), every ground-truth message

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def on_truth(self, msg):
        p = msg.pose.pose
        self.truth = (msg.header.stamp, p.position.x, p.position.y,
                      yaw_from_quaternion(p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w))
        self.truth_history.append((msg.header.stamp.to_sec(),) + self.truth[1:])

    def truth_at(self, t):
        """Ground truth interpolated at stamp t (None outside the recorded span)."""
        h = self.truth_history
        i = bisect.bisect_left(h, (t,))
        if i == 0 or i >= len(h) or h[i][0] - h[i - 1][0] > 0.1:
            return None
        a, b = h[i - 1], h[i]
        f = (t - a[0]) / max(b[0] - a[0], 1e-9)
        return (a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2]), normalize(a[3] + f * normalize(b[3] - a[3])))

    def keyframe_samples(self, topic):
        """The SLAM node's keyframes after its last optimisation, paired with ground truth."""
        path = rospy.wait_for_message(topic, Path, timeout=30)
        out = []
        for p in path.poses:
            t = p.header.stamp.to_sec()
            g = self.truth_at(t)
            q = p.pose.orientation
            if g is not None:
                out.append((t, (p.pose.position.x, p.pose.position.y, yaw_from_quaternion(q.x, q.y, q.z, q.w)), g))
        return out

    def wait(self, cond, timeout, what):
        # Wall-clock bound: connections and start-up take wall time whatever the sim speed.
        deadline = time.monotonic() + timeout
        while not cond():
            if rospy.is_shutdown() or time.monotonic() > deadline:
                self.fail("timed out (%.0f s) waiting for %s" % (timeout, what))
            time.sleep(0.02)

    def command(self, v, w):
        if self.drive == "joints":
            r, sep = 0.1, 0.3  # true mybot geometry
            self.left.publish(Float64((v - w * sep / 2) / r))
            self.right.publish(Float64((v + w * sep / 2) / r))
        else:
            t = Twist()
            t.linear.x, t.angular.z = v, w
            self.cmd.publish(t)

    def estimates(self):
        """The online estimate (tf map -> base as SLAM published it) at each sampled stamp, read
        after the drive from the listener's buffer: waiting for it during the drive would hold
        simulated time, which waits for this node under lockstep."""
        for stamp, truth in self.to_sample:
            try:
                t = self.tf.lookup_transform("map", self.base_frame, stamp)
            except (tf2_ros.LookupException, tf2_ros.ExtrapolationException, tf2_ros.ConnectivityException):
                continue
            q = t.transform.rotation
            est = (t.transform.translation.x, t.transform.translation.y, yaw_from_quaternion(q.x, q.y, q.z, q.w))
            self.samples.append((stamp.to_sec(), est, truth))

    def drive_route(self):
        rate = self.ls.Rate(20)
        last_record = None
        for wx, wy in self.waypoints:
            deadline = rospy.Time.now() + rospy.Duration(120)
            while not rospy.is_shutdown():
                stamp, x, y, yaw = self.truth
                self.assertLess(rospy.Time.now(), deadline,
                                "waypoint (%.1f, %.1f) not reached: ground truth (%.2f, %.2f, %.2f rad) at %.2f s, "
                                "now %.2f s" % (wx, wy, x, y, yaw, stamp.to_sec(), rospy.Time.now().to_sec()))
                dist = math.hypot(wx - x, wy - y)
                if dist < 0.1:
                    break
                err = normalize(math.atan2(wy - y, wx - x) - yaw)
                if abs(err) > 0.25:
                    self.command(0.0, max(-1.0, min(1.0, 2.0 * err)))
                else:
                    self.command(min(self.speed, dist + 0.1), 2.0 * err)
                if last_record is None or (self.truth[0] - last_record).to_sec() >= 0.2:
                    self.to_sample.append((self.truth[0], self.truth[1:]))
                    last_record = self.truth[0]
                rate.sleep()
        self.command(0.0, 0.0)
        self.ls.release()

    def fetch_map(self, service):
        rospy.wait_for_service(service, timeout=30)
        return rospy.ServiceProxy(service, GetMap)().map

    def score(self, grid, name, samples):
        # The trajectory also gives the map -> world alignment (its least-squares fit).
        base = os.path.join(self.tmp, name)
        save_map(grid, base)
        cmd = ["rosrun", "mybot_slam", "slam_score", "--map", base + ".yaml", "--truth", os.path.join(self.tmp, "truth.yaml")]
        with open(base + "_est.txt", "w") as fe, open(base + "_gt.txt", "w") as fg:
            for t, e, g in samples:
                fe.write("%.4f %.5f %.5f %.5f\n" % ((t,) + e))
                fg.write("%.4f %.5f %.5f %.5f\n" % ((t,) + tuple(g)))
        cmd += ["--traj", base + "_est.txt", "--truth-traj", base + "_gt.txt"]
        out = subprocess.run(cmd, check=True, capture_output=True, text=True, timeout=60).stdout
        result = dict((k, float(v)) for k, v in (line.split() for line in out.splitlines()))
        rospy.loginfo("slam_sim_test: %s: %s", name, result)
        return result

    def test_mapping(self):
        # Under lockstep (the launch names this node in lockstep_wait_for, so time starts with
        # it), hold simulated time at start_at while the set-up below takes its wall time: the
        # drive then starts at the same simulated moment in every run, and odom_noise has drawn
        # the same noise before it (it draws per odometry message, standing still too).
        self.ls.sleep_until(rospy.Time(rospy.get_param("~start_at", 1.0)))
        self.wait(lambda: self.truth is not None, 30, "ground_truth/odom")
        # Ground truth at the laser's height, from the same world file the simulator loaded.
        # Polled in wall time: lookup_transform's own timeout sleeps in sim time, which stands here.
        self.wait(lambda: self.tf.can_transform("base_footprint", "hokuyo", rospy.Time(0)), 30,
                  "tf base_footprint -> hokuyo")
        tf = self.tf.lookup_transform("base_footprint", "hokuyo", rospy.Time(0))
        subprocess.run(["rosrun", "mybot_gazebo_lite", "world_to_map", self.world, os.path.join(self.tmp, "truth"),
                        "--resolution", "0.05", "--height", "%.3f" % tf.transform.translation.z],
                       check=True, timeout=60)
        self.wait(lambda: self.tf.can_transform("map", self.base_frame, rospy.Time(0)), 30, "tf map -> " + self.base_frame)
        self.drive_route()
        # Let the last scans be processed before reading the map.
        rospy.sleep(2.0)
        # The listener is tf2_ros's (it fills the buffer in wall time, while this node holds
        # time at start_at too): every sample is read once the transforms at the last one are in.
        last = self.to_sample[-1][0]
        self.wait(lambda: self.tf.can_transform("map", self.base_frame, last), 30,
                  "tf map -> %s at %.2f s" % (self.base_frame, last.to_sec()))
        self.estimates()
        self.assertGreater(len(self.samples), 20)
        if self.mode == "accuracy":
            # The online estimate (tf map -> base as the robot drove): the stricter trajectory.
            closed = self.score(self.fetch_map("dynamic_map"), "slam", self.samples)
            self.assertGreaterEqual(closed["precision"], rospy.get_param("~min_precision", 0.9))
            self.assertGreaterEqual(closed["recall"], rospy.get_param("~min_recall", 0.9))
            self.assertLess(closed["ate_rmse_m"], rospy.get_param("~max_ate", 0.05))
            # finish_trajectory (Cartographer's name): the final optimisation, after which the
            # map no longer changes; scored on the keyframes it was rendered from.
            rospy.wait_for_service("finish_trajectory", timeout=30)
            finish = rospy.ServiceProxy("finish_trajectory", Trigger)
            done = finish()
            self.assertTrue(done.success, done.message)
            final = self.score(self.fetch_map("dynamic_map"), "final", self.keyframe_samples("slam/trajectory"))
            self.assertGreaterEqual(final["precision"], rospy.get_param("~min_precision", 0.9))
            self.assertGreaterEqual(final["recall"], rospy.get_param("~min_recall", 0.9))
            self.assertLess(final["ate_rmse_m"], rospy.get_param("~max_ate", 0.05))
            again = finish()
            self.assertFalse(again.success)
            self.assertIn("already finished", again.message)
        else:
            # Each node's own keyframes: the online estimate of the closed-loop node is only
            # corrected after a closure, and the open-loop node publishes no tf.
            closed = self.score(self.fetch_map("dynamic_map"), "slam", self.keyframe_samples("slam/trajectory"))
            open_loop = self.score(self.fetch_map("open/dynamic_map"), "open",
                                   self.keyframe_samples("open/slam/trajectory"))
            rospy.loginfo("slam_sim_test: closed %s, open %s", closed, open_loop)
            # The closed-loop map, whatever the open loop did.
            min_precision = rospy.get_param("~min_precision", 0.8)
            self.assertGreaterEqual(closed["precision"], min_precision)
            self.assertGreaterEqual(closed["recall"], rospy.get_param("~min_recall", 0.0))
            self.assertLess(closed["ate_rmse_m"], rospy.get_param("~max_ate", float("inf")))
            if open_loop["precision"] < min_precision:
                # The open loop drifted out of what is asked of a map: closing loops must pull it
                # back with a clear win (margins; defaults: just "better"), so that noise in
                # either run cannot decide it.
                self.assertLess(closed["ate_rmse_m"],
                                rospy.get_param("~max_ate_ratio", 1.0) * open_loop["ate_rmse_m"])
                self.assertGreater(closed["precision"],
                                   open_loop["precision"] + rospy.get_param("~min_precision_gain", 0.0))
                # Recall gains only where the open loop's recall missed the bar too: an open loop
                # whose recall was 0.973 (seed 3) cannot be beaten by 0.03.
                if open_loop["recall"] < rospy.get_param("~min_recall", 0.0):
                    self.assertGreater(closed["recall"],
                                       open_loop["recall"] + rospy.get_param("~min_recall_gain", 0.0))
            else:
                # The odometry's noise left the open loop a good map (it happens for some seeds):
                # there is no drift to remove, and closing loops must not make the map worse than
                # a tolerance (its closures are matches too, each a little off).
                self.assertLess(closed["ate_rmse_m"],
                                open_loop["ate_rmse_m"] + rospy.get_param("~ate_tolerance", 0.0))
                self.assertGreater(closed["precision"],
                                   open_loop["precision"] - rospy.get_param("~precision_tolerance", 0.0))


if __name__ == "__main__":
    rostest.rosrun(PKG, "slam_sim", SlamSimTest, sys.argv)
