"""slam_replay from the command line, as a user runs it: the parameters it maps with by default."""
import math
import os
import subprocess

import pytest


def slam_replay():
    """The built slam_replay, found as rosrun finds it."""
    found = subprocess.run(["catkin_find", "--libexec", "mybot_slam", "slam_replay"], capture_output=True,
                           text=True).stdout.split()
    assert found, "slam_replay is not built (catkin_find --libexec mybot_slam slam_replay)"
    return [found[0]]


def room_ranges(x, n=181, half=2.0):
    """A 180 deg scan from (x, 0) facing +x in the square room |x|, |y| <= half."""
    ranges = []
    for i in range(n):
        a = -math.pi / 2 + i * math.pi / (n - 1)
        c, s = math.cos(a), math.sin(a)
        d = [(half - x) / c if c > 1e-9 else math.inf, half / abs(s) if abs(s) > 1e-9 else math.inf]
        ranges.append(min(d))
    return ranges


def write_room_bag(path, scans=6):
    """A robot creeping forward 2 cm a scan in a 4 m room: odometry, tf_static base_link -> laser, scans."""
    import rosbag
    import rospy
    from geometry_msgs.msg import TransformStamped
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import LaserScan
    from tf2_msgs.msg import TFMessage

    with rosbag.Bag(str(path), "w") as bag:
        t0 = rospy.Time(100)
        mount = TransformStamped()
        mount.header.stamp, mount.header.frame_id, mount.child_frame_id = t0, "base_link", "laser"
        mount.transform.rotation.w = 1.0
        bag.write("/tf_static", TFMessage([mount]), t0)
        stamps = []
        for k in range(scans):
            t = t0 + rospy.Duration(0.2 * (k + 1))
            odom = Odometry()
            odom.header.stamp, odom.header.frame_id, odom.child_frame_id = t, "odom", "base_link"
            odom.pose.pose.position.x = 0.02 * k
            odom.pose.pose.orientation.w = 1.0
            bag.write("/odom", odom, t)
            scan = LaserScan()
            scan.header.stamp, scan.header.frame_id = t, "laser"
            scan.angle_min, scan.angle_increment = -math.pi / 2, math.pi / 180
            scan.angle_max = math.pi / 2
            scan.range_min, scan.range_max = 0.05, 30.0
            scan.ranges = room_ranges(0.02 * k)
            bag.write("/scan", scan, t)
            stamps.append(t.to_sec())
    return stamps


def test_slam_replay_maps_with_the_packages_slam_yaml_when_given_no_params(tmp_path):
    stamps = write_room_bag(tmp_path / "room.bag")
    out = tmp_path / "out"
    run = subprocess.run(slam_replay() + ["--bag", str(tmp_path / "room.bag"), "--out", str(out), "--quiet"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert "slam_replay: parameters from " in run.stderr
    assert run.stderr.split("parameters from ")[1].split("\n")[0].endswith(
        os.path.join("mybot_slam", "config", "slam.yaml"))
    poses = [[float(v) for v in ln.split()] for ln in open(str(out / "trajectory.tum"))]
    assert [round(p[0], 3) for p in poses] == [round(s, 3) for s in stamps]
    # 2 cm a scan, 10 cm in all, as the odometry and the walls agree.
    assert poses[-1][1] - poses[0][1] == pytest.approx(0.10, abs=0.02)
    assert (out / "map.yaml").exists() and (out / "timing.json").exists()


def test_slam_replay_without_params_or_the_package_says_what_to_do(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "ROS_PACKAGE_PATH"}
    run = subprocess.run(slam_replay() + ["--bag", str(tmp_path / "none.bag"), "--out", str(tmp_path / "out")],
                         capture_output=True, text=True, env=env)
    assert run.returncode == 2
    assert run.stderr.strip().splitlines() == [
        "slam_replay: no --params given and the package mybot_slam is not on ROS_PACKAGE_PATH to take its "
        "config/slam.yaml from: source the workspace's setup.bash or pass --params FILE"]
    assert not (tmp_path / "out").exists()
