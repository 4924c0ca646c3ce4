#!/usr/bin/env python3
"""Simulator-in-the-loop tests of AMCL and move_base, judged on the simulator's ground truth.

~mode:
  navigation  -> every goal in ~goals is reached (ground truth within ~xy_tolerance / ~yaw_tolerance),
                 the robot never touches an obstacle (the simulator's contact count), the path driven is
                 at most ~max_path_ratio x the shortest grid path, AMCL tracks within ~max_rms_xy /
                 ~max_rms_yaw RMS; with ~expect_strafe the robot must have used sideways motion
  errors      -> a goal in an obstacle and a goal outside the map abort with a reason; a goal cancelled
                 mid-way stops the robot
  global      -> after global_localization, AMCL converges within 0.25 m / 0.25 rad in ~max_converge s
  reset       -> reset_simulation mid-goal: goal aborted, no motion, AMCL and topics start over
  kidnap      -> the robot is teleported with set_model_state; AMCL re-localizes within ~max_converge s
The map frame is the world frame: the known map is the world rendered by world_to_map."""
import math
import os
import subprocess
import tempfile
import time
import unittest

import numpy as np
import rospy
import rostest
import tf2_ros
import yaml
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseWithCovarianceStamped, Twist
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from nav_msgs.msg import OccupancyGrid, Odometry
from rosgraph_msgs.msg import Log
from PIL import Image
from std_srvs.srv import Empty

from gazebo_msgs.msg import ModelState
from mybot_gazebo_lite.msg import ModelContacts
from mybot_move_base.action_client import SimpleActionClient
from mybot_move_base.trajectory import sideways_distance
from gazebo_msgs.srv import SetModelState
from mybot_common.geometry import wrap as normalize, yaw_of
from mybot_lockstep import TransformListener, participant

PKG = "mybot_nav_bringup"


def load_map(yaml_path):
    """Occupied mask (row 0 = bottom), resolution and origin of a map_server map."""
    with open(yaml_path) as f:
        meta = yaml.safe_load(f)
    img = np.array(Image.open(os.path.join(os.path.dirname(yaml_path), meta["image"])).convert("L"), dtype=float)
    occ = (255.0 - img) / 255.0 > meta["occupied_thresh"]
    return occ[::-1, :], meta["resolution"], meta["origin"]


class NavSimTest(unittest.TestCase):
    def setUp(self):
        rospy.init_node("nav_sim_test")
        self.mode = rospy.get_param("~mode")
        self.map_file = rospy.get_param("~map_file")
        self.footprint = rospy.get_param("~footprint")
        self.model = rospy.get_param("~model", "mybot")
        self.truth = None
        self.truth_went_back_to = None
        self.truth_speed = 0.0
        self.log = []  # (t, truth x, y, yaw, amcl x, y, yaw or None)
        self.max_vy = 0.0
        # A lockstep participant (mybot_lockstep): every ground-truth sample is logged before
        # simulated time moves on, however busy the machine is. Every mode runs period by period:
        # this node joins once set up (the launch names it in lockstep_wait_for with map_server,
        # AMCL and move_base, so time starts with all of them in), its tf, the move_base action and
        # AMCL's and SLAM's topics come through the participant, and its main thread sleeps through
        # it (a service call it makes while holding a period, such as a teleport or a reset, is
        # answered before that period ends), so what it does falls in the same periods on every run.
        self.ls = ls = participant(defer_join=True)
        self.tf = tf2_ros.Buffer(cache_time=rospy.Duration(900))
        self.listener = TransformListener(self.tf, ls)
        # Every client made now, before time starts: one made later would connect to move_base in
        # a period that depends on load.
        self.clients = ([SimpleActionClient("move_base", MoveBaseAction, ls=ls)
                         for _ in range(2 if self.mode == "errors" else 1)]
                        if self.mode in ("navigation", "errors", "reset") else [])
        ls.Subscriber("ground_truth/odom", Odometry, self.on_truth, queue_size=50)
        ls.Subscriber("cmd_vel", Twist, self.on_cmd, queue_size=50)
        self.contacts = None
        ls.Subscriber("/gazebo/model_contacts", ModelContacts, self.on_contacts, queue_size=100)
        self.cmd = ls.Publisher("cmd_vel", Twist, queue_size=1)
        self.occ, self.res, self.origin = load_map(self.map_file)
        self.slam_map_stamps = []
        self.amcl_poses = []  # (stamp, x, y, yaw) of /amcl_pose
        self.logs = []
        if rospy.get_param("~slam_ns", ""):
            ls.Subscriber(rospy.get_param("~slam_ns") + "/map", OccupancyGrid,
                          lambda m: self.slam_map_stamps.append(m.header.stamp), queue_size=10)
        # /rosout is not counted: roscpp hands log lines to rosout from a thread of its own, in
        # their period or a later one. The reset check reads it after it has acted; kidnap waits
        # on AMCL's "recovery stops" while the robot turns, so a line seen a period late stops the
        # turn one look (0.2 s of sim time) later and moves the last figures a little.
        if rospy.get_param("~slam_ns", "") or self.mode == "kidnap":
            rospy.Subscriber("/rosout", Log, lambda m: self.logs.append(m.msg), queue_size=100)
        if self.mode == "reset":
            ls.Subscriber("amcl_pose", PoseWithCovarianceStamped, self.on_amcl_pose, queue_size=100)

    # ----- helpers ---------------------------------------------------------------------------
    def on_truth(self, msg):
        p = msg.pose.pose
        if self.truth is not None and msg.header.stamp.to_sec() < self.truth[0]:
            self.truth_went_back_to = msg.header.stamp  # the first ground truth after a reset
        self.truth = (msg.header.stamp.to_sec(), p.position.x, p.position.y, yaw_of(p.orientation))
        self.truth_speed = math.hypot(msg.twist.twist.linear.x, msg.twist.twist.linear.y)
        self.log.append(self.truth)

    def on_amcl_pose(self, msg):
        p = msg.pose.pose
        self.amcl_poses.append((msg.header.stamp, p.position.x, p.position.y, yaw_of(p.orientation)))

    def on_contacts(self, msg):
        if msg.model_name == self.model:
            self.contacts = msg

    def on_cmd(self, msg):
        self.max_vy = max(self.max_vy, abs(msg.linear.y))

    def amcl_pose(self, stamp=None):
        """AMCL's belief (tf map -> base_footprint), at a ground-truth stamp or the latest."""
        try:
            t = self.tf.lookup_transform("map", "base_footprint", rospy.Time(0) if stamp is None else rospy.Time(stamp))
        except (tf2_ros.LookupException, tf2_ros.ExtrapolationException, tf2_ros.ConnectivityException):
            return None
        return (t.transform.translation.x, t.transform.translation.y, yaw_of(t.transform.rotation))

    def wait(self, cond, timeout, what):
        # Wall-clock bound: start-up and connections take wall time whatever the sim speed.
        deadline = time.monotonic() + timeout
        while not cond():
            if rospy.is_shutdown() or time.monotonic() > deadline:
                self.fail("timed out (%.0f s wall) waiting for %s" % (timeout, what))
            time.sleep(0.02)

    def wait_for(self, cond, sim_timeout, what):
        """Sleeps through the participant, period by period, until cond() or sim_timeout s of sim
        time: a busy machine makes the wait longer in wall time, never different."""
        if not self.ls.wait_for(cond, sim_timeout):
            self.fail("timed out (%.0f s of sim time) waiting for %s" % (sim_timeout, what))

    def wait_sim(self, seconds):
        self.ls.sleep(seconds)

    def cell_occupied(self, x, y):
        cx = int(math.floor((x - self.origin[0]) / self.res))
        cy = int(math.floor((y - self.origin[1]) / self.res))
        if cx < 0 or cy < 0 or cy >= self.occ.shape[0] or cx >= self.occ.shape[1]:
            return True
        return bool(self.occ[cy, cx])

    def outline(self):
        """The footprint outline sampled every 2 cm, in the robot frame (k x 2)."""
        pts = []
        n = len(self.footprint)
        for i in range(n):
            a, b = np.array(self.footprint[i], float), np.array(self.footprint[(i + 1) % n], float)
            steps = max(1, int(np.hypot(*(b - a)) / 0.02))
            pts.extend(a + (b - a) * k / steps for k in range(steps + 1))
        return np.array(pts)

    def close_passes(self, poses):
        """The ground-truth poses (t, x, y, yaw) at which the footprint outline overlaps an
        occupied cell of the ground-truth map (or leaves the map). The map marks every cell an
        obstacle touches, so this also counts passes up to a cell (5 cm) clear of it."""
        if not poses:
            return []
        p = np.array(poses, float)
        pts = self.outline()
        c, s = np.cos(p[:, 3])[:, None], np.sin(p[:, 3])[:, None]
        wx = p[:, 1][:, None] + c * pts[:, 0] - s * pts[:, 1]
        wy = p[:, 2][:, None] + s * pts[:, 0] + c * pts[:, 1]
        cx = np.floor((wx - self.origin[0]) / self.res).astype(int)
        cy = np.floor((wy - self.origin[1]) / self.res).astype(int)
        h, w = self.occ.shape
        inside = (cx >= 0) & (cy >= 0) & (cx < w) & (cy < h)
        hit = ~inside
        hit[inside] = self.occ[cy[inside], cx[inside]]
        return [tuple(round(v, 3) for v in poses[i]) for i in np.nonzero(hit.any(axis=1))[0]]

    def shortest_grid_path(self, start, goal):
        """8-connected shortest path on the free cells of the map eroded by the inscribed radius."""
        from scipy import ndimage
        from scipy.sparse import coo_matrix
        from scipy.sparse.csgraph import dijkstra
        inscribed = min(math.hypot(*p) for p in self.footprint) * 0.7
        free = ndimage.distance_transform_edt(~self.occ) * self.res > inscribed
        h, w = free.shape
        idx = np.arange(h * w).reshape(h, w)
        ys, xs = np.nonzero(free)
        rows, cols, vals = [], [], []
        for dy, dx, cost in [(0, 1, 1.0), (1, 0, 1.0), (1, 1, math.sqrt(2)), (1, -1, math.sqrt(2))]:
            ny, nx = ys + dy, xs + dx
            ok = (ny >= 0) & (ny < h) & (nx >= 0) & (nx < w)
            ok[ok] &= free[ny[ok], nx[ok]]
            rows.append(idx[ys[ok], xs[ok]])
            cols.append(idx[ny[ok], nx[ok]])
            vals.append(np.full(int(ok.sum()), cost))
        g = coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(h * w, h * w))

        def cell(p):
            return (int((p[1] - self.origin[1]) / self.res) * w + int((p[0] - self.origin[0]) / self.res))
        d = dijkstra(g.tocsr(), directed=False, indices=cell(start))
        return d[cell(goal)] * self.res

    def action_client(self, i=0):
        client = self.clients[i]
        self.assertTrue(client.wait_for_server(rospy.Duration(60)), "move_base action server not up in 60 s of sim time")
        return client

    def goal(self, x, y, yaw):
        g = MoveBaseGoal()
        g.target_pose.header.frame_id = "map"
        g.target_pose.header.stamp = rospy.Time.now()
        g.target_pose.pose.position.x = x
        g.target_pose.pose.position.y = y
        g.target_pose.pose.orientation.z = math.sin(yaw / 2)
        g.target_pose.pose.orientation.w = math.cos(yaw / 2)
        return g

    def wait_ready(self):
        """Joins lockstep: from here on period by period, every wait in sim time."""
        self.ls.hold_next_period()
        self.wait_for(lambda: self.truth is not None, 30.0, "ground truth")
        self.wait_for(lambda: self.amcl_pose() is not None, 30.0, "AMCL's map -> base_footprint transform")

    def localization_error(self):
        """AMCL's error against ground truth at one stamp. The latest tf and the latest truth
        message can be a few tenths of a sim second apart under load, which while turning at
        0.6 rad/s alone reads as a heading error of the order of the 0.25 rad gate."""
        for t in reversed(self.log[-200:]):
            est = self.amcl_pose(t[0])
            if est is not None:
                break
        else:
            est, t = self.amcl_pose(), self.truth
        return math.hypot(est[0] - t[1], est[1] - t[2]), abs(normalize(est[2] - t[3]))

    def set_truth_pose(self, x, y, yaw):
        rospy.wait_for_service("/gazebo/set_model_state", 30)
        srv = rospy.ServiceProxy("/gazebo/set_model_state", SetModelState)
        st = ModelState()
        st.model_name = self.model
        st.pose.position.x, st.pose.position.y = x, y
        st.pose.orientation.z, st.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
        st.reference_frame = "world"
        self.assertTrue(srv(st).success)

    def spin_until(self, done, max_sim, speed=0.6):
        """Turns in place (and nudges AMCL) until done() after each 0.2 s; returns sim time."""
        nomotion = rospy.ServiceProxy("request_nomotion_update", Empty)
        start = rospy.Time.now()
        twist = Twist()
        twist.angular.z = speed
        while (rospy.Time.now() - start).to_sec() < max_sim:
            self.cmd.publish(twist)
            nomotion()
            self.wait_sim(0.2)
            if done():
                break
        self.cmd.publish(Twist())
        return (rospy.Time.now() - start).to_sec()

    def spin_until_localized(self, max_sim, speed=0.6):
        """Turns in place until AMCL has agreed with ground truth for 2 s; returns sim time."""
        good_since = [None]

        def localized():
            dxy, dyaw = self.localization_error()
            if dxy >= 0.25 or dyaw >= 0.25:
                good_since[0] = None
                return False
            good_since[0] = good_since[0] or rospy.Time.now()
            return (rospy.Time.now() - good_since[0]).to_sec() > 2.0

        return self.spin_until(localized, max_sim, speed)

    # ----- tests -------------------------------------------------------------------------------
    def test_nav(self):
        getattr(self, "check_" + self.mode)()

    def random_goals(self, n, seed, clearance):
        """n goals on free cells at least `clearance` from obstacles, headings uniform."""
        from scipy import ndimage
        rng = np.random.default_rng(seed)
        free = ndimage.distance_transform_edt(~self.occ) * self.res > clearance
        # Only the part connected to the robot's start counts as reachable.
        labels, _ = ndimage.label(free)
        sx = int((self.truth[1] - self.origin[0]) / self.res)
        sy = int((self.truth[2] - self.origin[1]) / self.res)
        ys, xs = np.nonzero(labels == labels[sy, sx])
        goals, last = [], (self.truth[1], self.truth[2])
        while len(goals) < n:
            k = rng.integers(len(xs))
            x, y = self.origin[0] + (xs[k] + 0.5) * self.res, self.origin[1] + (ys[k] + 0.5) * self.res
            if math.hypot(x - last[0], y - last[1]) < 2.0:
                continue
            goals.append([round(x, 2), round(y, 2), round(float(rng.uniform(-math.pi, math.pi)), 2)])
            last = (x, y)
        return goals

    def check_navigation(self):
        goals = rospy.get_param("~goals", [])
        # The robot stops anywhere inside the planner's tolerance, judged by AMCL: truth may be off by
        # that tolerance plus the localization error the test allows (twice the RMS bound).
        max_rms_xy = rospy.get_param("~max_rms_xy", 0.05)
        xy_tol = rospy.get_param("~xy_tolerance", rospy.get_param("/move_base/DWAPlannerROS/xy_goal_tolerance", 0.1)
                                 + 2.0 * max_rms_xy)
        # Heading likewise: the planner's yaw tolerance plus twice the heading error the test allows.
        max_rms_yaw = math.radians(rospy.get_param("~max_rms_yaw_deg", 2.0))
        yaw_tol = rospy.get_param("~yaw_tolerance", rospy.get_param("/move_base/DWAPlannerROS/yaw_goal_tolerance", 0.1)
                                  + 2.0 * max_rms_yaw)
        max_ratio = rospy.get_param("~max_path_ratio", 1.25)
        self.wait_ready()
        client = self.action_client()
        if rospy.get_param("~random_goals", 0):
            goals = self.random_goals(rospy.get_param("~random_goals"), rospy.get_param("~seed", 1),
                                      rospy.get_param("~clearance", 0.6))
        for gx, gy, gyaw in goals:
            start = self.truth[1:3]
            shortest = self.shortest_grid_path(start, (gx, gy))
            self.assertTrue(math.isfinite(shortest), "no grid path from (%.2f, %.2f) to goal (%.1f, %.1f): "
                            "start or goal not in the eroded free space" % (start[0], start[1], gx, gy))
            i0 = len(self.log)
            client.send_goal(self.goal(gx, gy, gyaw))
            timeout = rospy.get_param("~goal_timeout", 240.0)
            if not client.wait_for_result(rospy.Duration(timeout)):
                self.fail("timed out (%.0f s of sim time) waiting for goal (%.1f, %.1f)" % (timeout, gx, gy))
            if client.get_state() != GoalStatus.SUCCEEDED:
                t, est = self.truth, self.amcl_pose() or (float("nan"),) * 3
                self.fail("goal (%.1f, %.1f): %s; robot at truth (%.2f, %.2f, %.2f), AMCL (%.2f, %.2f, %.2f)"
                          % ((gx, gy, client.get_goal_status_text()) + tuple(t[1:]) + tuple(est)))
            # Both the pose when the action reported success and 0.5 s later, so a failure tells a
            # planner stopping short from localization error from drift after the stop.
            nan3 = (float("nan"),) * 3
            t0, est0 = self.truth, self.amcl_pose() or nan3
            self.wait_sim(0.5)
            t, est = self.truth, self.amcl_pose() or nan3
            where = ("goal (%.2f, %.2f, %.2f): truth (%.3f, %.3f, %.3f), AMCL (%.3f, %.3f, %.3f); at success "
                     "truth (%.3f, %.3f, %.3f), AMCL (%.3f, %.3f, %.3f)"
                     % ((gx, gy, gyaw) + tuple(t[1:]) + tuple(est) + tuple(t0[1:]) + tuple(est0)))
            rospy.loginfo("reached %s", where)
            self.assertLess(math.hypot(t[1] - gx, t[2] - gy), xy_tol, "position off by more than %.2f m at %s"
                            % (xy_tol, where))
            self.assertLess(abs(normalize(t[3] - gyaw)), yaw_tol, "heading off by more than %.3f rad at %s"
                            % (yaw_tol, where))
            seg = self.log[i0:]
            driven = sum(math.hypot(b[1] - a[1], b[2] - a[2]) for a, b in zip(seg, seg[1:]))
            rospy.loginfo("driven %.2f m, shortest grid path %.2f m (%.2fx)", driven, shortest, driven / shortest)
            self.assertLessEqual(driven, max_ratio * shortest, "path to (%.1f, %.1f): driven %.2f m, more than "
                                 "%.2fx the shortest grid path %.2f m" % (gx, gy, driven, max_ratio, shortest))
        log = list(self.log)  # the mission's samples: what follows runs while time moves on
        self.ls.release()
        self.check_no_contact()
        close = self.close_passes(log)
        rospy.loginfo("footprint within a map cell of an obstacle at %d of %d ground-truth poses %s",
                      len(close), len(log), close[:3])
        sideways, driven = sideways_distance(log)
        rospy.loginfo("driven %.2f m, %.2f m of it sideways (body frame, ground truth)", driven, sideways)
        # Compared at equal stamps (a wall-clock lag would show as error at 5x real time); the
        # first ~settle s let the filter converge from the initial spread.
        settle = log[0][0] + rospy.get_param("~settle", 5.0)
        errs, moving = [], []
        for s, nxt in zip(log[::4], log[1::4]):
            est = self.amcl_pose(s[0]) if s[0] > settle else None
            if est:
                ex, ey = est[0] - s[1], est[1] - s[2]
                errs.append((math.hypot(ex, ey), normalize(est[2] - s[3])))
                # Signed error along the direction of travel: a bias there means the estimate leads or lags.
                step = math.hypot(nxt[1] - s[1], nxt[2] - s[2])
                if step > 1e-4:
                    moving.append((ex * (nxt[1] - s[1]) + ey * (nxt[2] - s[2])) / step)
        rms_xy = math.sqrt(sum(e[0] ** 2 for e in errs) / len(errs))
        rms_yaw = math.sqrt(sum(e[1] ** 2 for e in errs) / len(errs))
        rospy.loginfo("AMCL RMS error %.3f m, %.2f deg over %d samples (largest %.3f m, %.2f deg); mean error along "
                      "the direction of travel %+.3f m over %d moving samples", rms_xy, math.degrees(rms_yaw), len(errs),
                      max(e[0] for e in errs), math.degrees(max(abs(e[1]) for e in errs)),
                      sum(moving) / max(1, len(moving)), len(moving))
        self.assertLess(rms_xy, max_rms_xy)
        self.assertLess(rms_yaw, max_rms_yaw)
        if rospy.get_param("~expect_strafe", False):
            self.assertGreater(self.max_vy, 0.1, "the holonomic robot was never commanded sideways")
            min_sideways = rospy.get_param("~min_sideways_fraction", 0.05)
            self.assertGreater(sideways, min_sideways * driven, "the holonomic robot drove %.2f m of %.2f m "
                               "sideways (less than %.0f %%)" % (sideways, driven, 100 * min_sideways))
        else:
            self.assertLess(sideways, 0.02 * driven, "a diff-drive robot slid %.2f m sideways in %.2f m"
                            % (sideways, driven))

    def check_no_contact(self):
        """Zero contacts with any obstacle, counted by the physics engine at every step."""
        end = self.log[-1][0]
        self.wait(lambda: self.contacts is not None and self.contacts.header.stamp.to_sec() >= end, 60,
                  "/gazebo/model_contacts for '%s' up to t=%.1f" % (self.model, end))
        c = self.contacts
        self.assertEqual(c.contact_steps, 0, "the robot touched '%s' at t=%.2f s: in contact for %.3f s in all, "
                         "%.1f mm deep at most (now touching %s)" % (c.first_model, c.first_time, c.contact_time,
                                                                    1000 * c.max_depth, list(c.touching)))

    def check_errors(self):
        self.wait_ready()
        client = self.action_client()
        for (x, y), what in [(rospy.get_param("~obstacle_goal"), "obstacle"), ((100.0, 100.0), "outside the map")]:
            client.send_goal(self.goal(x, y, 0.0))
            self.wait_for(lambda: client.get_state() not in (GoalStatus.PENDING, GoalStatus.ACTIVE), 10, "abort")
            self.assertEqual(client.get_state(), GoalStatus.ABORTED)
            self.assertIn(what, client.get_goal_status_text())
        gx, gy = rospy.get_param("~far_goal")
        client.send_goal(self.goal(gx, gy, 0.0))
        self.wait_for(lambda: self.truth_speed > 0.15, 30, "the robot to start moving")
        client.cancel_goal()
        self.wait_for(lambda: client.get_state() == GoalStatus.PREEMPTED, 5, "the goal to be preempted")
        stop_start = rospy.Time.now()
        self.wait_for(lambda: self.truth_speed < 0.01, 5, "the robot to stop")
        stopped_in = (rospy.Time.now() - stop_start).to_sec()
        rospy.loginfo("errors: cancelled at %.2f s, the robot stopped %.2f s of sim time later", stop_start.to_sec(),
                      stopped_in)
        self.assertLess(stopped_in, 2.0)
        self.wait_sim(1.0)
        self.assertLess(self.truth_speed, 0.01)
        # A new goal replaces the current one, which ends preempted with SimpleActionServer's words;
        # a goal in the robot's own frame ("0.4 m ahead", as rviz can send it) is placed from where
        # the robot was at the goal's stamp.
        other = self.action_client(1)
        other.send_goal(self.goal(gx, gy, 0.0))
        self.wait_for(lambda: other.get_state() == GoalStatus.ACTIVE, 5, "the far goal to start")
        start = self.truth
        ahead = self.goal(0.4, 0.0, 0.0)
        ahead.target_pose.header.frame_id = "base_footprint"
        client.send_goal(ahead)
        self.wait_for(lambda: other.get_state() == GoalStatus.PREEMPTED, 5, "the far goal to be preempted")
        self.assertIn("another goal", other.get_goal_status_text())
        self.wait_for(lambda: client.get_state() not in (GoalStatus.PENDING, GoalStatus.ACTIVE), 60, "the goal ahead")
        self.assertEqual(client.get_state(), GoalStatus.SUCCEEDED, client.get_goal_status_text())
        # Judged against ground truth: the goal tolerance (0.1 m) plus AMCL's error.
        self.wait_sim(1.0)
        end = self.truth
        ahead_x = start[1] + 0.4 * math.cos(start[3])
        ahead_y = start[2] + 0.4 * math.sin(start[3])
        rospy.loginfo("errors: the goal 0.4 m ahead: stopped at (%.4f, %.4f), the goal was (%.4f, %.4f)",
                      end[1], end[2], ahead_x, ahead_y)
        self.assertLess(math.hypot(end[1] - ahead_x, end[2] - ahead_y), 0.2,
                        "stopped at (%.2f, %.2f), the goal 0.4 m ahead was (%.2f, %.2f)" % (end[1], end[2], ahead_x, ahead_y))

    def check_reset(self):
        """Time going backwards mid-goal (reset_simulation): the goal is aborted saying why, the
        robot stays still, AMCL starts over at its initial pose and the topics flow again."""
        self.wait_ready()
        client = self.action_client()
        gx, gy = rospy.get_param("~far_goal")
        # The goal is sent late enough that the one after the reset is stamped before it (an
        # actionlib server that orders goals by stamp would recall that one).
        self.wait_for(lambda: rospy.Time.now().to_sec() >= 8.0, 10, "8 s of sim time")
        first_goal_at = rospy.Time.now()
        client.send_goal(self.goal(gx, gy, 0.0))
        self.wait_for(lambda: self.truth is not None and math.hypot(self.truth[1], self.truth[2]) > 0.5, 30,
                      "the robot to drive 0.5 m towards the goal")
        # Time goes back by more than a tf buffer's cache_time (10 s): a transform stamped before
        # the reset that reached a buffer after its clear would then make tf2 refuse the frame's
        # new transforms, and move_base lose the robot's pose (mybot_lockstep's time_jump.h).
        self.wait_for(lambda: rospy.Time.now().to_sec() >= 12.0, 10, "12 s of sim time")
        before = rospy.Time.now()
        # Called while this node holds the period: the simulator resets between two periods, and
        # every participant sees time go back at the same boundary (mybot_lockstep's README).
        rospy.wait_for_service("/gazebo/reset_simulation", 30)
        rospy.ServiceProxy("/gazebo/reset_simulation", Empty)()
        self.wait_for(lambda: rospy.Time.now() < before and self.truth_went_back_to is not None, 1,
                      "sim time to go back")
        reset_at = min(self.truth_went_back_to, rospy.Time.now())
        self.wait_for(lambda: client.get_state() == GoalStatus.ABORTED, 5, "the goal to be aborted")
        self.assertIn("time went backwards", client.get_goal_status_text())
        # Ground truth flows again from the spawn pose, and the robot does not move by itself.
        self.wait_for(lambda: self.truth is not None and self.truth[0] >= reset_at.to_sec(), 5, "ground truth after reset")
        self.wait_sim(1.0)
        start = self.truth
        self.wait_sim(2.0)
        end = self.truth
        self.assertGreater(end[0], start[0], "ground truth stopped flowing")
        moved = math.hypot(end[1] - start[1], end[2] - start[2])
        self.assertLess(moved, 0.01, "the robot moved %.3f m after the reset with no goal" % moved)
        self.assertLess(math.hypot(end[1], end[2]), 0.05, "the reset did not bring the robot back to its spawn")
        # AMCL starts over at its initial pose (the spawn pose): its first /amcl_pose stamped after
        # the reset (AMCL may send it before the first ground truth, and a robot at rest gives it no
        # reason to send another).
        self.wait_for(lambda: any(reset_at <= p[0] < before for p in self.amcl_poses), 5, "AMCL's pose after the reset")
        est = next(p[1:] for p in self.amcl_poses if reset_at <= p[0] < before)
        rospy.loginfo("reset: time went back from %.2f s to %.2f s; the goal aborted, the robot at (%.4f, %.4f), "
                      "AMCL at (%.4f, %.4f)", before.to_sec(), reset_at.to_sec(), end[1], end[2], est[0], est[1])
        self.assertLess(math.hypot(est[0] - end[1], est[1] - end[2]), 0.3, "AMCL at %s after the reset" % (est,))
        # SLAM starts a new map and publishes it.
        if rospy.get_param("~slam_ns", ""):
            self.wait_for(lambda: any(reset_at <= t < before for t in self.slam_map_stamps), 10,
                          "a new SLAM map after the reset")
        # And it takes goals again, though stamped before the aborted one.
        self.assertLess(rospy.Time.now(), first_goal_at)
        client.send_goal(self.goal(0.5, 0.0, 0.0))
        self.wait_for(lambda: client.get_state() not in (GoalStatus.PENDING, GoalStatus.ACTIVE), 30, "a goal after reset")
        self.assertEqual(client.get_state(), GoalStatus.SUCCEEDED, client.get_goal_status_text())
        # What SLAM said, read last and in wall time: /rosout is no counted input, and a wait on it
        # in sim time would move the goal above by a period whenever the line came late.
        if rospy.get_param("~slam_ns", ""):
            self.ls.release()
            self.wait(lambda: any("slam: time went backwards" in m and "starting a new map" in m for m in self.logs),
                      30, "SLAM's log line that it starts a new map")

    def check_global(self):
        self.wait_ready()
        rospy.wait_for_service("global_localization", 30)
        rospy.ServiceProxy("global_localization", Empty)()
        took = self.spin_until_localized(rospy.get_param("~max_converge", 20.0) + 2.0)
        dxy, dyaw = self.localization_error()
        est = self.amcl_pose() or (float("nan"),) * 3
        # Where AMCL settled, not only how far off: a lookalike place has its own coordinates.
        rospy.loginfo("global localization: %.1f s sim, error %.3f m %.3f rad "
                      "(AMCL at %.2f, %.2f, %.2f; truth %.2f, %.2f, %.2f)",
                      took, dxy, dyaw, est[0], est[1], est[2], self.truth[1], self.truth[2], self.truth[3])
        self.assertLess(dxy, 0.25)
        self.assertLess(dyaw, 0.25)
        self.assertLess(took, rospy.get_param("~max_converge", 20.0) + 2.0)

    def check_kidnap(self):
        self.wait_ready()
        self.spin_until_localized(10.0)
        x, y, yaw = rospy.get_param("~kidnap_to")
        self.set_truth_pose(x, y, yaw)
        # The teleport is applied at the next period's start.
        self.wait_for(lambda: math.hypot(self.truth[1] - x, self.truth[2] - y) < 0.2, 1,
                      "ground truth at the teleport target")
        self.wait_sim(0.5)
        dxy, _ = self.localization_error()
        self.assertGreater(dxy, 1.0, "teleport did not displace the robot")
        took = self.spin_until_localized(rospy.get_param("~max_converge", 60.0))
        dxy, dyaw = self.localization_error()
        rospy.loginfo("kidnap recovery: %.1f s sim, error %.3f m %.3f rad", took, dxy, dyaw)
        self.assertLess(dxy, 0.25)
        self.assertLess(dyaw, 0.25)
        # AMCL stops adding random particles, and stays where it found the robot.
        took = self.spin_until(lambda: any("recovery stops" in m for m in self.logs), 90.0)
        self.assertTrue(any("recovery stops" in m for m in self.logs), "AMCL still searching after %.0f s" % took)
        dxy, dyaw = self.localization_error()
        rospy.loginfo("kidnap: recovery stopped %.1f s sim later, error %.3f m %.3f rad", took, dxy, dyaw)
        self.assertLess(dxy, 0.25)
        self.assertLess(dyaw, 0.25)


if __name__ == "__main__":
    rostest.rosrun(PKG, "nav_sim_test", NavSimTest)
