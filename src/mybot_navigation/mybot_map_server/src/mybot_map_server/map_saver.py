"""map_saver's checks and its save of a nav_msgs/OccupancyGrid (ROS navigation
map_server/src/map_saver.cpp, Noetic); the file pair itself is mybot_common.map_file's.

Pure functions: no rospy, so they are unit tested directly."""
import math

from mybot_common.geometry import yaw_from_quaternion  # noqa: F401 (part of this module's interface)
from mybot_common.map_file import DEFAULT_FREE, DEFAULT_OCC, save_map_files


def check_grid(info):
    """A map worth saving: a positive finite resolution and a finite origin. Returns an error
    message naming the field, or None."""
    if not (math.isfinite(info.resolution) and info.resolution > 0):
        return "map info.resolution must be a positive number, got %r" % (info.resolution,)
    p, q = info.origin.position, info.origin.orientation
    for name, v in (("x", p.x), ("y", p.y), ("z", p.z)):
        if not math.isfinite(v):
            return "map info.origin.position.%s is %r" % (name, v)
    for name, v in (("x", q.x), ("y", q.y), ("z", q.z), ("w", q.w)):
        if not math.isfinite(v):
            return "map info.origin.orientation.%s is %r" % (name, v)
    return None


def save_map(grid, basename, occ=DEFAULT_OCC, free=DEFAULT_FREE):
    """Writes basename.pgm and basename.yaml from a nav_msgs/OccupancyGrid-like object, both or
    neither: the grid is checked and both files composed before anything is written, then they
    replace the old pair atomically. Raises ValueError (a malformed grid) or
    mybot_common.atomic_file.AtomicFileError (naming the file). Returns the two paths."""
    info = grid.info
    error = check_grid(info)
    if error:
        raise ValueError(error)
    q = info.origin.orientation
    return save_map_files(basename, grid.data, info.width, info.height, info.resolution, info.origin.position.x,
                          info.origin.position.y, yaw_from_quaternion(q.x, q.y, q.z, q.w), occ, free)


def check_thresholds(occ, free):
    """map_saver's rule: 0 <= free < occ <= 100. Returns an error message or None."""
    if not (0 <= free <= 100 and 0 <= occ <= 100):
        return "--occ and --free must be in [0, 100] (got occ=%d, free=%d)" % (occ, free)
    if free >= occ:
        return "--free (%d) must be smaller than --occ (%d)" % (free, occ)
    return None
