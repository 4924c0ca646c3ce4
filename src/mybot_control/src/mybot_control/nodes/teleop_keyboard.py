"""rosrun mybot_control teleop_keyboard: teleop_twist_keyboard behaviour on cmd_vel."""
import os
import select
import signal
import sys
import termios

import rospy
from geometry_msgs.msg import Twist, TwistStamped

from mybot_common import params
from mybot_common.shutdown import linger
from mybot_control import teleop_keyboard as tk
from mybot_control.nodes import common

POLL = 0.02  # s (wall) between stdin polls; the logic below runs on ROS time


def _cbreak(fd):
    """Keys unbuffered, no echo, Ctrl-C as a byte (so we can stop the robot first), output untouched."""
    old = termios.tcgetattr(fd)
    new = termios.tcgetattr(fd)
    new[0] &= ~(termios.ICRNL | termios.IXON)
    new[3] &= ~(termios.ICANON | termios.ECHO | termios.ISIG)
    new[6][termios.VMIN] = 1
    new[6][termios.VTIME] = 0
    termios.tcsetattr(fd, termios.TCSADRAIN, new)
    return old


class Node:
    def __init__(self):
        self.teleop = tk.KeyboardTeleop(
            speed=common.get("speed", 0.5, params.number),
            turn=common.get("turn", 1.0, params.number),
            speed_limit=common.get("speed_limit", 1000.0, params.number, low=0, low_open=True),
            turn_limit=common.get("turn_limit", 1000.0, params.number, low=0, low_open=True))
        self.repeat_rate = common.get("repeat_rate", 0.0, params.number, low=0)
        self.key_timeout = common.get("key_timeout", 0.5, params.number, low=0)
        self.stamped = common.get("stamped", False, params.boolean)
        self.frame_id = common.get("frame_id", "", params.string)
        self.pub = rospy.Publisher("cmd_vel", TwistStamped if self.stamped else Twist, queue_size=1)
        self.stop_requested = False

    def publish(self, values):
        lx, ly, lz, az = values
        msg = TwistStamped() if self.stamped else Twist()
        t = msg.twist if self.stamped else msg
        if self.stamped:
            msg.header.stamp = rospy.Time.now()
            msg.header.frame_id = self.frame_id
        t.linear.x, t.linear.y, t.linear.z, t.angular.z = lx, ly, lz, az
        self.pub.publish(msg)
        self.last_pub = rospy.get_time()

    def read_key(self, fd):
        ready, _, _ = select.select([fd], [], [], POLL)
        if not ready:
            return None
        data = os.read(fd, 1)
        if not data:  # terminal closed: behave like Ctrl-C
            return tk.CTRL_C
        return data.decode("latin-1")

    def wait_for_subscribers(self, fd):
        polls = 0
        while self.pub.get_num_connections() == 0:
            if self.stop_requested or rospy.is_shutdown() or self.read_key(fd) == tk.CTRL_C:
                return False
            polls += 1
            if polls % 125 == 0:
                print("Waiting for subscriber to connect to {}".format(self.pub.resolved_name))
        return True

    def loop(self, fd):
        if not self.wait_for_subscribers(fd):
            return
        self.publish(self.teleop.twist())
        print(tk.MSG)
        print(tk.vels(self.teleop.speed, self.teleop.turn))
        last_key = now = rospy.get_time()
        while not (self.teleop.done or self.stop_requested or rospy.is_shutdown()):
            key = self.read_key(fd)
            before, now = now, rospy.get_time()
            if now < before:  # ROS time jumped back (simulation reset): restart the timers
                self.last_pub = last_key = now
            if key is None and self.key_timeout > 0 and now - last_key >= self.key_timeout:
                key = tk.TIMEOUT
            if key is not None:
                last_key = now
                changed, lines = self.teleop.handle_key(key)
                for line in lines:
                    print(line)
                if changed:
                    self.publish(self.teleop.twist())
            elif self.repeat_rate > 0 and now - self.last_pub >= 1.0 / self.repeat_rate:
                self.publish(self.teleop.twist())

    def request_stop(self, *_):
        self.stop_requested = True

    def main(self):
        fd = sys.stdin.fileno()
        old = _cbreak(fd)
        signal.signal(signal.SIGINT, self.request_stop)
        signal.signal(signal.SIGTERM, self.request_stop)
        try:
            self.loop(fd)
        finally:
            termios.tcsetattr(fd, termios.TCSADRAIN, old)
            if not rospy.is_shutdown():
                self.publish((0.0, 0.0, 0.0, 0.0))
                linger()
                rospy.signal_shutdown("teleop_keyboard finished")
        return 0


def main():
    if not sys.stdin.isatty():
        sys.stderr.write(
            "teleop_keyboard: stdin is not a terminal; run it with `rosrun mybot_control teleop_keyboard` "
            "in a terminal, or from roslaunch with launch-prefix=\"xterm -e\" (see teleop_keyboard.launch)\n")
        sys.exit(1)
    common.run("teleop_keyboard", lambda: Node().main(), disable_signals=True)
