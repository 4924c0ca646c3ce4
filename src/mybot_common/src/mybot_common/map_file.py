"""The map_server file pair (ROS navigation map_server's map_saver.cpp, Noetic), byte for byte:
the Python twin of mybot_common/map_file.h (C++), one home per language. Pure: no rospy."""
import os

from mybot_common.atomic_file import write_files_atomically

DEFAULT_OCC = 65
DEFAULT_FREE = 25


def map_pgm(data, width, height, resolution, occ=DEFAULT_OCC, free=DEFAULT_FREE, creator="map_saver.cpp"):
    """P5 image, top row first: 0 <= v <= free -> 254, v >= occ -> 0, anything else -> 205.
    `data` is row-major from the grid's bottom row, as nav_msgs/OccupancyGrid's."""
    if len(data) != width * height:
        raise ValueError("map data has %d cells, expected width*height = %d" % (len(data), width * height))
    comment = creator.replace("\n", " ").replace("\r", " ")  # one comment line
    header = "P5\n# CREATOR: %s %.3f m/pix\n%d %d\n255\n" % (comment, resolution, width, height)
    out = bytearray(width * height)
    i = 0
    for y in range(height):
        row = (height - y - 1) * width
        for x in range(width):
            v = data[row + x]
            out[i] = 254 if 0 <= v <= free else (0 if v >= occ else 205)
            i += 1
    return header.encode("ascii") + bytes(out)


def map_yaml(image_name, resolution, origin_x, origin_y, yaw):
    """The YAML beside the image, as map_saver writes it (thresholds 0.65 / 0.196, negate 0)."""
    return ("image: %s\nresolution: %f\norigin: [%f, %f, %f]\nnegate: 0\noccupied_thresh: 0.65\n"
            "free_thresh: 0.196\n\n" % (image_name, resolution, origin_x, origin_y, yaw))


def save_map_files(basename, data, width, height, resolution, origin_x, origin_y, yaw, occ=DEFAULT_OCC,
                   free=DEFAULT_FREE, creator="map_saver.cpp"):
    """basename.pgm and basename.yaml, both or neither: both contents are composed first (a
    malformed grid raises ValueError before any file is touched), then they replace the old pair
    atomically (mybot_common.atomic_file.AtomicFileError names a file that cannot be written).
    Returns the two paths."""
    pgm_path = basename + ".pgm"
    yaml_path = basename + ".yaml"
    image = map_pgm(data, width, height, resolution, occ, free, creator)
    text = map_yaml(os.path.basename(pgm_path), resolution, origin_x, origin_y, yaw)
    write_files_atomically([(pgm_path, image), (yaml_path, text)])
    return pgm_path, yaml_path
