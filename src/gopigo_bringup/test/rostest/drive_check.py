#!/usr/bin/env python3
"""rostest checks of the GoPiGo chain with the simulated backend (see the .test files).

~check:
  open_loop  - nav_forward: equal wheel speeds; nav_rotate: opposite ones; cmd_vel vs
               cmd_vel_enc within ~tolerance (2%) in steady state. Runs the nav_* launch files.
  drift      - drive ~distance straight; heading drift from the simulated motors' true
               wheel angles must be below ~max_drift_deg or above ~min_drift_deg.
  timeout    - wheel commands stop: the driver zeroes the motors within ~max_stop_delay.
"""
import math
import os
import subprocess
import sys
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32

from mybot_lockstep import participant
from mybot_lockstep.start_paused import finish, start_paused

R = 0.03325
B = 0.117


def wait_until(pred, timeout, what):
    """Waits up to `timeout` s of sim time, period by period under lockstep."""
    if not participant().wait_for(pred, timeout, period=0.01):
        raise AssertionError("timed out after %.1f s of sim time waiting for %s" % (timeout, what))


class Recorder:
    """Every message of a topic with the ROS time it was handled at: under lockstep (drift,
    open_loop) the time of its period, whatever the load."""

    def __init__(self, topic, cls, convert):
        self.samples = []
        participant().Subscriber(topic, cls, lambda m: self.samples.append((rospy.get_time(), convert(m))), queue_size=200)

    def between(self, t0, t1):
        return [v for t, v in self.samples if t0 <= t <= t1]


def mean(xs):
    assert xs, "no samples"
    return sum(xs) / len(xs)


class GoPiGoChain(unittest.TestCase):
    def setUp(self):
        rospy.init_node("drive_check")
        # Under lockstep this node joins at its first sleep, with everything below set up (the
        # launch names it in lockstep_wait_for, so time starts with it and its connections), and
        # from then on its main thread runs period by period: each check acts in the same
        # periods on every run.
        self.ls = participant(defer_join=True)
        if rospy.get_param("~check") == "timeout":
            # The driver's own stamps: this node's callback scheduling on a loaded machine is not
            # part of the driver's stop delay.
            self.stamped = Recorder("gopigo_driver/sim_truth", JointState,
                                    lambda m: (m.header.stamp.to_sec(), tuple(m.effort)))
            self.lp = self.ls.Publisher("lwheel_angular_vel_motor", Float32, queue_size=1)
            self.rp = self.ls.Publisher("rwheel_angular_vel_motor", Float32, queue_size=1)
        self.procs = []
        self.truth = Recorder("gopigo_driver/sim_truth", JointState,
                              lambda m: (tuple(m.position), tuple(m.velocity), tuple(m.effort)))
        self.joints = Recorder("joint_states", JointState, lambda m: tuple(m.velocity))
        self.lmotor = Recorder("lwheel_angular_vel_motor", Float32, lambda m: m.data)
        self.rmotor = Recorder("rwheel_angular_vel_motor", Float32, lambda m: m.data)
        self.cmd = Recorder("cmd_vel", Twist, lambda m: (m.linear.x, m.angular.z))
        self.enc = Recorder("cmd_vel_enc", Twist, lambda m: (m.linear.x, m.angular.z))
        self.ls.hold_next_period()
        # Until a fixed moment, not the first sample: the driver may send one before it takes part,
        # which reaches this node only if its connection was already open (1 soak run in 20 then
        # paused at 0.01 s instead of 0.06 s, and drifted 0.86 deg instead of -0.73).
        wait_until(lambda: self.truth.samples and rospy.get_time() >= 0.2, 30.0, "the driver's sim_truth")

    def tearDown(self):
        # The moves' processes end in wall time (nav_timed lingers after its last twist),
        # after this node stopped holding simulated time.
        self.ls.release()
        for proc, name in self.procs:
            code, out = finish(proc)
            self.assertEqual(code, 0, "%s: %s" % (name, out[-3000:]))

    def run_launch(self, name, *args):
        """roslaunch gopigo_bringup `name`, a straight or turning nav_timed move; returns the sim
        times it started and ended at (its last twist, a zero, out of the mux). Under lockstep the
        simulation is paused, from the period this node holds, until the move's node takes part:
        it joins while time stands, and starts its profile in the period after the pause."""
        t0 = rospy.get_time()
        proc = start_paused(self.ls, ["roslaunch", "gopigo_bringup", name] + list(args), "/" + name.split(".")[0],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.procs.append((proc, name))
        moved = lambda: any(t > t0 and max(abs(x) for x in c) > 1e-6 for t, c in self.cmd.samples)
        done = lambda: moved() and max(abs(x) for x in self.cmd.samples[-1][1]) <= 1e-6
        wait_until(done, 120.0, "%s to move and stop" % name)
        if self.ls.active:
            # Under lockstep it starts in the first period after the pause: its subscriber was
            # connected before time moved on (0.03 s here: two periods through mux and controller).
            first = next(t for t, c in self.cmd.samples if t > t0 and max(abs(x) for x in c) > 1e-6)
            self.assertLess(first - t0, 0.05, "%s started moving %.2f s after the pause" % (name, first - t0))
        return t0, rospy.get_time()

    def moving_window(self, t0, t1):
        """The steady part of a move: 1 s after cmd_vel went non-zero, until it dropped."""
        moving = [t for t, c in self.cmd.samples if t0 <= t <= t1 and max(abs(x) for x in c) > 1e-6]
        self.assertTrue(moving, "no non-zero cmd_vel came out of the twist mux")
        self.assertGreater(moving[-1] - moving[0], 1.5, "move too short for a steady-state window")
        return moving[0] + 1.0, moving[-1] - 0.05

    def check_cmd_vs_enc(self, a, b, index, label):
        tol = rospy.get_param("~tolerance", 0.02)
        want = mean([c[index] for c in self.cmd.between(a, b)])
        got = mean([e[index] for e in self.enc.between(a, b)])
        rospy.loginfo("%s: cmd_vel %.4f, cmd_vel_enc %.4f (%.2f%%)", label, want, got, 100 * (got - want) / want)
        self.assertLess(abs(got - want), tol * abs(want), "%s: cmd_vel %.4f vs cmd_vel_enc %.4f" % (label, want, got))

    def test_chain(self):
        check = rospy.get_param("~check")
        getattr(self, "check_" + check)()

    def check_open_loop(self):
        t0, t1 = self.run_launch("nav_forward.launch", "distance:=0.3", "linear_speed:=0.1")
        a, b = self.moving_window(t0, t1)
        lm, rm = mean(self.lmotor.between(a, b)), mean(self.rmotor.between(a, b))
        rospy.loginfo("forward: motor commands %.3f / %.3f rad/s", lm, rm)
        self.assertGreater(lm, 2.5)
        self.assertAlmostEqual(lm, rm, delta=1e-4)
        lj = mean([v[0] for v in self.joints.between(a, b)])
        rj = mean([v[1] for v in self.joints.between(a, b)])
        self.assertAlmostEqual(lj, rj, delta=0.02 * abs(lj))
        self.check_cmd_vs_enc(a, b, 0, "forward linear.x")

        t0, t1 = self.run_launch("nav_rotate.launch", "angle:=3.0", "angular_speed:=1.0")
        a, b = self.moving_window(t0, t1)
        lm, rm = mean(self.lmotor.between(a, b)), mean(self.rmotor.between(a, b))
        rospy.loginfo("rotate: motor commands %.3f / %.3f rad/s", lm, rm)
        self.assertLess(lm, -1.0)
        self.assertAlmostEqual(lm, -rm, delta=1e-4)
        lj = mean([v[0] for v in self.joints.between(a, b)])
        rj = mean([v[1] for v in self.joints.between(a, b)])
        self.assertAlmostEqual(lj, -rj, delta=0.02 * abs(lj))
        self.check_cmd_vs_enc(a, b, 1, "rotate angular.z")

    def check_drift(self):
        distance = rospy.get_param("~distance", 2.0)
        speed = rospy.get_param("~linear_speed", 0.15)
        p0 = self.truth.samples[-1][1][0]
        t0, t1 = self.run_launch("nav_forward.launch", "distance:=%f" % distance, "linear_speed:=%f" % speed)
        a, b = self.moving_window(t0, t1)
        # Heading at the end of the drive (cmd_vel back to zero, wheels decelerated);
        # what the wheel loop does at standstill is not part of this measurement.
        end = b + 0.05 + rospy.get_param("~settle", 0.4)
        wait_until(lambda: self.truth.samples[-1][0] >= end, 5.0, "the end of the drive")
        p1 = next(v[0] for t, v in self.truth.samples if t >= end)
        dl, dr = p1[0] - p0[0], p1[1] - p0[1]
        travelled = R * (dl + dr) / 2
        heading = math.degrees(R * (dr - dl) / B)
        rospy.loginfo("drift: travelled %.3f m, heading drift %.2f deg", travelled, heading)
        if rospy.has_param("~max_drift_deg"):
            self.assertGreater(travelled, 0.95 * distance)
            self.assertLess(abs(heading), rospy.get_param("~max_drift_deg"))
        if rospy.has_param("~min_drift_deg"):
            self.assertGreater(abs(heading), rospy.get_param("~min_drift_deg"))

    def check_timeout(self):
        max_delay = rospy.get_param("~max_stop_delay", 0.6)
        ls, lp, rp, stamped = self.ls, self.lp, self.rp, self.stamped
        # Under lockstep open since time started (the simulator holds time on a join until every
        # connection between participants is open).
        self.assertTrue(lp.get_num_connections() and rp.get_num_connections(), "the driver did not subscribe")
        end = rospy.get_time() + 1.0
        while rospy.get_time() < end:
            lp.publish(Float32(3.0))
            rp.publish(Float32(3.0))
            last = rospy.get_time()
            ls.sleep(0.05)
        self.assertTrue(any(e[0] != 0 for t, (_, _, e) in self.truth.samples if t > end - 0.5), "motors never driven")
        # Waiting period by period, as a participant: the 2 s are simulated time this node saw.
        self.assertTrue(ls.wait_for(lambda: self.truth.samples[-1][1][2] == (0.0, 0.0), 2.0),
                        "the motor commands did not drop to 0")
        self.assertTrue(ls.wait_for(lambda: stamped.samples and stamped.samples[-1][1][1] == (0.0, 0.0), 2.0),
                        "no stamped stop")
        ls.release()
        stopped = next(stamp for _, (stamp, e) in stamped.samples if stamp > last and e == (0.0, 0.0))
        rospy.loginfo("motors stopped %.3f s after the last command", stopped - last)
        self.assertLess(stopped - last, max_delay)


if __name__ == "__main__":
    rostest.rosrun("gopigo_bringup", "drive_check", GoPiGoChain, sys.argv)
