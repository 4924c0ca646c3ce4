"""Helpers shared by the diff-drive rostests: publish cmd_vel, follow odom, wait on conditions
(ROS time, so the loopback's accelerated /clock and the simulator both work)."""
import math
import threading

import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from std_srvs.srv import Trigger

from mybot_lockstep import participant, wait_connected
from mybot_common import node_process
from mybot_common.geometry import wrap, yaw_of  # noqa: F401 (the tests import them from here)


class Chain:
    def __init__(self, cmd_topic='cmd_vel', odom_topic='odom'):
        self.lock = threading.Lock()
        self.odom = None
        self.odom_count = 0
        # A lockstep participant under the simulator: sim time waits for this test's commands.
        self.ls = participant(defer_join=True)  # joins at its first sleep, set up (first call only)
        self.pub = self.ls.Publisher(cmd_topic, Twist, queue_size=10)
        self.ls.Subscriber(odom_topic, Odometry, self._on_odom, queue_size=50)
        self._subs = []  # subscribe(): connected before wait_ready / wait_connected return

    def subscribe(self, topic, data_class, callback, **kw):
        """A subscription the test asserts on: through lockstep (every message of a period is
        handed over before the period ends, so what the test reads after a wait is never stale
        under load), and connected before wait_ready() or wait_connected() returns."""
        sub = self.ls.Subscriber(topic, data_class, callback, **kw)
        self._subs.append(sub)
        return sub

    def wait_connected(self, timeout=60.0):
        """Until every subscribe() subscription has a publisher connected (otherwise a loaded
        machine can miss the first messages)."""
        wait_connected(self._subs, timeout)

    def _on_odom(self, msg):
        with self.lock:
            self.odom = msg
            self.odom_count += 1

    def wait_for(self, condition, timeout, what):
        """Wait (ROS time) until condition() is true; fail with `what` on timeout."""
        deadline = rospy.get_time() + timeout
        while not rospy.is_shutdown():
            if condition():
                return
            if rospy.get_time() > deadline:
                raise AssertionError('timed out waiting for ' + what)
            self.ls.sleep(0.01)
        raise AssertionError('shut down while waiting for ' + what)

    def wait_ready(self, subscribed=()):
        """Until odom flows and each topic of `subscribed` has a subscriber: nodelets are loaded
        into their manager one by one, after it has joined lockstep, so time may run before the
        last of them listens."""
        if self.ls.active:  # sim time waits for this test: its start is the same every run
            assert self.ls.wait_for(lambda: self.odom is not None, 60.0), 'no odom received'
            if subscribed:
                topics = [rospy.resolve_name(t) for t in subscribed]
                assert self.ls.wait_for(lambda: node_process.subscribed(topics), 60.0), \
                    'no subscriber on one of %s' % (subscribed,)
            self.wait_connected()
            return
        # Wall-clock bound only for the start-up (clock may not run yet).
        import time
        t0 = time.time()
        while self.odom is None and time.time() - t0 < 60.0 and not rospy.is_shutdown():
            time.sleep(0.05)
        assert self.odom is not None, 'no odom received'
        self.wait_connected()

    def pose(self):
        with self.lock:
            o = self.odom
        p = o.pose.pose
        return p.position.x, p.position.y, yaw_of(p.orientation)

    def speed(self):
        with self.lock:
            t = self.odom.twist.twist
        return t.linear.x, t.angular.z

    def drive(self, vx, wz, duration, rate=20.0):
        """Publish (vx, wz) at `rate` for `duration` s of ROS time, then a zero twist."""
        msg = Twist()
        msg.linear.x = vx
        msg.angular.z = wz
        end = rospy.get_time() + duration
        r = self.ls.Rate(rate)
        while rospy.get_time() < end and not rospy.is_shutdown():
            self.pub.publish(msg)
            r.sleep()
        self.pub.publish(Twist())

    def wait_stopped(self, timeout=5.0):
        """Wait until odom reports standstill for several consecutive messages."""
        count = [0]
        last = [self.odom_count]

        def still():
            if self.odom_count != last[0]:
                last[0] = self.odom_count
                vx, wz = self.speed()
                count[0] = count[0] + 1 if abs(vx) < 1e-4 and abs(wz) < 1e-4 else 0
            return count[0] >= 10
        self.wait_for(still, timeout, 'the robot to stop')

    def reset_odom(self, service='diffdrive_odom/reset_odometry'):
        # Called while holding a period (the robot stands still): the odometry node serves it
        # between periods, and the test goes on from the same period on every run. Releasing
        # the simulation meanwhile let time run for as long as the call took in wall time, so
        # the next drive started at a period that depended on load, and its metres with it.
        rospy.wait_for_service(service, timeout=30.0)
        assert rospy.ServiceProxy(service, Trigger)().success
        n = self.odom_count
        self.wait_for(lambda: self.odom_count > n + 2, 5.0, 'odom after reset')
