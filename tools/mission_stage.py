#!/usr/bin/env python3
"""One stage of the demo mission, run as a rospy node against the stage's own
master (the orchestrator, tools/demo.py, starts one per stage):

  mapping:    runs the frontier explorer until the map is complete (or the
              budget is spent), finishes the SLAM trajectory (its final
              optimisation), then saves the map with map_saver;
  navigation: gives AMCL an initial pose, lets it localize, then visits goals.

Both record ground truth (ground_truth/odom, world frame), the estimated pose
(tf map -> base_footprint) and odometry, and write <out>/<name>.json and
<out>/<name>_traj.npz. Everything waits in ROS (sim) time, and, in the simulator's
lockstep, period by period: a stage run twice gives the same figures.
"""
import argparse
import collections
import json
import math
import os
import subprocess
import sys
import threading
import time

import rosgraph
import numpy as np
import rospy
import tf2_ros
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseWithCovarianceStamped, Twist
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from nav_msgs.msg import Odometry, Path
from rosgraph_msgs.msg import Clock
from std_msgs.msg import String
from std_srvs.srv import Trigger

from mybot_gazebo_lite.msg import ModelContacts
from mybot_move_base.action_client import SimpleActionClient
from mybot_move_base.trajectory import sideways_distance
from mybot_common.geometry import wrap, yaw_of
from mybot_lockstep import TransformListener, participant


def log(msg):
    print("[demo]   " + msg, flush=True)


class Recorder:
    """Samples ground truth (converted into the map frame), the tf estimate and
    odometry at a fixed sim-time rate, all three at the ground truth's stamp:
    compared at different instants, a robot driving at 0.5 m/s would show
    errors that are only the sampling lag of a busy machine."""

    def __init__(self, world_to_map, map_frame="map", base_frame="base_footprint", rate=5.0, progress_file=None):
        self.map_frame, self.base_frame = map_frame, base_frame
        # The orchestrator's watchdog reads the sim time from here: a stage is stopped only when
        # sim time stops advancing, never because a busy machine makes it slow.
        self.progress_file, self.progress_written = progress_file, -1e9
        wx, wy, wyaw = world_to_map  # pose of the map frame in the world
        self.T = (wx, wy, wyaw)
        self.gt = None
        self.gts = collections.deque(maxlen=500)  # (stamp, pose in the map frame)
        self.gt_history = []  # (stamp s, x, y, yaw) of every ground-truth message, map frame
        self.lock = threading.Lock()  # subscriber and timer threads
        self.odoms = collections.deque(maxlen=200)  # (stamp, x, y, yaw)
        self.rows = []  # t, gt x y yaw, est x y yaw, odom x y yaw
        self.skipped = collections.Counter()  # samples not taken, by reason
        self.tf_error = ""
        # A lockstep participant (mybot_lockstep): the simulator waits until every ground-truth,
        # odometry, tf and command message of a period is recorded, however fast it may run. It
        # joins once the stage is set up (defer_join; the launch names it in lockstep_wait_for),
        # so time starts with every connection open.
        self.ls = ls = participant(defer_join=True)
        self.tf = tf2_ros.Buffer(rospy.Duration(30))
        TransformListener(self.tf, ls)
        ls.Subscriber("ground_truth/odom", Odometry, self._on_gt, queue_size=50)
        ls.Subscriber("odom", Odometry, self._on_odom, queue_size=50)
        self.max_vy = 0.0  # sideways command: a holonomic robot should use it
        ls.Subscriber("cmd_vel", Twist, self._on_cmd, queue_size=50)
        self.contacts = None  # the simulator's count for the (only) robot
        ls.Subscriber("/gazebo/model_contacts", ModelContacts, self._on_contacts, queue_size=100)
        self.explore_exit = None  # the explorer's exit code, from its last status
        self.stopped = False
        ls.Subscriber("explore/status", String, self._on_explore_status, queue_size=10)
        ls.Timer(1.0 / rate, self._sample)

    def world_to_map(self, x, y, yaw):
        wx, wy, wyaw = self.T
        dx, dy = x - wx, y - wy
        c, s = math.cos(-wyaw), math.sin(-wyaw)
        return c * dx - s * dy, s * dx + c * dy, wrap(yaw - wyaw)

    def _on_gt(self, msg):
        p = msg.pose.pose
        self.gt = self.world_to_map(p.position.x, p.position.y, yaw_of(p.orientation))
        with self.lock:
            self.gts.append((msg.header.stamp, self.gt))
            if not self.stopped:
                self.gt_history.append((msg.header.stamp.to_sec(),) + tuple(self.gt))

    def _on_contacts(self, msg):
        self.contacts = msg

    def _on_explore_status(self, msg):
        if msg.data.startswith("exiting with code "):
            self.explore_exit = int(msg.data.split()[-1])

    def contact_report(self, timeout=30.0):
        """The physics engine's contact count up to the last ground-truth sample."""
        end = self.gt_history[-1][0] if self.gt_history else 0.0
        wait_for(lambda: self.contacts is not None and self.contacts.header.stamp.to_sec() >= end, timeout,
                 "/gazebo/model_contacts")
        c = self.contacts
        return {"contact_steps": int(c.contact_steps), "contact_s": c.contact_time, "max_depth_m": c.max_depth,
                "first_s": c.first_time, "first_model": c.first_model}

    def _on_cmd(self, msg):
        self.max_vy = max(self.max_vy, abs(msg.linear.y))

    def _on_odom(self, msg):
        p = msg.pose.pose
        with self.lock:
            self.odoms.append((msg.header.stamp.to_sec(), p.position.x, p.position.y, yaw_of(p.orientation)))

    def estimate(self, stamp=None):
        try:
            t = self.tf.lookup_transform(self.map_frame, self.base_frame, stamp or rospy.Time(0))
        except tf2_ros.TransformException as e:
            # Kept short (no stamps) so that skip reasons group in the result.
            self.tf_error = type(e).__name__
            return None
        return (t.transform.translation.x, t.transform.translation.y, yaw_of(t.transform.rotation))

    def truth_at(self, stamps):
        """Ground truth (x, y, yaw) at each stamp, interpolated between the two messages around
        it (50 Hz: a turning robot's yaw moves a degree between them); NaN where there are none
        within 50 ms."""
        with self.lock:
            h = np.array(self.gt_history, dtype=float).reshape(-1, 4)
        out = np.full((len(stamps), 3), np.nan)
        if len(h) < 2:
            return out
        hi = np.clip(np.searchsorted(h[:, 0], stamps), 1, len(h) - 1)
        lo = hi - 1
        span = np.maximum(h[hi, 0] - h[lo, 0], 1e-9)
        f = np.clip((stamps - h[lo, 0]) / span, 0.0, 1.0)
        dyaw = np.arctan2(np.sin(h[hi, 3] - h[lo, 3]), np.cos(h[hi, 3] - h[lo, 3]))
        interp = np.column_stack([h[lo, 1] + f * (h[hi, 1] - h[lo, 1]), h[lo, 2] + f * (h[hi, 2] - h[lo, 2]),
                                  np.arctan2(np.sin(h[lo, 3] + f * dyaw), np.cos(h[lo, 3] + f * dyaw))])
        near = (stamps >= h[lo, 0] - 0.05) & (stamps <= h[hi, 0] + 0.05) & (span <= 0.1)
        out[near] = interp[near]
        return out

    def _odom_at(self, t):
        if not self.odoms:
            return (math.nan,) * 3
        with self.lock:
            best = min(self.odoms, key=lambda o: abs(o[0] - t))
        return best[1:] if abs(best[0] - t) < 0.1 else (math.nan,) * 3

    def stop(self):
        """No samples from here on: the figures end where the stage's work did."""
        with self.lock:
            self.stopped = True
            self.stopped_at = rospy.Time.now().to_sec()

    def _sample(self, _):
        # A ground-truth pose a little in the past, when tf and odometry of that
        # instant have surely arrived.
        # rospy.Time cannot go negative, and an exception here would end the timer's thread
        # for good (every later sample lost): the first 0.3 s of sim time are not sampled.
        now = rospy.Time.now()
        if self.progress_file and now.to_sec() - self.progress_written >= 1.0:
            self.progress_written = now.to_sec()
            with open(self.progress_file, "w") as f:
                f.write("%.3f\n" % self.progress_written)
        if self.stopped:
            return
        if now.to_sec() < 0.3:
            self.skipped["no ground truth yet"] += 1
            return
        lag = now - rospy.Duration(0.3)
        with self.lock:
            older = [g for g in self.gts if g[0] <= lag]
        if not older:
            self.skipped["no ground truth yet"] += 1
            return
        stamp, gt = older[-1]
        est = self.estimate(stamp)
        if est is None:  # tf not yet (or no longer) buffered at that stamp
            self.skipped["no tf at the ground truth's stamp: %s" % self.tf_error] += 1
            return
        self.rows.append((stamp.to_sec(),) + tuple(gt) + tuple(est) + tuple(self._odom_at(stamp.to_sec())))

    def array(self):
        return np.array(self.rows, dtype=float).reshape(-1, 10)

    def errors(self, since=None):
        a = self.array()
        if since is not None:
            a = a[a[:, 0] >= since]
        if len(a) == 0:
            return {"samples": 0}
        pos = np.hypot(a[:, 1] - a[:, 4], a[:, 2] - a[:, 5])
        ang = np.abs([wrap(v) for v in a[:, 3] - a[:, 6]])
        return {"samples": int(len(a)), "rms_m": float(np.sqrt(np.mean(pos ** 2))), "max_m": float(pos.max()),
                "rms_deg": float(np.degrees(np.sqrt(np.mean(ang ** 2)))), "final_m": float(pos[-1])}


def wait_for(cond, timeout, what):
    """Waits in wall time (the sim may be paused or not started yet)."""
    deadline = time.monotonic() + timeout
    while not rospy.is_shutdown() and time.monotonic() < deadline:
        if cond():
            return
        time.sleep(0.05)
    raise RuntimeError("timed out after %.0f s waiting for %s" % (timeout, what))


def sim_started():
    try:
        rospy.wait_for_message("/clock", Clock, timeout=1.0)
        return True
    except rospy.ROSException:
        return False


def path_length(a):
    if len(a) < 2:
        return 0.0
    return float(np.sum(np.hypot(np.diff(a[:, 1]), np.diff(a[:, 2]))))


def start_explore(args):
    """The frontier explorer, started with the stage: the simulator's time starts once it takes
    part (lockstep_wait_for), so every run explores from the same first period."""
    cmd = ["rosrun", "mybot_explore", "explore",
           "_time_budget:=%f" % args.budget, "_robot_radius:=%f" % args.robot_radius,
           # Half a metre of frontier is still worth a trip in a building of shelves.
           "_min_frontier_size:=0.5",
           # The factory's racks are 4 x 0.8 m: their unseen insides (3.2 m^2) are no frontier.
           "_min_unknown_area:=4.0",
           # Back to the start before the map is saved: the tour's drift (up to 0.4 m and 3 deg
           # in 50 m when no path crossed itself) is then removed by a loop closure.
           "_return_to_init:=true"]
    if args.boundary:
        cmd.append("_boundary:=[%s]" % ",".join("%.3f" % v for v in args.boundary))
    return subprocess.Popen(cmd, stdout=open(args.out + "/" + args.name + "_explore.log", "w"),
                            stderr=subprocess.STDOUT)


def run_mapping(args, rec, result, explore):
    log("exploring (frontiers on the SLAM map, goals through the move_base action)")
    # Period by period: the explorer's last status arrives in the period after its end on every
    # run, and this thread holds that period while the trajectory is finished and the map saved.
    ended = rec.ls.wait_for(lambda: rec.explore_exit is not None or explore.poll() is not None,
                            2.0 * args.budget + 600.0, period=0.1)
    code = rec.explore_exit if rec.explore_exit is not None else explore.poll()
    if not ended or code is None:
        raise RuntimeError("the explorer did not end within %.0f s of sim time" % (2.0 * args.budget + 600.0))
    rec.stop()
    result["explore_exit"] = code
    result["explore_sim_s"] = rospy.Time.now().to_sec()
    result["explored_completely"] = code == 0
    log("exploration ended (%s) after %.0f s of sim time" %
        ("no frontier left" if code == 0 else "exit %d" % code, result["explore_sim_s"]))
    # As with Cartographer: finish the trajectory (the final optimisation ties every keyframe to
    # every earlier pass through its place) and save the map it publishes.
    rospy.wait_for_service("finish_trajectory", timeout=30)
    finish = rospy.ServiceProxy("finish_trajectory", Trigger)()
    result["finish_trajectory"] = finish.message
    if not finish.success:
        raise RuntimeError("finish_trajectory failed: " + finish.message)
    log("trajectory finished: " + finish.message)
    # The map and the trajectory no longer change: time may move on while they are saved.
    rec.ls.release()
    saver = subprocess.run(["rosrun", "mybot_map_server", "map_saver", "-f", args.map_out],
                           capture_output=True, text=True, timeout=120)
    result["map_saved"] = saver.returncode == 0
    if saver.returncode != 0:
        raise RuntimeError("map_saver failed: " + (saver.stderr or saver.stdout)[-500:])
    log("map saved to %s.yaml / .pgm" % args.map_out)
    save_keyframes(args, rec, result)


def save_keyframes(args, rec, result):
    """The SLAM node's keyframe poses after its last optimisation (what the saved map was
    rendered from) beside the ground truth at the same stamps: the trajectory a SLAM run is
    scored by, while the online estimate shows what the robot believed as it went."""
    try:
        path = rospy.wait_for_message("slam/trajectory", Path, timeout=10.0)
    except rospy.ROSException:
        result["keyframes"] = 0
        log("no slam/trajectory received: the map is scored by the online estimate")
        return
    est = np.array([(p.header.stamp.to_sec(), p.pose.position.x, p.pose.position.y, yaw_of(p.pose.orientation))
                    for p in path.poses], dtype=float).reshape(-1, 4)
    gt = rec.truth_at(est[:, 0])
    ok = np.isfinite(gt).all(axis=1)
    result["keyframes"] = int(ok.sum())
    np.savez(args.out + "/" + args.name + "_keyframes.npz", est=est[ok], gt=np.column_stack([est[ok, 0], gt[ok]]))


def send_initial_pose(pub, x, y, yaw):
    msg = PoseWithCovarianceStamped()
    msg.header.frame_id = "map"
    msg.header.stamp = rospy.Time.now()
    msg.pose.pose.position.x, msg.pose.pose.position.y = x, y
    msg.pose.pose.orientation.z, msg.pose.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    cov = [0.0] * 36
    cov[0] = cov[7] = 0.25 ** 2
    cov[35] = 0.25 ** 2
    msg.pose.covariance = cov
    pub.publish(msg)


def run_navigation(args, rec, result, client, initial_pose):
    """Period by period (this thread sleeps through the lockstep participant): the initial pose,
    each goal and the wait for its result fall in the same periods on every run."""
    ix, iy, iyaw = args.initial_pose
    log("initial pose estimate (%.2f, %.2f, %.0f deg) given to AMCL" % (ix, iy, math.degrees(iyaw)))
    send_initial_pose(initial_pose, ix, iy, iyaw)
    # Goals only once AMCL has taken the estimate: before that, map -> odom is
    # missing (or AMCL's default pose) and move_base would refuse or misplan.
    if not rec.ls.wait_for(lambda: (lambda e: e is not None and math.hypot(e[0] - ix, e[1] - iy) < 1.0)(
            rec.estimate()), 60.0):
        raise RuntimeError("AMCL did not publish map -> odom at the initial pose within 60 s of sim time")
    # Before this, AMCL sat at its default pose: not a localization error to report (nor to draw).
    result["localized_from"] = rospy.Time.now().to_sec()
    if not client.wait_for_server(rospy.Duration(60)):
        raise RuntimeError("no move_base action server")
    goals = []
    for i, (gx, gy, gyaw) in enumerate(args.goals):
        goal = MoveBaseGoal()
        goal.target_pose.header.frame_id = "map"
        goal.target_pose.header.stamp = rospy.Time.now()
        goal.target_pose.pose.position.x, goal.target_pose.pose.position.y = gx, gy
        goal.target_pose.pose.orientation.z = math.sin(gyaw / 2)
        goal.target_pose.pose.orientation.w = math.cos(gyaw / 2)
        t0 = rospy.Time.now()
        client.send_goal(goal)
        done = client.wait_for_result(rospy.Duration(args.goal_timeout))
        state = client.get_state() if done else GoalStatus.ABORTED
        if not done:
            client.cancel_goal()
        gt = rec.gt
        err = math.hypot(gt[0] - gx, gt[1] - gy) if gt else math.nan
        yaw_err = abs(wrap(gt[2] - gyaw)) if gt else math.nan
        est = rec.estimate()
        loc_err = math.hypot(gt[0] - est[0], gt[1] - est[1]) if gt and est else math.nan
        reached = state == GoalStatus.SUCCEEDED and err < args.goal_tolerance
        goals.append({"goal": [gx, gy, gyaw], "reached": bool(reached), "state": int(state),
                      "text": client.get_goal_status_text(), "sim_s": (rospy.Time.now() - t0).to_sec(),
                      "position_error_m": err, "yaw_error_deg": math.degrees(yaw_err),
                      "localization_error_m": loc_err})
        log("goal %d/%d (%.2f, %.2f): %s in %.1f s sim, %.3f m from the goal by ground truth, "
            "localization error %.3f m" % (i + 1, len(args.goals), gx, gy, "reached" if reached else
                                           "NOT reached (%s)" % client.get_goal_status_text(),
                                           goals[-1]["sim_s"], err, loc_err))
    rec.stop()
    result["goals"] = goals
    result["goals_reached"] = sum(g["reached"] for g in goals)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("stage", choices=("mapping", "navigation"))
    ap.add_argument("--name", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--map-origin", type=float, nargs=3, default=[0, 0, 0],
                    help="pose (x y yaw) of the map frame in the world frame")
    ap.add_argument("--map-out", help="mapping: map_saver -f argument")
    ap.add_argument("--budget", type=float, default=900.0, help="mapping: exploration budget, sim s")
    ap.add_argument("--robot-radius", type=float, default=0.25)
    ap.add_argument("--boundary", type=float, nargs=4, help="mapping: explore only inside xmin ymin xmax ymax (map frame)")
    ap.add_argument("--initial-pose", type=float, nargs=3, help="navigation: AMCL initial pose (map frame)")
    ap.add_argument("--goals", type=json.loads, default=[], help="navigation: JSON list of [x, y, yaw]")
    ap.add_argument("--goal-timeout", type=float, default=180.0)
    ap.add_argument("--goal-tolerance", type=float, default=0.3)
    ap.add_argument("--startup-timeout", type=float, default=120.0)
    args = ap.parse_args()

    # rospy reads /use_sim_time once, in init_node: wait until the launch has set it.
    master = rosgraph.Master("/demo_" + args.stage)
    deadline = time.monotonic() + args.startup_timeout
    while time.monotonic() < deadline:
        try:
            if master.hasParam("/use_sim_time"):
                break
        except Exception:  # master not up yet
            pass
        time.sleep(0.1)
    rospy.init_node("demo_" + args.stage, disable_signals=True)
    result = {"stage": args.stage, "name": args.name, "ok": False}
    wall0 = time.monotonic()
    explore = None
    try:
        # Everything this stage takes part in lockstep with is set up before it joins: the
        # launch names it (and the explorer) in the simulator's lockstep_wait_for, so time
        # starts once they are in, with their connections open, and every run starts alike.
        rec = Recorder(args.map_origin, progress_file=os.path.join(args.out, args.name + ".progress"))
        if args.stage == "mapping":
            explore = start_explore(args)
        else:
            client = SimpleActionClient("move_base", MoveBaseAction, ls=rec.ls)
            # Through the participant (synchronous): what it sent is counted exactly at each Ack.
            initial_pose = rec.ls.Publisher("initialpose", PoseWithCovarianceStamped, latch=True)
        # The simulator repeats its first /clock while it waits for the named participants.
        wait_for(sim_started, args.startup_timeout, "/clock from the simulator")
        # Set up: join, and hold the first period time moves to. From here on this thread
        # sleeps through the participant, so what it does falls in the same period on every run.
        rec.ls.hold_next_period()
        if not rec.ls.wait_for(lambda: rec.gt is not None, 10.0):
            raise RuntimeError("no ground_truth/odom within 10 s of sim time")
        if args.stage == "mapping":
            run_mapping(args, rec, result, explore)
            result["ok"] = result["map_saved"]
        else:
            run_navigation(args, rec, result, client, initial_pose)
            result["ok"] = bool(result["goals"]) and result["goals_reached"] == len(result["goals"])
        a = rec.array()
        result["trajectory_error"] = rec.errors(result.get("localized_from"))
        result["distance_m"] = path_length(a)
        result["max_sideways_cmd_mps"] = rec.max_vy
        with rec.lock:
            result["sideways_m"], result["driven_m"] = sideways_distance(list(rec.gt_history))
        result["samples_skipped"] = dict(rec.skipped)
        # Time starts at 0 once the stage has joined; the stage's work ends where its samples do.
        result["sim_s"] = rec.stopped_at if rec.stopped else rospy.Time.now().to_sec()
        np.savez(args.out + "/" + args.name + "_traj.npz", traj=a)
        rec.ls.release()  # the stage's figures are taken: time may move on
        result["contacts"] = rec.contact_report()
    except Exception as e:  # the orchestrator reports the reason
        result["error"] = str(e)
        log("FAILED: %s" % e)
    finally:
        if explore is not None and explore.poll() is None:
            explore.terminate()
    result["wall_s"] = time.monotonic() - wall0
    with open(args.out + "/" + args.name + ".json", "w") as f:
        json.dump(result, f, indent=2)
    return 0 if result["ok"] else 1


if __name__ == "__main__":
    sys.exit(main())
