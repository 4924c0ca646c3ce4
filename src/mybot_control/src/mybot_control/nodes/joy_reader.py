"""rosrun mybot_control joy_reader: sensor_msgs/Joy from a Linux joystick (/dev/input/js*).

Parameters follow the ROS joy package: ~dev, ~deadzone, ~autorepeat_rate,
~coalesce_interval, ~sticky_buttons. ~dev may also be a FIFO or a file of
recorded js_event bytes (replayed once; grouping uses the recorded timestamps).
"""
import errno
import fcntl
import os
import select
import stat
import sys

import rospy
from sensor_msgs.msg import Joy

from mybot_common import params
from mybot_control import joy
from mybot_control.nodes import common

POLL = 0.02  # s (wall) between device polls; timing logic runs on ROS time
JSIOCGAXES = 0x80016a11
JSIOCGBUTTONS = 0x80016a12


def _ioctl_count(fd, request):
    try:
        buf = fcntl.ioctl(fd, request, b"\0")
        return buf[0]
    except OSError:
        return 0


class Node:
    def __init__(self):
        self.dev = common.get("dev", "/dev/input/js0", params.string)
        deadzone = common.get("deadzone", 0.05, params.number)
        try:
            joy.check_deadzone(deadzone)
        except ValueError as e:
            raise params.ParamError("~deadzone", str(e))
        self.deadzone = deadzone
        self.autorepeat_rate = common.get("autorepeat_rate", 0.0, params.number, low=0)
        self.coalesce_ms = 1000.0 * common.get("coalesce_interval", 0.001, params.number, low=0)
        self.sticky = common.get("sticky_buttons", False, params.boolean)
        self.pub = rospy.Publisher("joy", Joy, queue_size=10)
        self.state = None
        self.last_pub = None

    def open(self):
        """Open ~dev; returns (fd, kind) with kind 'device', 'fifo' or 'file'."""
        st = os.stat(self.dev)
        if stat.S_ISFIFO(st.st_mode):
            # O_RDWR keeps a writer end open ourselves, so a replaying writer that
            # closes does not look like an unplugged device.
            return os.open(self.dev, os.O_RDWR | os.O_NONBLOCK), "fifo"
        if stat.S_ISREG(st.st_mode):
            return os.open(self.dev, os.O_RDONLY), "file"
        return os.open(self.dev, os.O_RDONLY | os.O_NONBLOCK), "device"

    def publish(self):
        msg = Joy()
        msg.header.stamp = rospy.Time.now()
        msg.header.frame_id = self.dev
        msg.axes = list(self.state.axes)
        msg.buttons = list(self.state.buttons)
        self.pub.publish(msg)
        self.last_pub = rospy.get_time()

    def pump(self, fd, pending):
        """Read what is available; publish coalesced groups. Returns (pending bytes, eof)."""
        try:
            data = os.read(fd, 64 * joy.EVENT_SIZE)
        except BlockingIOError:
            return pending, False
        if not data:
            return pending, True
        events, pending = joy.decode_events(pending + data)
        for group in joy.coalesce(events, self.coalesce_ms):
            changed = False
            for ev in group:
                changed |= self.state.apply(ev)
            if changed or self.last_pub is None:
                self.publish()
        return pending, False

    def run(self):
        try:
            fd, kind = self.open()
        except FileNotFoundError:
            rospy.logerr("joy_reader: joystick device ~dev=%s does not exist (is the joystick plugged in? "
                         "`ls /dev/input/js*` lists joysticks)", self.dev)
            return 1
        except PermissionError:
            rospy.logerr("joy_reader: no permission to read ~dev=%s (add yourself to the 'input' group)", self.dev)
            return 1
        n_axes = _ioctl_count(fd, JSIOCGAXES) if kind == "device" else 0
        n_buttons = _ioctl_count(fd, JSIOCGBUTTONS) if kind == "device" else 0
        self.state = joy.JoystickState(self.deadzone, n_axes, n_buttons, self.sticky)
        rospy.loginfo("joy_reader: reading %s (%s, %d axes, %d buttons)", self.dev, kind, n_axes, n_buttons)
        pending = b""
        while not rospy.is_shutdown():
            if fd is not None:
                ready, _, _ = select.select([fd], [], [], POLL)
                if ready:
                    try:
                        pending, eof = self.pump(fd, pending)
                    except OSError as e:
                        if e.errno not in (errno.ENODEV, errno.EIO):
                            raise
                        eof = True
                    if eof:
                        os.close(fd)
                        fd = None
                        if kind == "file":
                            rospy.loginfo("joy_reader: end of recorded events in %s", self.dev)
                        else:
                            # Like an unplugged joystick: release everything so teleop stops the robot.
                            rospy.logwarn("joy_reader: %s disconnected", self.dev)
                            self.state.release_all()
                            self.publish()
                            return 1
            else:
                rospy.sleep(POLL)
            if (self.autorepeat_rate > 0 and self.last_pub is not None
                    and rospy.get_time() - self.last_pub >= 1.0 / self.autorepeat_rate):
                self.publish()
        return 0


def main():
    common.run("joy_reader", lambda: Node().run())
