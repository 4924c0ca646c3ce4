"""web_controller node: ROS side of the web page (thin: topics, tf, action <-> the pure parts).

Threads: tornado's IOLoop runs in the main thread and calls the backend; rospy callbacks and
the dead-man timer run in rospy's threads. Shared state is guarded by self._lock; commands and
the zeroing twist are published under it so a stale command can never overtake a stop.
"""
import logging
import math
import os
import socket
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import rospkg
import rospy
import tf2_ros
import tornado.ioloop
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import Twist
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from nav_msgs.msg import OccupancyGrid, Path
from sensor_msgs.msg import LaserScan
from std_msgs.msg import Bool, Float32, Float64

from mybot_move_base.action_client import SimpleActionClient

from . import config as web_config
from . import hosts, views
from .auth import ConfigError, resolve_token
from .control import DriveArbiter, scale_command
from .server import WebServer

NUMBER_TYPES = {"std_msgs/Float64": Float64, "std_msgs/Float32": Float32}
GOAL_STATES = {getattr(GoalStatus, n): n for n in dir(GoalStatus) if n.isupper() and
               isinstance(getattr(GoalStatus, n), int)}
CPU_PERIOD = 1.0  # s between CPU samples (a machine measurement: wall clock is right here)
STALE_AFTER = 5.0  # s (wall) after which a robot-side reading is no longer shown


class NumberTopic:
    """Latest value of a std_msgs/Float64 or Float32 topic (whichever the publisher uses)."""

    def __init__(self, topic):
        self.topic = topic
        self.value = None
        self.stamp = None  # time.monotonic() of the last message
        self._warned = False
        self.sub = rospy.Subscriber(topic, rospy.AnyMsg, self._cb, queue_size=1)

    def _cb(self, raw):
        kind = raw._connection_header.get("type")
        cls = NUMBER_TYPES.get(kind)
        if cls is None:
            if not self._warned:
                rospy.logerr("%s has type %s; expected std_msgs/Float64 or Float32",
                             rospy.resolve_name(self.topic), kind)
                self._warned = True
            return
        v = cls().deserialize(raw._buff).data
        self.value = round(v, 3) if math.isfinite(v) else None
        self.stamp = time.monotonic()

    def fresh(self):
        """The value, or None when nothing arrived for STALE_AFTER s (publisher gone)."""
        if self.stamp is None or time.monotonic() - self.stamp > STALE_AFTER:
            return None
        return self.value


def _pose2d(transform):
    t, q = transform.transform.translation, transform.transform.rotation
    return t.x, t.y, views.yaw_from_quaternion(q.x, q.y, q.z, q.w)


class RosBackend:
    def __init__(self, cfg):
        self.cfg = cfg
        self._lock = threading.Lock()
        self.arbiter = DriveArbiter(cfg.deadman_timeout)
        self.mode = cfg.initial_mode
        self.cmd_pub = rospy.Publisher("cmd_vel_web", Twist, queue_size=1)
        self.lock_pub = rospy.Publisher("nav_lock", Bool, queue_size=1, latch=True)
        self.tf = tf2_ros.Buffer(cache_time=rospy.Duration(10.0))
        self.tf_listener = tf2_ros.TransformListener(self.tf)
        self.frame = None  # frame the views are drawn in: global_frame, else odom_frame
        self.trail = views.Trail()
        self._map = None
        self._map_version = 0
        self._scan = []
        self._path = []
        self._goal = None
        self._cpu = views.CpuMeter()
        self._cpu_value = None
        self._cpu_stamp = None
        self.battery = NumberTopic("battery_voltage")
        # mybot_control's cpu_monitor on the robot; else this machine's own load.
        self.robot_cpu = NumberTopic("cpu_load")
        self.modules = [(m, NumberTopic(cfg.swerve_angle_topic.format(module=m)),
                         NumberTopic(cfg.swerve_speed_topic.format(module=m)))
                        for m in cfg.swerve_modules]
        self.subs = [
            # Raw: the cells go to the page as bytes (see views.parse_occupancy_grid).
            rospy.Subscriber("map", rospy.AnyMsg, self._on_map, queue_size=1),
            rospy.Subscriber("scan", LaserScan, self._on_scan, queue_size=1),
            rospy.Subscriber("plan", Path, self._on_plan, queue_size=1),
        ]
        self.move_base = SimpleActionClient(cfg.move_base_action, MoveBaseAction)
        # Goals go out on a worker: waiting for the action server must not stall the page.
        self._goal_worker = ThreadPoolExecutor(max_workers=1)
        self._publish_lock()
        self._lock_period = 1.0 / cfg.lock_rate
        self._last_lock_pub = rospy.get_rostime()
        self._robot_pose = None
        # Checked often so the stop comes close to the timeout, not a period later.
        self.timer = rospy.Timer(rospy.Duration(min(0.02, cfg.deadman_timeout / 5.0)), self._tick)
        # The pose (and trail) is tracked with or without a page open, so the trail has history.
        self.pose_timer = rospy.Timer(rospy.Duration(1.0 / cfg.view_rate), self._update_pose)

    # -- dead man and mode lock (rospy timer thread, ROS time) --
    def _tick(self, _event):
        now = rospy.get_rostime()
        with self._lock:
            if self.arbiter.check(now.to_sec()):
                rospy.logwarn("web drive commands stopped arriving for %.2f s: stopping",
                              self.cfg.deadman_timeout)
                self.cmd_pub.publish(Twist())
            if now < self._last_lock_pub or (now - self._last_lock_pub).to_sec() >= self._lock_period:
                self._publish_lock()
                self._last_lock_pub = now

    def _publish_lock(self):
        # Manual: navigation's mux input is locked out; the web and teleop inputs are above
        # the lock's priority and keep working in both modes.
        self.lock_pub.publish(Bool(data=self.mode == "manual"))

    # -- backend interface (IOLoop thread) --
    def info(self):
        c = self.cfg
        return {"holonomic": c.holonomic, "scale_linear": c.scale_linear,
                "scale_angular": c.scale_angular, "deadman_timeout": c.deadman_timeout,
                "send_period": min(0.05, c.deadman_timeout / 3.0), "mode": self.mode,
                "modules": list(c.swerve_modules), "trail": self.trail.flat(),
                "trail_frame": self.trail.frame}

    def drive(self, client, msg):
        vx, vy, wz = scale_command(msg, self.cfg.scale_linear, self.cfg.scale_angular,
                                   self.cfg.holonomic)
        with self._lock:
            refused = self.arbiter.command(client, rospy.get_rostime().to_sec())
            if refused:
                return refused
            t = Twist()
            t.linear.x, t.linear.y, t.angular.z = vx, vy, wz
            self.cmd_pub.publish(t)
        return None

    def release(self, client):
        with self._lock:
            if self.arbiter.release(client):
                self.cmd_pub.publish(Twist())

    def set_mode(self, mode):
        with self._lock:
            self.mode = mode
            self._publish_lock()
            self._last_lock_pub = rospy.get_rostime()

    def send_goal(self, g):
        frame = self.frame
        if frame is None:
            return "goal refused: the robot's pose is unknown (no tf %s or %s -> %s)" % (
                self.cfg.global_frame, self.cfg.odom_frame, self.cfg.base_frame)
        goal = MoveBaseGoal()
        goal.target_pose.header.frame_id = frame
        goal.target_pose.header.stamp = rospy.get_rostime()
        goal.target_pose.pose.position.x = g.x
        goal.target_pose.pose.position.y = g.y
        goal.target_pose.pose.orientation.z = math.sin(g.yaw / 2.0)
        goal.target_pose.pose.orientation.w = math.cos(g.yaw / 2.0)
        # A goal means "go there": hand the wheels to navigation.
        self.set_mode("autonomous")
        with self._lock:
            self._goal = {"x": round(g.x, 3), "y": round(g.y, 3), "yaw": round(g.yaw, 3),
                          "frame": frame, "status": "SENDING"}
        self._goal_worker.submit(self._send_goal_blocking, goal)
        return None

    def _send_goal_blocking(self, goal):
        if not self.move_base.wait_for_server(rospy.Duration(2.0)):
            self._set_goal_status("NO ACTION SERVER (%s)" % rospy.resolve_name(self.cfg.move_base_action))
            return
        # Before send_goal: a fast server's ACTIVE can arrive before send_goal returns.
        self._set_goal_status("PENDING")
        self.move_base.send_goal(goal, done_cb=self._goal_done,
                                 active_cb=lambda: self._set_goal_status("ACTIVE"))

    def _goal_done(self, state, _result):
        self._set_goal_status(GOAL_STATES.get(state, str(state)))

    def _set_goal_status(self, status):
        with self._lock:
            if self._goal is not None:
                self._goal = dict(self._goal, status=status)

    def cancel_goal(self):
        # All goals, not just ours: "cancel" on the page means navigation stops.
        self._goal_worker.submit(self.move_base.cancel_all_goals)
        self._set_goal_status("CANCELLING")

    def map_message(self):
        with self._lock:
            return None if self._map is None else (self._map_version, self._map)

    def state(self):
        pose = self._robot_pose
        now = rospy.get_rostime()
        if self._cpu_stamp is None or time.monotonic() - self._cpu_stamp >= CPU_PERIOD:
            self._cpu_stamp = time.monotonic()
            value = self._cpu.sample()
            if value is not None:
                self._cpu_value = value
        robot_cpu = self.robot_cpu.fresh()
        with self._lock:
            return {
                "time": round(now.to_sec(), 3),
                "frame": self.frame,
                "pose": [round(v, 3) for v in pose] if pose else None,
                "scan": self._scan,
                "path": self._path,
                "goal": self._goal,
                "mode": self.mode,
                "driver": self.arbiter.owner,
                "battery": self.battery.fresh(),
                "cpu": robot_cpu if robot_cpu is not None else self._cpu_value,
                "cpu_source": "robot" if robot_cpu is not None else "web host",
                "modules": [{"name": m, "angle": a.fresh(), "speed": s.fresh()}
                            for m, a, s in self.modules],
            }

    # -- ROS inputs --
    def _update_pose(self, _event):
        self._robot_pose = self._lookup_pose()

    def _lookup_pose(self):
        for frame in (self.cfg.global_frame, self.cfg.odom_frame):
            try:
                tr = self.tf.lookup_transform(frame, self.cfg.base_frame, rospy.Time(0))
            except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
                    tf2_ros.ExtrapolationException):
                continue
            pose = _pose2d(tr)
            with self._lock:
                self.frame = frame
                self.trail.add(frame, pose[0], pose[1])
            return pose
        with self._lock:
            self.frame = None
        return None

    def _on_map(self, raw):
        kind = raw._connection_header.get("type")
        try:
            if kind != OccupancyGrid._type:
                raise ValueError("type %s; expected %s" % (kind, OccupancyGrid._type))
            grid = views.parse_occupancy_grid(raw._buff)
        except ValueError as e:
            rospy.logerr_throttle(10.0, "%s: %s" % (rospy.resolve_name("map"), e))
            return
        o = grid.origin  # x y z qx qy qz qw
        payload = {
            "type": "map", "frame": grid.frame_id, "width": grid.width, "height": grid.height,
            "resolution": grid.resolution,
            "origin": [o[0], o[1], views.yaw_from_quaternion(o[3], o[4], o[5], o[6])],
            "data": views.encode_grid(grid.data),
        }
        with self._lock:
            self._map_version += 1
            self._map = payload

    def _on_scan(self, msg):
        frame = self.frame
        if frame is None:
            return
        try:
            tr = self.tf.lookup_transform(frame, msg.header.frame_id, msg.header.stamp)
        except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
                tf2_ros.ExtrapolationException):
            try:
                tr = self.tf.lookup_transform(frame, msg.header.frame_id, rospy.Time(0))
            except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
                    tf2_ros.ExtrapolationException):
                return
        points = views.scan_points(msg.ranges, msg.angle_min, msg.angle_increment,
                                   msg.range_min, msg.range_max, _pose2d(tr),
                                   self.cfg.max_scan_points)
        with self._lock:
            self._scan = points

    def _on_plan(self, msg):
        frame = self.frame
        pts = [(p.pose.position.x, p.pose.position.y) for p in msg.poses]
        if frame and msg.header.frame_id and msg.header.frame_id.lstrip("/") != frame and pts:
            try:
                tr = self.tf.lookup_transform(frame, msg.header.frame_id, rospy.Time(0))
            except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
                    tf2_ros.ExtrapolationException):
                return
            pose = _pose2d(tr)
            pts = [views.compose(pose, p) for p in pts]
        with self._lock:
            self._path = views.decimate_path(pts, self.cfg.max_path_points)

    def shutdown(self):
        self.timer.shutdown()
        self.pose_timer.shutdown()
        with self._lock:
            if self.arbiter.owner is not None:
                self.arbiter.release(self.arbiter.owner)
                try:
                    self.cmd_pub.publish(Twist())
                except rospy.ROSException:
                    pass  # already closed by rospy; the mux's timeout stops the robot
        self._goal_worker.shutdown(wait=False)


def main(argv=None):
    rospy.init_node("web_controller")
    try:
        cfg = web_config.load(lambda name, default: rospy.get_param("~" + name, default))
        token, generated = resolve_token(cfg.host, cfg.token)
    except ConfigError as e:
        rospy.logfatal("web_controller: %s", e)
        return 1
    www = os.path.join(rospkg.RosPack().get_path("mybot_web"), "www")
    backend = RosBackend(cfg)
    loop = tornado.ioloop.IOLoop.current()
    # Only asked when used: getfqdn() may wait for DNS.
    machine = (socket.gethostname(), socket.getfqdn()) if hosts.is_wildcard(cfg.host) else ()
    allowed = hosts.allowed_names(cfg.host, cfg.allowed_hosts, machine)
    server = WebServer(backend, www, token=token, view_rate=cfg.view_rate,
                       log=logging.getLogger("rosout"), allowed_hosts=allowed)
    try:
        port = server.listen(cfg.host, cfg.port)
    except OSError as e:
        rospy.logfatal("web_controller: cannot listen on ~host %s, ~port %d: %s",
                       cfg.host, cfg.port, e)
        backend.shutdown()
        return 1
    host = cfg.host
    if host in ("0.0.0.0", "::"):
        host = socket.gethostname()  # all interfaces: show a name others can reach
    host = "[%s]" % host if ":" in host else host
    url = "http://%s:%d/" % (host, port)
    rospy.set_param("~url", url)
    rospy.loginfo("web_controller: answering Host %s and addresses (~allowed_hosts adds names)",
                  ", ".join(sorted(allowed)))
    if token is None:
        rospy.loginfo("web_controller: open %s", url)
    else:
        rospy.loginfo("web_controller: open %s?token=%s%s", url, token,
                      " (generated token; set ~token to choose one)" if generated else "")
    # Stop the robot first (while rospy can still publish), then the server.
    rospy.on_shutdown(backend.shutdown)
    rospy.on_shutdown(lambda: loop.add_callback(loop.stop))
    if rospy.is_shutdown():
        return 0
    loop.start()
    server.stop()
    return 0


if __name__ == "__main__":
    sys.exit(main())
