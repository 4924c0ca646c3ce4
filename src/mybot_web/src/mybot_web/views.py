"""What the page draws, computed from plain values (no ROS types): poses, laser points in the
global frame, a decimated path, the trajectory trail, the map encoding and CPU load."""
import base64
import math
import zlib
from collections import deque


def yaw_from_quaternion(x, y, z, w):
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def compose(pose, local):
    """pose (x, y, yaw) applied to a local (x, y) point."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return pose[0] + c * local[0] - s * local[1], pose[1] + s * local[0] + c * local[1]


def scan_points(ranges, angle_min, angle_increment, range_min, range_max, sensor_pose, max_points):
    """Valid returns of a LaserScan as a flat [x0, y0, x1, y1, ...] in the frame of sensor_pose,
    rounded to 1 cm, at most max_points points (evenly subsampled)."""
    n = len(ranges)
    step = max(1, int(math.ceil(n / float(max_points)))) if max_points > 0 else n + 1
    out = []
    for i in range(0, n, step):
        r = ranges[i]
        if not (math.isfinite(r) and range_min <= r <= range_max):
            continue
        a = angle_min + i * angle_increment
        x, y = compose(sensor_pose, (r * math.cos(a), r * math.sin(a)))
        out.append(round(x, 2))
        out.append(round(y, 2))
    return out


def decimate_path(points, max_points):
    """Keep at most max_points of a polyline (always its last point), rounded to 1 cm."""
    n = len(points)
    if n == 0 or max_points <= 0:
        return []
    step = max(1, int(math.ceil(n / float(max_points))))
    keep = list(range(0, n, step))
    if keep[-1] != n - 1:
        keep[-1] = n - 1
    out = []
    for i in keep:
        out.append(round(points[i][0], 2))
        out.append(round(points[i][1], 2))
    return out


class Trail:
    """The robot's trajectory: a point every `spacing` metres, the newest `max_points` kept.
    Cleared when the frame changes (e.g. localisation starts and map replaces odom)."""

    def __init__(self, spacing=0.05, max_points=2000):
        self.spacing = spacing
        self.points = deque(maxlen=max_points)
        self.frame = None

    def add(self, frame, x, y):
        if frame != self.frame:
            self.points.clear()
            self.frame = frame
        if self.points:
            px, py = self.points[-1]
            if math.hypot(x - px, y - py) < self.spacing:
                return False
        self.points.append((round(x, 2), round(y, 2)))
        return True

    def flat(self):
        return [c for p in self.points for c in p]


def encode_grid(data):
    """OccupancyGrid cells (int8 -1..100, row-major from the origin) -> base64 of zlib-deflated
    bytes (unknown -1 becomes 255); the page inflates it with DecompressionStream('deflate')."""
    raw = bytes(v & 0xFF for v in data) if not isinstance(data, (bytes, bytearray)) else bytes(data)
    return base64.b64encode(zlib.compress(raw, 6)).decode("ascii")


def parse_proc_stat(text):
    """First line of /proc/stat -> (idle, total) jiffies (idle includes iowait)."""
    for line in text.splitlines():
        fields = line.split()
        if fields and fields[0] == "cpu":
            values = [int(v) for v in fields[1:]]
            if len(values) < 4:
                break
            # guest/guest_nice (fields 9, 10) are already counted in user/nice.
            total = sum(values[:8])
            idle = values[3] + (values[4] if len(values) > 4 else 0)
            return idle, total
    raise ValueError("no aggregate 'cpu' line in /proc/stat")


class CpuMeter:
    """CPU use in percent between two samples of /proc/stat."""

    def __init__(self, read=None):
        self._read = read or (lambda: open("/proc/stat").read())
        self._prev = None

    def sample(self):
        """Percent busy since the previous sample; None on the first call or if unreadable."""
        try:
            idle, total = parse_proc_stat(self._read())
        except (OSError, ValueError):
            return None
        prev, self._prev = self._prev, (idle, total)
        if prev is None or total <= prev[1]:
            return None
        busy = 1.0 - (idle - prev[0]) / float(total - prev[1])
        return round(100.0 * min(1.0, max(0.0, busy)), 1)
