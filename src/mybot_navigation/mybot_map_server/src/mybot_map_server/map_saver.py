"""map_saver's file format, byte for byte (ROS navigation map_server/src/map_saver.cpp, Noetic).

Pure functions: no rospy, so they are unit tested directly."""
import math
import os

from mybot_common.atomic_file import write_files_atomically
from mybot_common.geometry import yaw_from_quaternion  # noqa: F401 (part of this module's interface)

DEFAULT_OCC = 65
DEFAULT_FREE = 25


def pgm_bytes(data, width, height, resolution, occ=DEFAULT_OCC, free=DEFAULT_FREE):
    """P5 image, top row first: 0 <= v <= free -> 254, v >= occ -> 0, anything else -> 205."""
    if len(data) != width * height:
        raise ValueError("map data has %d cells, expected width*height = %d" % (len(data), width * height))
    header = "P5\n# CREATOR: map_saver.cpp %.3f m/pix\n%d %d\n255\n" % (resolution, width, height)
    out = bytearray(width * height)
    i = 0
    for y in range(height):
        row = (height - y - 1) * width
        for x in range(width):
            v = data[row + x]
            out[i] = 254 if 0 <= v <= free else (0 if v >= occ else 205)
            i += 1
    return header.encode("ascii") + bytes(out)


def yaml_text(image_name, resolution, origin_x, origin_y, yaw):
    return ("image: %s\nresolution: %f\norigin: [%f, %f, %f]\nnegate: 0\noccupied_thresh: 0.65\n"
            "free_thresh: 0.196\n\n" % (image_name, resolution, origin_x, origin_y, yaw))


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
    pgm_path = basename + ".pgm"
    yaml_path = basename + ".yaml"
    image = pgm_bytes(grid.data, info.width, info.height, info.resolution, occ, free)
    text = yaml_text(os.path.basename(pgm_path), info.resolution, info.origin.position.x,
                     info.origin.position.y, yaw_from_quaternion(q.x, q.y, q.z, q.w))
    write_files_atomically([(pgm_path, image), (yaml_path, text)])
    return pgm_path, yaml_path


def check_thresholds(occ, free):
    """map_saver's rule: 0 <= free < occ <= 100. Returns an error message or None."""
    if not (0 <= free <= 100 and 0 <= occ <= 100):
        return "--occ and --free must be in [0, 100] (got occ=%d, free=%d)" % (occ, free)
    if free >= occ:
        return "--free (%d) must be smaller than --occ (%d)" % (free, occ)
    return None
