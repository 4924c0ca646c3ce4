#!/usr/bin/env python3
"""The main job, headless and faster than real time.

For each robot (mybot, then the swerve robot):
  1. mapping: the robot is spawned in the world; the frontier explorer drives
     it through the move_base action while SLAM maps; the map is saved with
     map_saver;
  2. navigation: a fresh simulator spawns it at a different pose; map_server +
     AMCL + navigation run on the saved map; it localizes and visits goals.
Then a report (map precision/recall vs the world's ground truth, trajectory
and localization errors, goals, collisions, sim and wall time) and pictures
are written to the output folder. Exit status 0 only if the mission succeeded.
Each stage runs against its own private ROS master on a free port.
"""
import argparse
import json
import math
import os
import shutil
import socket
import subprocess
import sys
import time

import numpy as np

WS = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOOLS = os.path.join(WS, "tools")
ROBOTS = ("mybot", "swerve")

# Per world: where mapping starts, where navigation starts (a different pose).
WORLDS = {
    "factory": {"file": "factory.world", "map_start": (0.0, 0.0, 0.0), "nav_start": (-8.5, 3.0, -1.5708)},
    "mybot": {"file": "mybot.world", "map_start": (0.0, 0.0, 0.0), "nav_start": (1.0, 1.0, 1.5708)},
}
ROBOT_RADIUS = {"mybot": 0.25, "swerve": 0.33}


def log(msg):
    print("[demo] " + msg, flush=True)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Stage:
    """A roslaunch (with its own master) plus the stage runner against it."""

    def __init__(self, name, launch_file, launch_args, out_dir):
        self.name, self.out = name, out_dir
        port = free_port()
        self.env = dict(os.environ, ROS_MASTER_URI="http://127.0.0.1:%d" % port, ROS_IP="127.0.0.1")
        self.env.pop("ROS_HOSTNAME", None)
        self.env["ROS_LOG_DIR"] = os.path.join(out_dir, "logs", name)
        self.logfile = open(os.path.join(out_dir, "logs", name + "_launch.log"), "w")
        self.proc = subprocess.Popen(["roslaunch", "-p", str(port), "--screen",
                                      launch_file] + ["%s:=%s" % kv for kv in launch_args.items()],
                                     env=self.env, stdout=self.logfile, stderr=subprocess.STDOUT,
                                     start_new_session=True)

    def run(self, *runner_args, stall_timeout, timeout=0.0):
        """Runs the stage to its end. Its length is bounded in sim time (the exploration
        budget, the goal timeouts), so a busy machine only makes it slower; it is stopped
        when sim time has not advanced for stall_timeout s of wall time (a hang), or after
        timeout s of wall time if one is set."""
        cmd = [sys.executable, os.path.join(TOOLS, "mission_stage.py")] + list(runner_args) + \
              ["--name", self.name, "--out", self.out]
        progress = os.path.join(self.out, self.name + ".progress")
        if os.path.exists(progress):
            os.remove(progress)
        proc = subprocess.Popen(cmd, env=self.env)
        start = last_change = time.monotonic()
        sim = None
        while proc.poll() is None:
            time.sleep(1.0)
            now = time.monotonic()
            try:
                with open(progress) as f:
                    t = float(f.read())
            except (OSError, ValueError):
                t = sim
            if t != sim:
                sim, last_change = t, now
            why = None
            if now - last_change > stall_timeout:
                why = "sim time has not advanced for %.0f s of wall time (%s)" % (
                    stall_timeout, "stuck at %.1f s" % sim if sim is not None else "the stage never started recording")
            elif timeout > 0 and now - start > timeout:
                why = "stage timed out after %.0f s of wall time (--stage-timeout)" % timeout
            if why:
                log("%s: %s; stopping it" % (self.name, why))
                proc.send_signal(2)
                try:
                    proc.wait(timeout=20)
                except subprocess.TimeoutExpired:
                    proc.kill()
                    proc.wait()
                break
        rc = proc.returncode
        if self.proc.poll() is not None:
            log("%s: roslaunch exited early with %s; see %s" % (self.name, self.proc.returncode, self.logfile.name))
        return rc

    def close(self):
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, 2)
            try:
                self.proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, 9)
        self.logfile.close()


class Roslaunch:
    """roslaunch with its own roscore on a free port, stopped on exit."""

    def __init__(self, pkg, launch_file, *args, logdir):
        self.port = free_port()
        self.env = dict(os.environ, ROS_MASTER_URI="http://127.0.0.1:%d" % self.port, ROS_IP="127.0.0.1")
        self.env.pop("ROS_HOSTNAME", None)
        os.makedirs(logdir, exist_ok=True)
        self.logfile = open(os.path.join(logdir, "%s_%d.log" % (os.path.splitext(launch_file)[0], self.port)), "w")
        self.proc = subprocess.Popen(["roslaunch", "-p", str(self.port), pkg, launch_file] + list(args),
                                     env=self.env, stdout=self.logfile, stderr=subprocess.STDOUT)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.proc.terminate()
        try:
            self.proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            self.proc.kill()
        self.logfile.close()


def robot_frames(model, out_dir, timeout):
    """Expands a robot, publishes its tf tree headless and returns its frames."""
    with Roslaunch("mybot_description", "display.launch", "model:=" + model, "rviz:=false",
                   logdir=os.path.join(out_dir, "logs")) as rl:
        probe = subprocess.run([sys.executable, "-c", TF_PROBE, str(timeout)], env=rl.env,
                               capture_output=True, text=True, timeout=timeout + 30)
        if probe.returncode != 0:
            raise RuntimeError("%s: %s" % (model, probe.stderr.strip().splitlines()[-1:] or "tf probe failed"))
        return probe.stdout.strip().splitlines()


# Runs in a child process so each robot gets a fresh rospy node on its own master.
TF_PROBE = r'''
import sys, time, xml.etree.ElementTree as ET
import rospy, tf2_ros
timeout = float(sys.argv[1])
deadline = time.monotonic() + timeout
while True:
    try:
        rospy.get_master().getPid()
        if rospy.has_param("robot_description"):
            break
    except Exception:
        pass
    if time.monotonic() > deadline:
        sys.exit("no robot_description on the master")
    time.sleep(0.1)
rospy.init_node("demo_tf_probe", disable_signals=True)
links = [l.get("name") for l in ET.fromstring(rospy.get_param("robot_description")).findall("link")]
buf = tf2_ros.Buffer(); tf2_ros.TransformListener(buf)
while time.monotonic() < deadline:
    missing = [l for l in links if not buf.can_transform("base_footprint", l, rospy.Time(0))]
    if not missing:
        for l in links:
            t = buf.lookup_transform("base_footprint", l, rospy.Time(0)).transform.translation
            print("%-24s %7.3f %7.3f %7.3f" % (l, t.x, t.y, t.z))
        sys.exit(0)
    time.sleep(0.1)
sys.exit("frames not in tf: %s" % missing)
'''


def load_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return {"ok": False, "error": "no result written (%s)" % path}


def load_map(yaml_path):
    import yaml
    from PIL import Image
    with open(yaml_path) as f:
        meta = yaml.safe_load(f)
    img = np.array(Image.open(os.path.join(os.path.dirname(yaml_path), meta["image"])).convert("L"))
    # map_server trinary semantics: dark = occupied, light = free, else unknown.
    p = (255 - img.astype(float)) / 255.0
    if meta.get("negate", 0):
        p = 1.0 - p
    grid = np.full(img.shape, -1, dtype=np.int8)
    grid[p > meta["occupied_thresh"]] = 100
    grid[p < meta["free_thresh"]] = 0
    return np.flipud(grid), meta  # row 0 = lowest y


def world_to_map_frame(pose, origin):
    ox, oy, oyaw = origin
    dx, dy = pose[0] - ox, pose[1] - oy
    c, s = math.cos(-oyaw), math.sin(-oyaw)
    return (c * dx - s * dy, s * dx + c * dy, (pose[2] - oyaw + math.pi) % (2 * math.pi) - math.pi)


def world_extent(truth_yaml):
    """The ground-truth map's extent [xmin, ymin, xmax, ymax] (world frame)."""
    grid, meta = load_map(truth_yaml)
    (ox, oy), res = meta["origin"][:2], meta["resolution"]
    return [ox, oy, ox + grid.shape[1] * res, oy + grid.shape[0] * res]


def building_box(truth_yaml):
    """The inside of the outer walls [xmin, ymin, xmax, ymax] (world frame): the
    bounding box of the largest connected obstacle, shrunk past each side made
    mostly of wall (a door leaves most of its side standing)."""
    from scipy import ndimage
    grid, meta = load_map(truth_yaml)
    (ox, oy), res = meta["origin"][:2], meta["resolution"]
    labels, n = ndimage.label(grid == 100, structure=np.ones((3, 3)))
    if n == 0:
        return world_extent(truth_yaml)
    walls = labels == np.argmax(np.bincount(labels.ravel())[1:]) + 1
    rows, cols = np.nonzero(walls)
    r0, r1, c0, c1 = rows.min(), rows.max(), cols.min(), cols.max()
    while r0 < r1 and walls[r0, c0:c1 + 1].mean() > 0.5:
        r0 += 1
    while r1 > r0 and walls[r1, c0:c1 + 1].mean() > 0.5:
        r1 -= 1
    while c0 < c1 and walls[r0:r1 + 1, c0].mean() > 0.5:
        c0 += 1
    while c1 > c0 and walls[r0:r1 + 1, c1].mean() > 0.5:
        c1 -= 1
    return [ox + c0 * res, oy + r0 * res, ox + (c1 + 1) * res, oy + (r1 + 1) * res]


def numbers(values):
    """Command-line numbers argparse reads back: str(-3e-06) would look like an option."""
    return ["%.9f" % v for v in values]


def box_in_map(box, map_origin):
    """A world-frame box's bounding box in the map frame."""
    corners = [world_to_map_frame((x, y, 0.0), map_origin)[:2] for x in box[0::2] for y in box[1::2]]
    return [min(c[0] for c in corners), min(c[1] for c in corners),
            max(c[0] for c in corners), max(c[1] for c in corners)]


def compose(origin, align):
    """Pose in the world of a frame placed at align within the frame at origin."""
    c, s = math.cos(origin[2]), math.sin(origin[2])
    return (origin[0] + c * align[0] - s * align[1], origin[1] + s * align[0] + c * align[1],
            origin[2] + align[2])


def saved_map_at(shape, meta, map_yaml, map_origin):
    """The saved map's value (-1/0/100, -1 outside it) at the centre of each cell
    of a ground-truth grid of this shape and metadata."""
    res, (ox, oy) = meta["resolution"], meta["origin"][:2]
    rows, cols = np.indices(shape)
    mgrid, mmeta = load_map(map_yaml)
    mres, (mox, moy) = mmeta["resolution"], mmeta["origin"][:2]
    mx, my, _ = world_to_map_frame((ox + (cols + 0.5) * res, oy + (rows + 0.5) * res, 0.0), map_origin)
    mc, mr = np.floor((mx - mox) / mres).astype(int), np.floor((my - moy) / mres).astype(int)
    inside = (mr >= 0) & (mr < mgrid.shape[0]) & (mc >= 0) & (mc < mgrid.shape[1])
    out = np.full(shape, -1, dtype=np.int8)
    out[inside] = mgrid[mr[inside], mc[inside]]
    return out


def coverage(truth_yaml, map_yaml, map_origin, start_xy, clearance, box):
    """Share of the floor the robot could drive on (ground-truth free cells
    with the robot's clearance, inside the building, connected to the start)
    that the saved map knows, free or occupied."""
    from scipy import ndimage
    grid, meta = load_map(truth_yaml)
    res, (ox, oy) = meta["resolution"], meta["origin"][:2]
    rows, cols = np.indices(grid.shape)
    x, y = ox + (cols + 0.5) * res, oy + (rows + 0.5) * res
    floor = ((ndimage.distance_transform_edt(grid != 100) * res >= clearance)
             & (x >= box[0]) & (x <= box[2]) & (y >= box[1]) & (y <= box[3]))
    labels, _ = ndimage.label(floor)
    sr, sc = int((start_xy[1] - oy) / res), int((start_xy[0] - ox) / res)
    if not labels[sr, sc]:
        return math.nan
    floor = labels == labels[sr, sc]
    known = saved_map_at(grid.shape, meta, map_yaml, map_origin) >= 0
    return float(np.count_nonzero(known & floor)) / max(1, np.count_nonzero(floor))


def pick_goals(truth_yaml, map_yaml, map_origin, start_xy, n, clearance, seed=7):
    """Goals spread over the free space (world frame): cells with enough
    clearance in the ground truth that the saved map also knows as free (a
    robot can only plan where it mapped) and that connect to the start;
    farthest-point sampling, deterministic for a given world and map."""
    from scipy import ndimage
    grid, meta = load_map(truth_yaml)
    res, (ox, oy) = meta["resolution"], meta["origin"][:2]
    free = grid == 0
    mapped = saved_map_at(grid.shape, meta, map_yaml, map_origin) == 0
    clear = ndimage.distance_transform_edt(free) * res
    ok = (clear >= clearance) & mapped
    labels, _ = ndimage.label(ok)
    sr, sc = int((start_xy[1] - oy) / res), int((start_xy[0] - ox) / res)
    lab = labels[sr, sc] if 0 <= sr < grid.shape[0] and 0 <= sc < grid.shape[1] else 0
    if lab == 0:
        near = np.argwhere(labels > 0)
        lab = labels[tuple(near[np.argmin(np.hypot(near[:, 0] - sr, near[:, 1] - sc))])]
    cells = np.argwhere(labels == lab)
    rng = np.random.default_rng(seed)
    chosen = [np.array([sr, sc])]
    for _ in range(n):
        d = np.min([np.hypot(*(cells - c).T) for c in chosen], axis=0)
        d = d + rng.uniform(0, 1, len(d))  # deterministic tie-breaking
        chosen.append(cells[np.argmax(d)])
    goals = []
    for r, c in chosen[1:]:
        goals.append((ox + (c + 0.5) * res, oy + (r + 0.5) * res))
    return goals


def contact_count(stage):
    """The physics engine's contact count of a stage (steps in contact with an obstacle), or None
    when the stage did not report one."""
    c = stage.get("contacts")
    return None if c is None else c["contact_steps"]


def contact_text(stage):
    c = stage.get("contacts")
    if c is None:
        return "not measured"
    if c["contact_steps"] == 0:
        return "none"
    return "%.3f s in contact, first '%s' at %.1f s, %.1f mm deep at most" % (
        c["contact_s"], c["first_model"], c["first_s"], 1000 * c["max_depth_m"])


def score_map(map_yaml, truth_yaml, traj_npz, out_prefix):
    """Scores the saved map and the SLAM trajectory against ground truth. The trajectory is the
    SLAM node's keyframes after its last optimisation (what the map was rendered from); its best
    rigid fit to the truth also places the map. Online estimates drift before a loop closure
    corrects them and would misplace a good map. Falls back to the online estimate."""
    kf = out_prefix + "_keyframes.npz"
    if os.path.exists(kf) and len(np.load(kf)["est"]) >= 10:
        est_rows, gt_rows, source = np.load(kf)["est"], np.load(kf)["gt"], "keyframes"
    else:
        traj = np.load(traj_npz)["traj"]
        est_rows, gt_rows, source = traj[:, [0, 4, 5, 6]], traj[:, [0, 1, 2, 3]], "online estimate"
    est, gt = out_prefix + "_est.txt", out_prefix + "_gt.txt"
    np.savetxt(est, est_rows, header="stamp x y yaw (SLAM %s, map frame)" % source)
    np.savetxt(gt, gt_rows, header="stamp x y yaw (ground truth, map frame)")
    res = subprocess.run(["rosrun", "mybot_slam", "slam_score", "--map", map_yaml, "--truth", truth_yaml,
                          "--traj", est, "--truth-traj", gt], capture_output=True, text=True)
    if res.returncode != 0:
        return {"error": res.stderr.strip(), "trajectory": source}
    out = {k: float(v) for k, v in (line.split() for line in res.stdout.strip().splitlines())}
    out["trajectory"] = source
    return out


def plot(robot, out, truth_yaml, map_origin, map_yaml, traj_map, traj_nav, goals_map, frontier_goals):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    panels = [] if traj_map is None else [("mapping (exploration)", traj_map)]
    if traj_nav is not None or not panels:
        panels.append(("navigation on the saved map", traj_nav))
    fig, axes = plt.subplots(1, len(panels), figsize=(8 * len(panels) + 1, 7), squeeze=False)
    for ax, (title, traj) in zip(axes[0], panels):
        grid, meta = load_map(map_yaml)
        res, (ox, oy) = meta["resolution"], meta["origin"][:2]
        img = np.where(grid == 100, 0.0, np.where(grid == 0, 1.0, 0.75))
        ax.imshow(img, cmap="gray", origin="lower", vmin=0, vmax=1,
                  extent=(ox, ox + grid.shape[1] * res, oy, oy + grid.shape[0] * res))
        if traj is not None and len(traj):
            ax.plot(traj[:, 1], traj[:, 2], "g-", lw=2, label="ground truth")
            ax.plot(traj[:, 4], traj[:, 5], "r--", lw=1, label="online estimate (map frame)")
            ax.plot(traj[0, 1], traj[0, 2], "go", ms=8)
        kf = os.path.join(out, robot + "_mapping_keyframes.npz")
        if title.startswith("mapping") and os.path.exists(kf):
            est = np.load(kf)["est"]
            ax.plot(est[:, 1], est[:, 2], "b:", lw=1, label="SLAM keyframes, final")
        if title.startswith("navigation"):
            for i, g in enumerate(goals_map):
                ax.plot(g[0], g[1], "b*", ms=14)
                ax.annotate(str(i + 1), (g[0], g[1]), color="b", xytext=(5, 5), textcoords="offset points")
        elif frontier_goals:
            fg = np.array(frontier_goals)
            ax.plot(fg[:, 0], fg[:, 1], "m^", ms=7, label="frontier goals")
        # The world's extent: rays that left through a door do not shrink the building.
        xmin, ymin, xmax, ymax = box_in_map(world_extent(truth_yaml), map_origin)
        ax.set_xlim(xmin, xmax)
        ax.set_ylim(ymin, ymax)
        ax.set_title("%s: %s" % (robot, title))
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        if ax.get_legend_handles_labels()[0]:
            ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, robot + "_map.png"), dpi=110)
    plt.close(fig)

    panels = [(t, tr) for t, tr in (("mapping", traj_map), ("navigation", traj_nav)) if tr is not None and len(tr)]
    if not panels:
        return
    fig, axes = plt.subplots(len(panels), 1, figsize=(12, 3.5 * len(panels) + 0.5), squeeze=False)
    for ax, (title, traj) in zip(axes[:, 0], panels):
        if traj is None or not len(traj):
            continue
        t0 = traj[0, 0]
        t = traj[:, 0] - t0
        ax.plot(t, np.hypot(traj[:, 1] - traj[:, 4], traj[:, 2] - traj[:, 5]), label="|estimate - truth| [m]")
        traj = traj[np.isfinite(traj[:, 7:10]).all(axis=1)]
        t, odom = t[:0] if not len(traj) else traj[:, 0] - t0, traj[:, 7:10]
        if len(odom):
            # Odometry is in its own frame (the spawn pose): compare displacements from the start.
            o = odom - odom[0]
            g = traj[:, 1:4] - traj[0, 1:4]
            c, s = math.cos(traj[0, 3] - odom[0, 2]), math.sin(traj[0, 3] - odom[0, 2])
            ox, oy = c * o[:, 0] - s * o[:, 1], s * o[:, 0] + c * o[:, 1]
            ax.plot(t, np.hypot(ox - g[:, 0], oy - g[:, 1]), label="|odometry - truth| [m]")
        ax.set_title("%s: %s, error over sim time" % (robot, title))
        ax.set_xlabel("sim time [s]")
        ax.legend()
        ax.grid(True)
    fig.tight_layout()
    fig.savefig(os.path.join(out, robot + "_errors.png"), dpi=110)
    plt.close(fig)


def frontier_goals_from_log(path):
    goals = []
    try:
        with open(path) as f:
            for line in f:
                if "frontier of" in line and " at (" in line:
                    xy = line.split(" at (")[1].split(")")[0].split(",")
                    goals.append((float(xy[0]), float(xy[1])))
    except OSError:
        pass
    return goals


def run_mapping(robot, args, world, truth_yaml, out, common, summary):
    """Stage 1: explore with SLAM, save the map, score it. Returns the
    trajectory (None if the stage failed) and whether the map is good enough."""
    thresholds = {"precision": 0.85, "recall": 0.75, "coverage": 0.9}
    mx, my, myaw = world["map_start"]
    log("%s: mapping %s: spawn at (%.1f, %.1f), SLAM + navigation + frontier exploration" % (robot, args.world, mx, my))
    stage = Stage(robot + "_mapping", os.path.join(TOOLS, "launch", "mission_mapping.launch"),
                  dict(common, x=mx, y=my, yaw=myaw), out)
    map_prefix = os.path.join(out, robot + "_map")
    # Explore inside the building: rays through the loading bay's door would
    # otherwise lead the robot along the outside of the walls.
    building = building_box(truth_yaml)
    boundary = box_in_map(building, (mx, my, myaw))
    try:
        stage.run("mapping", "--map-out", map_prefix, "--budget", str(args.explore_budget),
                  "--boundary", *["%.3f" % v for v in boundary],
                  "--robot-radius", str(ROBOT_RADIUS[robot] + 0.15), "--map-origin", *numbers((mx, my, myaw)),
                  stall_timeout=args.stall_timeout, timeout=args.stage_timeout)
    finally:
        stage.close()
    mapping = load_json(os.path.join(out, robot + "_mapping.json"))
    summary["mapping"] = mapping
    if not mapping.get("ok"):
        log("%s: mapping FAILED: %s" % (robot, mapping.get("error", "see logs")))
        return None, False
    traj_map = np.load(os.path.join(out, robot + "_mapping_traj.npz"))["traj"]
    summary["map_score"] = score_map(map_prefix + ".yaml", truth_yaml, os.path.join(out, robot + "_mapping_traj.npz"),
                                     os.path.join(out, robot + "_mapping"))
    summary["mapping_collisions"] = contact_count(mapping)
    ms = summary["map_score"]
    # The saved map's frame in the world, as the SLAM trajectory's best fit to the ground truth
    # places it: a map a few tenths of a degree off the world is still a good map, and goals
    # given on it (as a user clicks them in rviz) are in its frame.
    summary["map_origin"] = compose((mx, my, myaw), (ms.get("align_x_m", 0.0), ms.get("align_y_m", 0.0),
                                                     ms.get("align_yaw_rad", 0.0)))
    summary["coverage"] = coverage(truth_yaml, map_prefix + ".yaml", summary["map_origin"], (mx, my),
                                   ROBOT_RADIUS[robot], building)
    online = mapping.get("trajectory_error", {})
    log("%s: map precision %.3f, recall %.3f, coverage %.3f, SLAM trajectory ATE %.3f m RMS (%s), online pose "
        "error %.3f m RMS / %.3f m max, contacts: %s" % (
            robot, ms.get("precision", math.nan), ms.get("recall", math.nan), summary["coverage"],
            ms.get("ate_rmse_m", math.nan), ms.get("trajectory", "?"), online.get("rms_m", math.nan),
            online.get("max_m", math.nan), contact_text(mapping)))

    mapping_ok = (ms.get("precision", 0) >= thresholds["precision"]
                  and ms.get("recall", 0) >= thresholds["recall"]
                  and summary["coverage"] >= thresholds["coverage"]
                  and summary["mapping_collisions"] == 0)
    log("%s: mapping %s (needs precision >= %.2f, recall >= %.2f, coverage >= %.2f, no collision)" % (
        robot, "succeeded" if mapping_ok else "FAILED", thresholds["precision"], thresholds["recall"],
        thresholds["coverage"]))
    return traj_map, mapping_ok


def run_robot(robot, args, world, truth_yaml, out):
    summary = {"robot": robot}
    wfile = os.path.join(args.worlds_dir, world["file"])
    mx, my, myaw = world["map_start"]
    nx, ny, nyaw = world["nav_start"]
    common = {"robot": robot, "world": wfile, "rviz": str(args.gui).lower(),
              "real_time_factor": args.real_time_factor,
              "sensor": args.sensor if robot == "swerve" else "laser"}
    summary["sensor"] = common["sensor"]

    if args.map:
        map_prefix = os.path.splitext(os.path.abspath(args.map))[0]
        log("%s: mapping skipped, navigating on %s.yaml (--map)" % (robot, map_prefix))
        summary["map_given"] = map_prefix + ".yaml"
        traj_map, mapping_ok = None, True
    else:
        traj_map, mapping_ok = run_mapping(robot, args, world, truth_yaml, out, common, summary)
        map_prefix = os.path.join(out, robot + "_map")
        if traj_map is None:
            return summary, False
    if not args.navigate and not args.map:
        plot(robot, out, truth_yaml, (mx, my, myaw), map_prefix + ".yaml", traj_map, None, [],
             frontier_goals_from_log(os.path.join(out, robot + "_mapping_explore.log")))
        return summary, mapping_ok
    frame = tuple(summary.get("map_origin", (mx, my, myaw)))  # the saved map's frame in the world
    goals_world = pick_goals(truth_yaml, map_prefix + ".yaml", frame, (nx, ny), args.goals, clearance=ROBOT_RADIUS[robot] + 0.35)
    goals_map = []
    for i, (gx, gy) in enumerate(goals_world):
        px, py = goals_world[i - 1] if i else (nx, ny)
        gyaw = math.atan2(gy - py, gx - px)
        goals_map.append(world_to_map_frame((gx, gy, gyaw), frame))
    init = world_to_map_frame((nx + 0.2, ny - 0.15, nyaw + 0.1), frame)  # a rough estimate, as a user clicks
    log("%s: navigation: respawn at (%.1f, %.1f), map_server + AMCL + navigation, %d goals" % (robot, nx, ny, len(goals_map)))
    stage = Stage(robot + "_navigation", os.path.join(TOOLS, "launch", "mission_navigation.launch"),
                  dict(common, x=nx, y=ny, yaw=nyaw, map_file=map_prefix + ".yaml",
                       real_time_factor=args.nav_real_time_factor), out)
    try:
        stage.run("navigation", "--initial-pose", *numbers(init), "--goals", json.dumps(goals_map),
                  "--map-origin", *numbers(frame), "--goal-timeout", str(args.goal_timeout),
                  stall_timeout=args.stall_timeout, timeout=args.stage_timeout)
    finally:
        stage.close()
    nav = load_json(os.path.join(out, robot + "_navigation.json"))
    summary["navigation"] = nav
    traj_nav = None
    if os.path.exists(os.path.join(out, robot + "_navigation_traj.npz")):
        traj_nav = np.load(os.path.join(out, robot + "_navigation_traj.npz"))["traj"]
        if nav.get("localized_from") is not None:
            # Before AMCL took the initial pose its estimate is the map origin: not drawn.
            traj_nav = traj_nav.copy()
            traj_nav[traj_nav[:, 0] < nav["localized_from"], 4:7] = np.nan
    plot(robot, out, truth_yaml, (mx, my, myaw), map_prefix + ".yaml", traj_map, traj_nav, goals_map,
         frontier_goals_from_log(os.path.join(out, robot + "_mapping_explore.log")))
    summary["navigation_collisions"] = contact_count(nav)
    ok = mapping_ok and bool(nav.get("ok")) and summary["navigation_collisions"] == 0
    if robot == "swerve" and nav.get("sideways_m", 0.0) < 0.05 * nav.get("driven_m", 0.0):
        log("swerve: navigation drove %.1f m of %.1f m sideways (< 5 %%): the holonomic planner is not being used"
            % (nav.get("sideways_m", 0.0), nav.get("driven_m", 0.0)))
        ok = False
    return summary, ok


def write_report(out, summaries, wall_s):
    lines = ["# Demo report", "", "wall time: %.0f s" % wall_s, ""]
    for s in summaries:
        m, n, ms = s.get("mapping", {}), s.get("navigation", {}), s.get("map_score", {})
        lines += ["## %s" % s["robot"], ""]
        if s.get("map_given"):
            lines.append("- mapping: skipped, navigation on the given map %s" % s["map_given"])
        else:
            lines.append("- mapping: %s; explored completely: %s; %.1f m driven; %.0f s sim, %.0f s wall" % (
                "ok" if m.get("ok") else "FAILED (%s)" % m.get("error", ""), m.get("explored_completely"),
                m.get("distance_m", math.nan), m.get("sim_s", math.nan), m.get("wall_s", math.nan)))
            lines.append("- map vs ground truth: precision %.3f, recall %.3f (occupied cells, 1-cell tolerance); "
                         "coverage %.3f (share of the drivable floor the map knows)" % (
                             ms.get("precision", math.nan), ms.get("recall", math.nan), s.get("coverage", math.nan)))
            if s.get("map_origin"):
                lines.append("- the saved map's frame is (%.3f m, %.3f m, %.2f deg) from the spawn pose by the SLAM "
                             "trajectory's best fit; goals and localization errors are in the map's frame" % (
                                 ms.get("align_x_m", 0.0), ms.get("align_y_m", 0.0),
                                 math.degrees(ms.get("align_yaw_rad", 0.0))))
            lines.append("- SLAM trajectory (%s after the last optimisation): ATE %.3f m RMS, RPE %.3f m / %.4f rad RMS" % (
                ms.get("trajectory", "?"), ms.get("ate_rmse_m", math.nan), ms.get("rpe_translation_rms_m", math.nan),
                ms.get("rpe_rotation_rms_rad", math.nan)))
            online = m.get("trajectory_error", {})
            lines.append("- online pose estimate while exploring (map -> base tf vs ground truth): %.3f m RMS, "
                         "%.3f m max, %.2f deg RMS" % (online.get("rms_m", math.nan), online.get("max_m", math.nan),
                                                       online.get("rms_deg", math.nan)))
        if not n:
            lines += ["- navigation stage not run (--mapping-only)", "- contacts with obstacles (physics engine): "
                      "mapping %s" % contact_text(m), ""]
            continue
        te = n.get("trajectory_error", {})
        lines.append("- localization (AMCL vs ground truth): %.3f m RMS, %.3f m max, %.2f deg RMS" % (
            te.get("rms_m", math.nan), te.get("max_m", math.nan), te.get("rms_deg", math.nan)))
        goals = n.get("goals", [])
        lines.append("- goals reached: %d / %d; navigation %.0f s sim, %.0f s wall, %.1f m driven, %.1f m of it "
                     "sideways (ground truth, body frame), largest sideways command %.2f m/s" % (
                         sum(g["reached"] for g in goals), len(goals), n.get("sim_s", math.nan),
                         n.get("wall_s", math.nan), n.get("distance_m", math.nan), n.get("sideways_m", math.nan),
                         n.get("max_sideways_cmd_mps", math.nan)))
        for i, g in enumerate(goals):
            lines.append("  - goal %d (%.2f, %.2f): %s, %.3f m / %.1f deg from it, %.0f s" % (
                i + 1, g["goal"][0], g["goal"][1], "reached" if g["reached"] else "NOT reached: " + g["text"],
                g["position_error_m"], g["yaw_error_deg"], g["sim_s"]))
        lines.append("- contacts with obstacles (physics engine, every step): mapping %s; navigation %s" % (
            contact_text(m) if m else "-", contact_text(n)))
        if n.get("error"):
            lines.append("- navigation error: " + n["error"])
        lines.append("")
    text = "\n".join(lines)
    # Both or neither: a demo interrupted while reporting leaves the previous report whole.
    from mybot_common.atomic_file import write_files_atomically  # built by scripts/setup; --help runs before

    write_files_atomically([(os.path.join(out, "report.md"), text + "\n"),
                            (os.path.join(out, "report.json"), json.dumps(summaries, indent=2, default=float))])
    return text


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--world", choices=sorted(WORLDS), default="factory")
    ap.add_argument("--robot", choices=ROBOTS + ("all",), default="all",
                    help="robot(s) for the mission (default all: mybot, then the swerve robot)")
    ap.add_argument("--mapping-only", dest="navigate", action="store_false",
                    help="stop after mapping (no AMCL + navigation stage)")
    ap.add_argument("--output", default=os.path.join(WS, "output", time.strftime("demo-%Y%m%d-%H%M%S")),
                    help="output folder for the report, pictures, maps and logs")
    ap.add_argument("--gui", action="store_true", help="also start rviz (needs a display)")
    ap.add_argument("--real-time-factor", type=float, default=0.0,
                    help="upper bound on the simulator's pace in the mapping stage (default 0: as fast as the "
                         "slowest lockstep participant, the simulator, SLAM, AMCL or move_base, allows)")
    ap.add_argument("--nav-real-time-factor", type=float, default=0.0,
                    help="the same for the navigation stage (default 0)")
    ap.add_argument("--sensor", choices=("laser", "depth"), default="laser",
                    help="the swerve robot's sensor: its laser, or the thesis's depth camera through depth_to_scan")
    ap.add_argument("--map", help="navigate on this saved map (map_server YAML) instead of exploring first")
    ap.add_argument("--goals", type=int, default=5, help="goals to visit per robot")
    ap.add_argument("--explore-budget", type=float, default=900.0, help="sim seconds of exploration per robot")
    ap.add_argument("--goal-timeout", type=float, default=240.0, help="sim seconds per goal")
    ap.add_argument("--stall-timeout", type=float, default=300.0,
                    help="stop a stage when sim time has not advanced for this many wall seconds (a hang)")
    ap.add_argument("--stage-timeout", type=float, default=0.0,
                    help="wall seconds per stage (default 0: none; a stage's length is bounded in sim time)")
    ap.add_argument("--worlds-dir", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worlds_dir is None:
        args.worlds_dir = subprocess.run(["rospack", "find", "mybot_gazebo_lite"], capture_output=True,
                                         text=True).stdout.strip() + "/worlds"
    out = os.path.abspath(args.output)
    os.makedirs(os.path.join(out, "logs"), exist_ok=True)
    log("output folder: %s" % out)
    t0 = time.monotonic()

    ok = True
    for model in ("mybot", "swerve", "gopigo"):
        log("%s: expanding the xacro and publishing its tf tree headless" % model)
        try:
            frames = robot_frames(model, out, 60.0)
            log("%s: %d frames reachable from base_footprint" % (model, len(frames)))
        except Exception as e:  # reported; the mission still runs
            log("%s: FAILED: %s" % (model, e))
            ok = False

    world = WORLDS[args.world]
    truth = os.path.join(out, args.world + "_truth")
    res = subprocess.run(["rosrun", "mybot_gazebo_lite", "world_to_map", os.path.join(args.worlds_dir, world["file"]),
                          truth, "--resolution", "0.05"], capture_output=True, text=True)
    if res.returncode != 0:
        log("FAILED to render the ground-truth map: " + res.stderr.strip())
        return 1
    log("ground-truth occupancy of %s rendered to %s.pgm" % (args.world, truth))

    summaries = []
    for robot in (ROBOTS if args.robot == "all" else (args.robot,)):
        summary, robot_ok = run_robot(robot, args, world, truth + ".yaml", out)
        summaries.append(summary)
        ok = ok and robot_ok
        log("%s: %s" % (robot, "mission succeeded" if robot_ok else "mission FAILED"))
    report = write_report(out, summaries, time.monotonic() - t0)
    print(report)
    log("report and pictures in %s" % out)
    log("mission %s in %.0f s of wall time" % ("succeeded" if ok else "FAILED", time.monotonic() - t0))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
