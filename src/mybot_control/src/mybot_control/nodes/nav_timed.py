"""nav_timed / twist_publisher: publish a timed twist profile on cmd_vel, then one zero twist.

All timing is ROS time, so it runs unchanged against a simulator at any real-time factor. In a
lockstep simulation it takes part (mybot_lockstep): each twist belongs to the period it was
meant for, however busy the machine is.
"""
import math
import signal

import rospy
from geometry_msgs.msg import Twist

from mybot_common import params
from mybot_common.shutdown import linger
from mybot_lockstep import participant
from mybot_control import timed_moves
from mybot_control.nodes import common


class Node:
    def __init__(self, default_mode):
        g = common.get
        mode = g("mode", default_mode, params.string)
        self.profile = timed_moves.build(
            mode,
            linear_speed=g("linear_speed", 0.1, params.number),
            angular_speed=g("angular_speed", 0.5, params.number),
            distance=g("distance", 0.5, params.number),
            angle=g("angle", math.pi / 2, params.number),
            side=g("side", 0.5, params.number),
            pause=g("pause", 0.5, params.number),
            clockwise=g("clockwise", False, params.boolean),
            linear_x=g("linear_x", 0.2, params.number),
            linear_y=g("linear_y", 0.0, params.number),
            angular_z=g("angular_z", 0.0, params.number),
            duration=g("duration", 0.0, params.number, low=0))
        self.rate = g("rate", 10.0, params.number, low=0, low_open=True)
        self.wait = g("wait_for_subscribers", 5.0, params.number, low=0)
        # Joins from the main thread's first sleep: a node that joins then owes its first period
        # with everything set up, and the simulator holds time on a join until its connections
        # are open (mybot_lockstep's README).
        self.ls = participant(defer_join=True)
        self.pub = self.ls.Publisher("cmd_vel", Twist, queue_size=1)
        self.stop = False

    def publish(self, twist):
        msg = Twist()
        msg.linear.x, msg.linear.y, msg.angular.z = twist
        self.pub.publish(msg)

    def _sleep_until(self, t):
        """Sleeps until ROS time t (rospy.Time), period by period under lockstep."""
        if t <= rospy.get_rostime():
            return
        if self.ls.active:
            self.ls.sleep_until(t)
        else:
            rospy.sleep(t - rospy.get_rostime())

    def run(self):
        if self.ls.active:
            # Joins, and holds the period after the one it joined in: by then the subscribers'
            # connections are open, so the profile starts a fixed number of periods after the
            # node joined (after a pause, the first period once time moves on again).
            self.ls.hold_next_period()
        else:
            # With use_sim_time, time is 0 until the first /clock message.
            while not self.stop and not rospy.is_shutdown() and rospy.get_time() == 0.0:
                rospy.sleep(0.001)  # returns once the clock moves
        start_wait = rospy.get_time()
        while (not self.stop and self.pub.get_num_connections() == 0
               and rospy.get_time() - start_wait < self.wait):
            self.ls.sleep(0.05)  # wakes holding a period: the first twist belongs to one
        t0 = rospy.get_rostime()
        period = 1.0 / self.rate
        current = -1
        try:
            while not self.stop and not rospy.is_shutdown():
                # Time since the start from integer nanoseconds, plus 1 us: a wake-up at a segment
                # boundary counts as at it, whichever way the boundary's float sum rounded. Without
                # it, t could sit a hair before the boundary while the wake-up time t0 + boundary
                # rounds to now, and under lockstep (time frozen while this thread holds the
                # period) the loop would spin without ever sleeping.
                t = (rospy.get_rostime() - t0).to_sec() + 1e-6
                k, twist = timed_moves.command_at(self.profile, t)
                if k is None:
                    break
                if k != current:
                    seg = self.profile[k]
                    rospy.loginfo("nav_timed: %s %s for %.2f s (t=%.2f)", seg.name, seg.twist, seg.duration, t)
                    current = k
                self.publish(twist)
                # next tick on a fixed grid (a late wake-up does not shift later ticks), or the
                # segment boundary if that comes first; both lie more than 1 us after now
                tick = (math.floor(t / period) + 1) * period
                self._sleep_until(t0 + rospy.Duration.from_sec(min(tick, timed_moves.next_boundary(self.profile, t))))
        finally:
            if not rospy.is_shutdown():
                self.publish(timed_moves.ZERO)
                rospy.loginfo("nav_timed: stopped after %.2f s", (rospy.get_rostime() - t0).to_sec())
                self.ls.release()  # the wall-time linger must not hold simulated time
                linger()
        return 0


def _main(name, default_mode):
    def body():
        node = Node(default_mode)

        def on_signal(*_):
            # Stop the robot now: with use_sim_time and a stopped /clock the loop's sleep
            # would never return to do it.
            node.stop = True
            if not rospy.is_shutdown():
                node.publish(timed_moves.ZERO)
                linger()
                rospy.signal_shutdown("interrupted")
        signal.signal(signal.SIGINT, on_signal)
        signal.signal(signal.SIGTERM, on_signal)
        code = node.run()
        rospy.signal_shutdown("done")
        return code
    common.run(name, body, disable_signals=True)


def main():
    _main("nav_timed", "forward")


def main_twist_publisher():
    _main("twist_publisher", "custom")
