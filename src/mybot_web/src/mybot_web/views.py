"""What the page draws, computed from plain values (no ROS types): poses, laser points in the
global frame, a decimated path, the trajectory trail, the map encoding and CPU load."""
import base64
import math
import struct
import zlib
from collections import deque, namedtuple
from mybot_common.geometry import yaw_from_quaternion


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


GridMessage = namedtuple("GridMessage", "frame_id resolution width height origin data")
_INFO = struct.Struct("<IIfII7d")  # map_load_time, resolution, width, height, origin pose


def parse_occupancy_grid(buff):
    """Serialized nav_msgs/OccupancyGrid -> GridMessage with `data` as raw bytes (int8 cells).
    rospy would unpack the cells into a tuple of ints: ~0.2 s for a 2000 x 2000 map, for
    nothing, as the page wants bytes. Raises ValueError on a truncated or inconsistent buffer."""
    try:
        _seq, _secs, _nsecs, n = struct.unpack_from("<IIII", buff, 0)
        at = 16
        frame_id = bytes(buff[at:at + n]).decode("utf-8")
        at += n
        values = _INFO.unpack_from(buff, at)
        at += _INFO.size
        (count,) = struct.unpack_from("<I", buff, at)
        at += 4
    except (struct.error, UnicodeDecodeError) as e:
        raise ValueError("malformed OccupancyGrid: %s" % e) from None
    _load_secs, _load_nsecs, resolution, width, height = values[:5]
    data = bytes(buff[at:at + count])
    if len(data) != count or count != width * height:
        raise ValueError("OccupancyGrid has %d cells for %d x %d" % (len(data), width, height))
    return GridMessage(frame_id, resolution, width, height, values[5:], data)


def encode_grid(data):
    """OccupancyGrid cells (int8 -1..100, row-major from the origin) -> base64 of zlib-deflated
    bytes (unknown -1 becomes 255); the page inflates it with DecompressionStream('deflate')."""
    raw = bytes(data) if isinstance(data, (bytes, bytearray)) else bytes(v & 0xFF for v in data)
    # Level 1: occupancy grids are long runs; higher levels cost time for a few % of size.
    return base64.b64encode(zlib.compress(raw, 1)).decode("ascii")


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
