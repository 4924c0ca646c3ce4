"""slam_replay and slam_score from the command line, as a user runs them: the parameters slam_replay maps
with by default, and how each answers --help and bad arguments."""
import math
import os
import subprocess

import pytest

from mybot_common.node_process import executable


def tool(name):
    """A built tool of mybot_slam, found as rosrun finds it."""
    return executable("mybot_slam", name)


def slam_replay():
    return tool("slam_replay")


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


def test_timing_json_names_any_bag_path_and_counts_each_fallback(tmp_path):
    import json
    bag = tmp_path / 'a "quoted" \\ bag.bag'
    write_room_bag(bag)
    out = tmp_path / "out"
    run = subprocess.run(slam_replay() + ["--bag", str(bag), "--out", str(out), "--quiet"], capture_output=True,
                         text=True)
    assert run.returncode == 0, run.stderr
    timing = json.load(open(str(out / "timing.json")))
    assert timing["bag"] == str(bag)
    assert timing["scans"] == 6
    for key in ("weak_matches", "motion_fallbacks", "corrections_undone", "turn_fallbacks", "stall_searches",
                "stall_matches", "retry_searches", "retry_matches"):
        assert timing[key] == 0, key


def test_slam_replay_without_params_or_the_package_says_what_to_do(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "ROS_PACKAGE_PATH"}
    run = subprocess.run(slam_replay() + ["--bag", str(tmp_path / "none.bag"), "--out", str(tmp_path / "out")],
                         capture_output=True, text=True, env=env)
    assert run.returncode == 2
    assert run.stderr.strip().splitlines() == [
        "slam_replay: no --params given and the package mybot_slam is not on ROS_PACKAGE_PATH to take its "
        "config/slam.yaml from: source the workspace's setup.bash or pass --params FILE"]
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("name", ["slam_replay", "slam_score"])
@pytest.mark.parametrize("flag", ["--help", "-h"])
def test_help_prints_the_usage_on_stdout_and_succeeds(name, flag):
    run = subprocess.run(tool(name) + [flag], capture_output=True, text=True)
    assert run.returncode == 0
    assert run.stdout.startswith("usage: " + name + " ")
    assert run.stderr == ""


@pytest.mark.parametrize("name", ["slam_replay", "slam_score"])
def test_an_unknown_argument_is_named_before_the_usage(name):
    run = subprocess.run(tool(name) + ["--bogus"], capture_output=True, text=True)
    assert run.returncode == 2
    lines = run.stderr.splitlines()
    assert lines[0] == name + ": unknown argument --bogus"
    assert lines[1].startswith("usage: " + name + " ")


@pytest.mark.parametrize("args, error", [
    (["--local-max-dt", "two"], "slam_score: --local-max-dt must be a number in [0, 1e+09], got 'two'"),
    (["--local-max-dt", "-1"], "slam_score: --local-max-dt must be a number in [0, 1e+09], got '-1'"),
    (["--tolerance", "1.5"], "slam_score: --tolerance must be a whole number in [0, 1000], got '1.5'"),
    (["--align-first", "3x"], "slam_score: --align-first must be a whole number in [0, 1e+09], got '3x'"),
])
def test_slam_score_names_the_option_of_a_bad_number(tmp_path, args, error):
    run = subprocess.run(tool("slam_score") + ["--map", str(tmp_path / "m.yaml"), "--truth", str(tmp_path / "t.yaml")]
                         + args, capture_output=True, text=True)
    assert run.returncode == 2
    assert run.stderr.strip().splitlines() == [error]


def test_a_failed_run_leaves_none_of_the_folders_it_created_and_keeps_a_given_one(tmp_path):
    (tmp_path / "text.bag").write_text("t1 t2 x y z roll pitch yaw\n")
    out = str(tmp_path / "new" / "out") + "/"  # two folders to create, and a trailing slash
    run = subprocess.run(slam_replay() + ["--bag", str(tmp_path / "text.bag"), "--out", out, "--quiet"],
                         capture_output=True, text=True)
    assert run.returncode == 1 and "text.bag: not a ROS 1 bag" in run.stderr, run.stderr
    assert not (tmp_path / "new").exists()
    # Through "..": both folders it made go, the one the path only passed through as well.
    out = str(tmp_path / "passed" / ".." / "made")
    run = subprocess.run(slam_replay() + ["--bag", str(tmp_path / "text.bag"), "--out", out, "--quiet"],
                         capture_output=True, text=True)
    assert run.returncode == 1
    assert not (tmp_path / "passed").exists() and not (tmp_path / "made").exists()
    given = tmp_path / "given"
    given.mkdir()
    (given / "notes.txt").write_text("kept")
    run = subprocess.run(slam_replay() + ["--bag", str(tmp_path / "text.bag"), "--out", str(given), "--quiet"],
                         capture_output=True, text=True)
    assert run.returncode == 1
    assert sorted(p.name for p in given.iterdir()) == ["notes.txt"]
