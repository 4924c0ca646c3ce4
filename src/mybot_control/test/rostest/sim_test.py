#!/usr/bin/python3
"""Diff-drive chain in the simulator (mybot, joint-command mode), checked against ground truth.
~mode: square (2 m square through twist_mux, odometry vs ground truth), step (wheel PID step
0 -> 5 rad/s), weak (left wheel 20% weaker; ~pid_on says whether the PID should hold the
heading)."""
import math
import sys
import threading
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from std_msgs.msg import Float32

from chain_common import Chain, wrap, yaw_of
from mybot_lockstep import participant


class GroundTruth:
    def __init__(self):
        self.msg = None
        # The test's first use of the helper: it joins at its first sleep, its subscriptions made.
        participant(defer_join=True).Subscriber('ground_truth/odom', Odometry, self._cb, queue_size=20)

    def _cb(self, m):
        self.msg = m

    def pose(self):
        p = self.msg.pose.pose
        return p.position.x, p.position.y, yaw_of(p.orientation)


def relative(start, now):
    """Pose `now` in the frame of `start` (both x, y, yaw)."""
    dx, dy = now[0] - start[0], now[1] - start[1]
    c, s = math.cos(start[2]), math.sin(start[2])
    return c * dx + s * dy, -s * dx + c * dy, wrap(now[2] - start[2])


class SimTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('sim_test')
        cls.mode = rospy.get_param('~mode')
        cls.gt = GroundTruth()

    def test_sim(self):
        getattr(self, 'run_' + self.mode)()

    # --- 2 m square through the whole chain -------------------------------------------
    def run_square(self):
        chain = Chain(cmd_topic='nav_vel')
        chain.wait_ready()
        chain.wait_for(lambda: self.gt.msg is not None, 30.0, 'ground truth')
        chain.wait_stopped(timeout=30.0)
        odom0, gt0 = chain.pose(), self.gt.pose()
        rate = participant().Rate(50)
        for side in range(4):
            start = chain.pose()
            while not rospy.is_shutdown():  # 2 m forward, slowing near the end
                p = chain.pose()
                left = 2.0 - math.hypot(p[0] - start[0], p[1] - start[1])
                if left < 0.002:
                    break
                self.pub(chain, min(0.4, max(0.03, 1.5 * left)), 0.0)
                rate.sleep()
            chain.pub.publish(Twist())
            chain.wait_stopped(timeout=20.0)
            start = chain.pose()
            while not rospy.is_shutdown():  # turn left pi/2
                left = math.pi / 2 - wrap(chain.pose()[2] - start[2])
                if left < 0.002:
                    break
                self.pub(chain, 0.0, min(0.6, max(0.05, 2.0 * left)))
                rate.sleep()
            chain.pub.publish(Twist())
            chain.wait_stopped(timeout=20.0)
        odom = relative(odom0, chain.pose())
        gt = relative(gt0, self.gt.pose())
        err = math.hypot(odom[0] - gt[0], odom[1] - gt[1])
        rospy.loginfo('square: odom %s ground truth %s error %.4f m', odom, gt, err)
        self.assertLess(err, 0.02, 'odometry %s vs ground truth %s' % (odom, gt))
        self.assertLess(math.hypot(gt[0], gt[1]), 0.3)  # it did drive a closed square

    @staticmethod
    def pub(chain, vx, wz):
        m = Twist()
        m.linear.x = vx
        m.angular.z = wz
        chain.pub.publish(m)

    # --- time going backwards --------------------------------------------------------------
    def run_reset(self):
        """Drive, reset the simulation (the clock goes back to 0, as in Gazebo) and command
        nothing more: the robot must not move by itself, and the topics must flow again."""
        from sensor_msgs.msg import JointState
        from std_srvs.srv import Empty
        ls = participant()
        js = []
        ls.Subscriber('joint_states', JointState, lambda m: js.append(m.header.stamp.to_sec()), queue_size=50)
        chain = Chain(cmd_topic='nav_vel')
        rospy.wait_for_service('/gazebo/reset_simulation', 10.0)
        reset = rospy.ServiceProxy('/gazebo/reset_simulation', Empty)
        chain.wait_ready()
        chain.wait_for(lambda: self.gt.msg is not None, 30.0, 'ground truth')
        rate = ls.Rate(50)
        end = rospy.get_time() + 3.0
        while rospy.get_time() < end:  # driving at 0.4 m/s when the reset comes
            self.pub(chain, 0.4, 0.0)
            rate.sleep()
        # Called while this node holds the period (the simulator serves calls while it waits):
        # the reset falls between the same two periods on every run, with the robot driving.
        before = rospy.get_time()
        reset()
        ls.wait_for(lambda: rospy.get_time() < before, 1.0)
        self.assertLess(rospy.get_time(), before, 'the clock did not go back')
        reset_at = rospy.get_time()
        # Topics flow again within a second of sim time.
        n_js, n_odom = len(js), chain.odom_count
        ls.wait_for(lambda: len(js) > n_js + 2 and chain.odom_count > n_odom + 2 and self.gt.msg.header.stamp.to_sec() <= reset_at + 1.0, 1.0)
        self.assertGreater(len(js), n_js + 2, 'joint_states silent after the reset')
        self.assertGreater(chain.odom_count, n_odom + 2, 'odom silent after the reset')
        self.assertLess(self.gt.msg.header.stamp.to_sec(), reset_at + 1.0, 'ground truth silent after the reset')
        # Nothing commanded since the reset: nothing moves (a little settling at most).
        ls.sleep(0.5)
        p0 = self.gt.pose()
        ls.sleep(3.0)
        p1 = self.gt.pose()
        moved = math.hypot(p1[0] - p0[0], p1[1] - p0[1])
        rospy.loginfo('reset: moved %.4f m in 3 s of sim time after the reset with no command', moved)
        self.assertLess(moved, 0.005, 'the robot drove by itself after the reset')

    # --- wheel PID step --------------------------------------------------------------
    def run_step(self):
        lock = threading.Lock()
        enc = []
        participant().Subscriber('lwheel_angular_vel_enc', Float32,
                         lambda m: (lock.acquire(), enc.append((rospy.get_time(), m.data)), lock.release()))
        pubs = [participant().Publisher(t, Float32, queue_size=10) for t in
                ('lwheel_tangent_vel_target', 'rwheel_tangent_vel_target')]
        chain = Chain()
        chain.wait_for(lambda: len(enc) > 10, 60.0, 'encoder speeds')
        radius = 0.1
        rate = participant().Rate(50)
        t0 = rospy.get_time()
        while rospy.get_time() - t0 < 2.0:
            for p in pubs:
                p.publish(Float32(5.0 * radius))
            rate.sleep()
        for p in pubs:
            p.publish(Float32(0.0))
        with lock:
            series = [(t - t0, v) for t, v in enc if t >= t0]
        peak = max(v for _, v in series)
        outside = [t for t, v in series if abs(v - 5.0) > 0.05 * 5.0]
        settle = max(outside) if outside else 0.0
        rospy.loginfo('step: peak %.3f rad/s, settled (5%%) after %.3f s', peak, settle)
        self.assertLess(peak, 5.0 * 1.05, 'overshoot')
        self.assertLess(settle, 0.5, 'settling time')
        self.assertAlmostEqual(series[-1][1], 5.0, delta=0.1)

    # --- weak wheel --------------------------------------------------------------------
    def run_weak(self):
        pid_on = rospy.get_param('~pid_on')
        chain = Chain()
        chain.wait_ready()
        chain.wait_for(lambda: self.gt.msg is not None, 30.0, 'ground truth')
        chain.wait_stopped(timeout=30.0)
        gt0 = self.gt.pose()
        rate = participant().Rate(50)
        while not rospy.is_shutdown():
            p = relative(gt0, self.gt.pose())
            if math.hypot(p[0], p[1]) >= 2.0:
                break
            self.pub(chain, 0.2, 0.0)
            rate.sleep()
        chain.pub.publish(Twist())
        chain.wait_stopped(timeout=20.0)
        drift = math.degrees(abs(relative(gt0, self.gt.pose())[2]))
        rospy.loginfo('weak wheel, pid_on %s: heading drift %.2f deg over 2 m', pid_on, drift)
        if pid_on:
            # 0.45 deg in every run in lockstep, idle or loaded; the 2 deg asked of the GoPiGo
            # (whose driver's simulated motors run on the wall clock) was the bound here too.
            self.assertLess(drift, 0.6)
        else:
            self.assertGreater(drift, 10.0)  # open loop visibly curves


if __name__ == '__main__':
    rostest.rosrun('mybot_control', 'sim_test', SimTest, sys.argv)
