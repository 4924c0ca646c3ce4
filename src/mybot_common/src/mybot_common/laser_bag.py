"""A 2D laser log written as a ROS 1 bag laid out as the Kuemmerle et al. 2009 benchmark's bags are,
which is what mybot_slam's slam_replay reads: /scan (sensor_msgs/LaserScan, frame `laser`), /odom
(nav_msgs/Odometry, odom -> base_link), /tf with each odometry pose, and one /tf_static
base_link -> laser. The log converters (carmen_to_bag, mines_to_bag) parse their formats and
hand the records here in log order, so that slam_replay's `--odom last` pairs each scan with the
odometry written before it."""
import collections

from mybot_common.atomic_file import replaced_atomically
from mybot_common.geometry import quaternion_from_yaw

# A LaserScan's fixed fields: radians, radians, metres, metres.
ScanGeometry = collections.namedtuple("ScanGeometry", "angle_min angle_increment range_min range_max")


def write_laser_bag(path, records, laser_x):
    """Writes `records`, an iterable of ("scan", stamp, ranges, ScanGeometry) and
    ("odom", stamp, (x, y, yaw)) in log order (stamps in seconds), to the bag `path`, with the
    laser `laser_x` metres ahead of base_link. Returns (scans, odometry messages) written. The bag
    is replaced atomically: a failure or a kill part-way leaves an older bag at `path` whole."""
    import rosbag
    import rospy
    from geometry_msgs.msg import TransformStamped
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import LaserScan
    from tf2_msgs.msg import TFMessage

    scans = odoms = 0
    with replaced_atomically(path) as tmp, rosbag.Bag(tmp, "w") as bag:
        for record in records:
            kind, stamp = record[0], rospy.Time.from_sec(record[1])
            if scans == 0 and odoms == 0:
                static = TransformStamped()
                static.header.stamp = stamp
                static.header.frame_id = "base_link"
                static.child_frame_id = "laser"
                static.transform.translation.x = laser_x
                static.transform.rotation.w = 1.0
                bag.write("/tf_static", TFMessage([static]), stamp)
            if kind == "scan":
                ranges, g = record[2], record[3]
                m = LaserScan()
                m.header.seq = scans
                m.header.stamp = stamp
                m.header.frame_id = "laser"
                m.angle_min = g.angle_min
                m.angle_increment = g.angle_increment
                m.angle_max = g.angle_min + g.angle_increment * (len(ranges) - 1)
                m.range_min = g.range_min
                m.range_max = g.range_max
                m.ranges = ranges
                bag.write("/scan", m, stamp)
                scans += 1
                continue
            x, y, yaw = record[2]
            q = quaternion_from_yaw(yaw)
            o = Odometry()
            o.header.seq = odoms
            o.header.stamp = stamp
            o.header.frame_id = "odom"
            o.child_frame_id = "base_link"
            o.pose.pose.position.x, o.pose.pose.position.y = x, y
            (o.pose.pose.orientation.x, o.pose.pose.orientation.y, o.pose.pose.orientation.z,
             o.pose.pose.orientation.w) = q
            bag.write("/odom", o, stamp)
            tf = TransformStamped()
            tf.header = o.header
            tf.child_frame_id = "base_link"
            tf.transform.translation.x, tf.transform.translation.y = x, y
            tf.transform.rotation = o.pose.pose.orientation
            bag.write("/tf", TFMessage([tf]), stamp)
            odoms += 1
    return scans, odoms
