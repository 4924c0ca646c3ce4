"""Planar angles and quaternions, one home for every Python node and test. No rospy.

A rotation about z by yaw is the quaternion (0, 0, sin(yaw/2), cos(yaw/2)); for any unit
quaternion the yaw of its rotation (z-y-x convention, as tf's getRPY) is
atan2(2 (w z + x y), 1 - 2 (y^2 + z^2))."""
import math


def yaw_from_quaternion(x, y, z, w):
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def yaw_of(q):
    """Yaw of a geometry_msgs/Quaternion-like object (fields x, y, z, w)."""
    return yaw_from_quaternion(q.x, q.y, q.z, q.w)


def quaternion_from_yaw(yaw):
    """(x, y, z, w) of a rotation about z."""
    return 0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)


def wrap(a):
    """An angle in (-pi, pi]."""
    return math.atan2(math.sin(a), math.cos(a))


def compose(a, b):
    """Planar pose a (x, y, yaw) followed by b, given in a's frame: a * b."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], wrap(a[2] + b[2]))


def inverse(a):
    """The pose that undoes a: inverse(a) * a is the identity."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return (-c * a[0] - s * a[1], s * a[0] - c * a[1], -a[2])


def between(a, b):
    """Pose b in a's frame: inverse(a) * b (a relative pose, as in Kuemmerle et al.'s relations)."""
    c, s = math.cos(a[2]), math.sin(a[2])
    dx, dy = b[0] - a[0], b[1] - a[1]
    return (c * dx + s * dy, -s * dx + c * dy, wrap(b[2] - a[2]))
