"""mines_to_bag: a CoreSLAM rover log's wheel odometry, stamps and URG-04LX readings."""
import math

import pytest
from scripts_under_test import load_script

m2b = load_script("mines_to_bag")


def line(usec, left, right, ranges_mm=None):
    """A record as the logs hold it: 707 fields, the ranges from field 25, a trailing 0."""
    ranges_mm = ranges_mm if ranges_mm is not None else [1500] * 682
    return " ".join(str(v) for v in [usec, 14710, left, right] + [0] * 20 + ranges_mm + [0])


def test_a_record_gives_its_stamp_ticks_and_682_ranges():
    (r,) = m2b.parse([line(2500000, 10, 20, list(range(682)))], "x.dat")
    assert r[0] == pytest.approx(2.5)
    assert (r[1], r[2]) == (10, 20)
    assert r[3] == list(range(682))


def test_equal_ticks_drive_straight_one_wheel_turn_per_2000_ticks():
    records = m2b.parse([line(0, 0, 0), line(100000, 2000, 2000)], "x.dat")
    poses = m2b.odometry(records, 0.077, 0.33, 2000)
    assert poses[0] == (0.0, 0.0, 0.0)
    assert poses[1] == pytest.approx((2 * math.pi * 0.077, 0.0, 0.0))


def test_opposite_ticks_turn_in_place_counter_clockwise_when_the_right_wheel_leads():
    # Each wheel rolls s = 2 pi r * 100 / 2000 of tread; the robot turns 2 s / separation.
    records = m2b.parse([line(0, 0, 0), line(100000, -100, 100)], "x.dat")
    x, y, yaw = m2b.odometry(records, 0.077, 0.33, 2000)[1]
    s = 2 * math.pi * 0.077 * 100 / 2000
    assert (x, y) == pytest.approx((0.0, 0.0))
    assert yaw == pytest.approx(2 * s / 0.33)


def test_readings_are_metres_as_urg_node_publishes_them():
    assert m2b.ranges_m(1234) == pytest.approx(1.234)
    assert math.isnan(m2b.ranges_m(0))  # nothing measured
    # An error code lies below range_min, where a LaserScan consumer drops it.
    assert m2b.ranges_m(7) < m2b.URG_04LX.range_min


def test_the_beams_span_240_degrees_from_the_right():
    g = m2b.URG_04LX
    assert g.angle_min == pytest.approx(math.radians(-120))
    assert g.angle_min + 681 * g.angle_increment == pytest.approx(math.radians(120))


def test_a_short_line_names_the_file_and_the_line():
    with pytest.raises(m2b.LogError, match=r"x\.dat:2: bad record: 30 fields"):
        m2b.parse([line(0, 0, 0), " ".join(["1"] * 30)], "x.dat")


def test_stamps_that_do_not_move_forward_are_refused():
    with pytest.raises(m2b.LogError, match=r"x\.dat:2: the time 1\.000000 s does not follow 1\.000000 s"):
        m2b.parse([line(1000000, 0, 0), line(1000000, 5, 5)], "x.dat")


def test_bad_robot_figures_are_refused(tmp_path, capsys):
    log = tmp_path / "x.dat"
    log.write_text(line(0, 0, 0) + "\n")
    with pytest.raises(SystemExit):
        m2b.main([str(log), str(tmp_path / "x.bag"), "--wheel-separation", "0"])
    assert "--wheel-separation must be a positive number" in capsys.readouterr().err


def test_the_whole_tool_writes_a_bag_slam_replay_reads(tmp_path):
    rosbag = pytest.importorskip("rosbag")
    log = tmp_path / "exp.dat"
    log.write_text("\n".join([line(1000000, 0, 0, [0] + [2000] * 681), line(1100000, 400, 400)]) + "\n")
    bag = tmp_path / "exp.bag"
    assert m2b.main([str(log), str(bag)]) == 0
    with rosbag.Bag(str(bag)) as b:
        order = [(topic, m) for topic, m, _ in b.read_messages()]
    # The laser's mount first, then each scan's odometry just before it, at its stamp.
    assert [topic for topic, _ in order] == ["/tf_static", "/odom", "/tf", "/scan", "/odom", "/tf", "/scan"]
    assert order[0][1].transforms[0].transform.translation.x == pytest.approx(0.145)
    scan, odom = order[6][1], order[4][1]
    assert scan.header.stamp.to_sec() == pytest.approx(1.1) and odom.header.stamp == scan.header.stamp
    assert odom.pose.pose.position.x == pytest.approx(400 * 2 * math.pi * 0.077 / 2000)
    assert len(scan.ranges) == 682 and scan.range_max == pytest.approx(5.6)
    first = order[3][1]
    assert math.isnan(first.ranges[0]) and first.ranges[1] == pytest.approx(2.0)
