"""Measurement helpers of the thesis's evaluation nodes (pure: no ROS).

Pose error of an estimate (odometry or map pose) against ground truth, CPU load
from /proc/stat and CPU temperature from /sys/class/thermal, with the roots
configurable so tests can use fake trees.
"""
import bisect
import math
import os
from mybot_common.geometry import compose, inverse, wrap, yaw_from_quaternion  # noqa: F401 (yaw_from_quaternion: re-exported)


class PoseHistory:
    """Time-ordered 2D poses with linear interpolation (yaw interpolated on the circle)."""

    def __init__(self, max_age=10.0):
        self.t, self.poses = [], []
        self.max_age = max_age

    def add(self, t, pose):
        if self.t and t < self.t[-1]:  # time went back (simulation reset)
            self.t, self.poses = [], []
        self.t.append(t)
        self.poses.append(pose)
        while self.t and self.t[-1] - self.t[0] > self.max_age:
            self.t.pop(0)
            self.poses.pop(0)

    def at(self, t):
        """Pose at time t, or None outside the recorded interval."""
        if not self.t or t < self.t[0] or t > self.t[-1]:
            return None
        k = bisect.bisect_left(self.t, t)
        if self.t[k] == t:
            return self.poses[k]
        t0, t1 = self.t[k - 1], self.t[k]
        p0, p1 = self.poses[k - 1], self.poses[k]
        f = (t - t0) / (t1 - t0)
        return (p0[0] + f * (p1[0] - p0[0]), p0[1] + f * (p1[1] - p0[1]),
                wrap(p0[2] + f * wrap(p1[2] - p0[2])))


class PoseErrorTracker:
    """Errors of estimated poses against ground truth.

    The estimate lives in its own frame (odom, map); `reference` is that frame's
    pose in the ground-truth (world) frame. With align_initial, it is taken from
    the first matched pair, so errors measure drift from the start.
    """

    def __init__(self, reference=None, align_initial=True):
        self.reference = reference
        self.align_initial = align_initial and reference is None
        self.samples = []  # (t, position error, yaw error)

    def add(self, t, estimate, truth):
        if self.reference is None:
            if self.align_initial:
                self.reference = compose(truth, inverse(estimate))
            else:
                self.reference = (0.0, 0.0, 0.0)
        est_world = compose(self.reference, estimate)
        pos = math.hypot(est_world[0] - truth[0], est_world[1] - truth[1])
        yaw = wrap(est_world[2] - truth[2])
        self.samples.append((t, pos, yaw))
        return pos, yaw

    def summary(self):
        if not self.samples:
            return {"samples": 0}
        pos = [s[1] for s in self.samples]
        yaw = [abs(s[2]) for s in self.samples]
        n = len(pos)
        return {
            "samples": n,
            "duration": self.samples[-1][0] - self.samples[0][0],
            "position_final": pos[-1], "position_mean": sum(pos) / n,
            "position_rms": math.sqrt(sum(p * p for p in pos) / n), "position_max": max(pos),
            "yaw_final": self.samples[-1][2], "yaw_mean_abs": sum(yaw) / n,
            "yaw_rms": math.sqrt(sum(y * y for y in yaw) / n), "yaw_max_abs": max(yaw),
        }


def read_cpu_times(proc_root="/proc"):
    """(total, idle) jiffies of the aggregate 'cpu' line of /proc/stat."""
    path = os.path.join(proc_root, "stat")
    with open(path) as f:
        for line in f:
            if line.startswith("cpu "):
                vals = [int(v) for v in line.split()[1:]]
                idle = vals[3] + (vals[4] if len(vals) > 4 else 0)  # idle + iowait
                # guest time is already counted in user/nice
                total = sum(vals[:8]) if len(vals) >= 8 else sum(vals)
                return total, idle
    raise ValueError("%s has no aggregate 'cpu' line" % path)


class CpuLoad:
    """CPU load in percent between successive samples."""

    def __init__(self, proc_root="/proc"):
        self.proc_root = proc_root
        self.last = read_cpu_times(proc_root)

    def sample(self):
        total, idle = read_cpu_times(self.proc_root)
        dt, di = total - self.last[0], idle - self.last[1]
        self.last = (total, idle)
        if dt <= 0:
            return 0.0
        return 100.0 * (dt - di) / dt


def find_thermal_zone(sys_root="/sys", zone=-1):
    """Path of the temperature file: zone N, or the first whose type looks like the CPU.

    Returns None if there is none (containers, some VMs)."""
    base = os.path.join(sys_root, "class", "thermal")
    if zone >= 0:
        p = os.path.join(base, "thermal_zone%d" % zone, "temp")
        return p if os.path.exists(p) else None
    try:
        zones = sorted((d for d in os.listdir(base) if d.startswith("thermal_zone")),
                       key=lambda d: int(d[len("thermal_zone"):]) if d[len("thermal_zone"):].isdigit() else 1 << 30)
    except OSError:
        return None
    found = []
    for d in zones:
        temp = os.path.join(base, d, "temp")
        if not os.path.exists(temp):
            continue
        try:
            with open(os.path.join(base, d, "type")) as f:
                kind = f.read().strip().lower()
        except OSError:
            kind = ""
        found.append((temp, kind))
    for temp, kind in found:  # the Raspberry Pi's cpu-thermal, x86_pkg_temp, ...
        if "cpu" in kind or "x86_pkg" in kind or "soc" in kind:
            return temp
    return found[0][0] if found else None


def read_temperature(path):
    """Degrees Celsius from a thermal zone file (millidegrees)."""
    with open(path) as f:
        return int(f.read().strip()) / 1000.0
