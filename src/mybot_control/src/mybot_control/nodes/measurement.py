"""The thesis's measurement nodes: goal latch, absolute position, pose error, CPU load/temperature."""
import os

import rospy
import yaml
from geometry_msgs.msg import PointStamped, PoseStamped
from nav_msgs.msg import Odometry
from std_msgs.msg import Float32, Float64

from mybot_common.atomic_file import write_file_atomically
from mybot_control import measurement as meas
from mybot_common import params
from mybot_control.nodes import common


def pose2d(pose):
    q = pose.orientation
    return (pose.position.x, pose.position.y, meas.yaw_from_quaternion(q.x, q.y, q.z, q.w))


class ClampedGoalPose:
    """Republishes the last goal (move_base_simple/goal) on clamped_goal_pose at ~rate."""

    def __init__(self):
        self.rate = common.get("rate", 1.0, params.number, low=0, low_open=True)
        self.restamp = common.get("restamp", True, params.boolean)
        self.goal = None
        self.pub = rospy.Publisher("clamped_goal_pose", PoseStamped, queue_size=1, latch=True)
        rospy.Subscriber("move_base_simple/goal", PoseStamped, self.on_goal, queue_size=1)
        rospy.Timer(rospy.Duration(1.0 / self.rate), self.tick)

    def on_goal(self, msg):
        self.goal = msg
        self.tick(None)

    def tick(self, _):
        if self.goal is None:
            return
        if self.restamp:
            self.goal.header.stamp = rospy.Time.now()
        self.pub.publish(self.goal)


class AbsolutePosition:
    """ground_truth/odom -> robot/position/absolute (PointStamped, ground-truth frame)."""

    def __init__(self):
        self.rate = common.get("rate", 0.0, params.number, low=0)
        self.last = None
        self.pub = rospy.Publisher("robot/position/absolute", PointStamped, queue_size=50)
        rospy.Subscriber("ground_truth/odom", Odometry, self.on_odom, queue_size=50)

    def on_odom(self, msg):
        t = msg.header.stamp.to_sec()
        if self.rate > 0 and self.last is not None and 0 <= t - self.last < 1.0 / self.rate:
            return
        self.last = t
        out = PointStamped()
        out.header = msg.header
        out.point = msg.pose.pose.position
        self.pub.publish(out)


class PoseError:
    """Position and yaw error of odometry (or the tf map pose) against ground truth."""

    def __init__(self):
        self.source = common.get("source", "odom", params.string, choices=("odom", "tf"))
        self.rate = common.get("rate", 10.0, params.number, low=0, low_open=True)
        self.summary_file = common.get("summary_file", "", params.string)
        align = common.get("align_initial", True, params.boolean)
        self.truth = meas.PoseHistory()
        self.estimate = meas.PoseHistory()
        self.tracker = meas.PoseErrorTracker(align_initial=align)
        self.last_t = None
        self.pub_pos = rospy.Publisher("pose_error/position", Float64, queue_size=10)
        self.pub_yaw = rospy.Publisher("pose_error/yaw", Float64, queue_size=10)
        rospy.Subscriber("ground_truth/odom", Odometry, self.on_truth, queue_size=50)
        if self.source == "odom":
            rospy.Subscriber("odom", Odometry, self.on_estimate, queue_size=50)
        else:
            import tf2_ros
            self.frame = common.get("frame_id", "map", params.string)
            self.base = common.get("base_frame", "base_footprint", params.string)
            self.buf = tf2_ros.Buffer()
            self.listener = tf2_ros.TransformListener(self.buf)
        rospy.Timer(rospy.Duration(1.0 / self.rate), self.tick)
        rospy.on_shutdown(self.report)

    def on_truth(self, msg):
        self.truth.add(msg.header.stamp.to_sec(), pose2d(msg.pose.pose))

    def on_estimate(self, msg):
        self.estimate.add(msg.header.stamp.to_sec(), pose2d(msg.pose.pose))

    def tick(self, _):
        if self.source == "tf":
            import tf2_ros
            try:
                tr = self.buf.lookup_transform(self.frame, self.base, rospy.Time(0))
            except (tf2_ros.LookupException, tf2_ros.ExtrapolationException, tf2_ros.ConnectivityException):
                return
            q, p = tr.transform.rotation, tr.transform.translation
            self.estimate.add(tr.header.stamp.to_sec(), (p.x, p.y, meas.yaw_from_quaternion(q.x, q.y, q.z, q.w)))
        if not self.truth.t or not self.estimate.t:
            return
        t = min(self.truth.t[-1], self.estimate.t[-1])
        if self.last_t is not None and t <= self.last_t:
            return
        est, tru = self.estimate.at(t), self.truth.at(t)
        if est is None or tru is None:
            return
        self.last_t = t
        pos, yaw = self.tracker.add(t, est, tru)
        self.pub_pos.publish(Float64(pos))
        self.pub_yaw.publish(Float64(yaw))

    def report(self):
        s = self.tracker.summary()
        rospy.loginfo("pose_error summary (%s vs ground truth): %s", self.source,
                      ", ".join("%s=%.4g" % (k, v) for k, v in s.items()))
        if self.summary_file:
            write_file_atomically(os.path.expanduser(self.summary_file),
                                  yaml.safe_dump({k: float(v) for k, v in s.items()}, sort_keys=False))


class CpuMonitor:
    """cpu_load (%) from /proc/stat and cpu_temperature (deg C) from /sys/class/thermal."""

    def __init__(self):
        self.rate = common.get("rate", 1.0, params.number, low=0, low_open=True)
        proc_root = common.get("proc_root", "/proc", params.string)
        sys_root = common.get("sys_root", "/sys", params.string)
        zone = common.get("thermal_zone", -1, params.number, integer=True, low=-1)
        try:
            self.load = meas.CpuLoad(proc_root)
        except (OSError, ValueError) as e:
            raise params.ParamError("~proc_root", "cannot read CPU times: %s" % e)
        self.temp_path = meas.find_thermal_zone(sys_root, zone)
        if self.temp_path is None:
            rospy.logwarn("cpu_monitor: no thermal zone under %s/class/thermal%s; cpu_temperature is not published",
                          sys_root, "" if zone < 0 else " (thermal_zone%d)" % zone)
        else:
            rospy.loginfo("cpu_monitor: temperature from %s", self.temp_path)
        self.pub_load = rospy.Publisher("cpu_load", Float32, queue_size=10)
        self.pub_temp = rospy.Publisher("cpu_temperature", Float32, queue_size=10)
        rospy.Timer(rospy.Duration(1.0 / self.rate), self.tick)

    def tick(self, _):
        self.pub_load.publish(Float32(self.load.sample()))
        if self.temp_path is not None:
            try:
                self.pub_temp.publish(Float32(meas.read_temperature(self.temp_path)))
            except (OSError, ValueError) as e:
                rospy.logwarn("cpu_monitor: %s unreadable (%s); cpu_temperature is no longer published",
                              self.temp_path, e)
                self.temp_path = None


def _spin(cls):
    def body():
        cls()
        rospy.spin()
        return 0
    return body


def main_clamped_goal_pose():
    common.run("clamped_goal_pose", _spin(ClampedGoalPose))


def main_absolute_position():
    common.run("absolute_position", _spin(AbsolutePosition))


def main_pose_error():
    common.run("pose_error", _spin(PoseError))


def main_cpu_monitor():
    common.run("cpu_monitor", _spin(CpuMonitor))
