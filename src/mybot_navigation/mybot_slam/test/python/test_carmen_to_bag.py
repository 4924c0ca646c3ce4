"""carmen_to_bag: a corrected CARMEN log's raw odometry, stamps, beams and reference relations."""
import gzip
import math

import pytest
from scripts_under_test import load_script

c2b = load_script("carmen_to_bag")


def close(a, b, tol=1e-9):
    return all(abs(u - v) < tol for u, v in zip(a, b))


def flaser(n, pose, stamp, r=1.5):
    x, y, t = pose
    return "FLASER %d %s %f %f %f %f %f %f %f pippo %f" % (n, " ".join([str(r)] * n), x, y, t, x, y, t, stamp, stamp)


def odom(pose, stamp):
    return "ODOM %f %f %f 0 0 0 %f pippo %f" % (pose[0], pose[1], pose[2], stamp, stamp)


def corrected_log(raw, corrected, steps=3):
    """A mapper's output for a robot whose raw odometry at scan k is raw[k] and whose corrected pose
    there is corrected[k]: scan k, an echo of its pose (stamped 0, as GMapping writes it), then
    odometry records carrying the raw motion towards scan k+1 on from the corrected pose."""
    lines, t = ["PARAM robot_frontlaser_offset -0.04 nohost 0"], 10.0
    for k in range(len(raw)):
        lines.append(flaser(180, corrected[k], t))
        lines.append(odom(corrected[k], 0.0))
        lines.append("NEFF 50")
        if k + 1 < len(raw):
            step = c2b.between(raw[k], raw[k + 1])
            for i in range(1, steps + 1):
                part = (step[0] * i / steps, step[1] * i / steps, step[2] * i / steps)
                t += 0.1
                lines.append(odom(c2b.compose(corrected[k], part), t))
            t += 0.1
    return lines


RAW = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.3), (1.8, 0.6, 0.9), (2.0, 1.6, 1.7)]
# The mapper moved each pose off the odometry (a drift the odometry does not know).
CORRECTED = [(0.0, 0.0, 0.0), (1.02, 0.05, 0.28), (1.75, 0.72, 0.85), (1.9, 1.7, 1.62)]


def test_the_raw_odometry_at_each_scan_is_rebuilt_from_the_corrected_logs_increments():
    records, params = c2b.parse(corrected_log(RAW, CORRECTED))
    assert params["robot_frontlaser_offset"] == "-0.04"
    assert c2b.is_corrected(records)
    records = c2b.drop_echoes(records)
    odometry = c2b.raw_odometry(records, corrected=True)
    at_scans = [p for r, p in zip(records, odometry) if r[0] == "scan"]
    # The odometry starts at the first scan's pose; from there its motion is the raw one.
    for k in range(1, len(RAW)):
        assert close(c2b.between(at_scans[0], at_scans[k]), c2b.between(RAW[0], RAW[k]), 1e-5)
    # And the reference is the corrected poses.
    assert [r[2] for r in records if r[0] == "scan"] == [pytest.approx(p) for p in CORRECTED]


def test_the_echo_after_each_scan_is_dropped_and_the_stamps_then_run_forward():
    records, _ = c2b.parse(corrected_log(RAW, CORRECTED))
    with pytest.raises(c2b.LogError, match="backwards at record 1 "):
        c2b.stamps(records, "log", "x.log")  # the echo's 0 after the first scan
    times = c2b.stamps(c2b.drop_echoes(records), "log", "x.log")
    assert times == sorted(times)


def test_a_log_whose_stamps_are_unusable_is_refused_unless_stamped_in_record_order():
    records = [("odom", (0, 0, 0), 0.0), ("scan", [1.0], (0, 0, 0), (0, 0, 0), 0.0)]
    with pytest.raises(c2b.LogError, match="x.log: every timestamp is 0; use --stamps records"):
        c2b.stamps(records, "log", "x.log")
    assert c2b.stamps(records, "records") == [1e9, pytest.approx(1e9 + 0.01)]


def test_a_malformed_record_names_the_file_and_the_line():
    lines = [odom((0, 0, 0), 1.0), "FLASER 180 1.0 2.0 0 0 0 0 0 0 1.0 pippo 1.0"]
    with pytest.raises(c2b.LogError, match=r"x.log:2: bad FLASER record: 180 readings announced"):
        c2b.parse(lines, "x.log")
    with pytest.raises(c2b.LogError, match=r"x.log:1: bad ODOM record"):
        c2b.parse(["ODOM 0 0 zero 0 0 0 1.0"], "x.log")


def test_scans_with_no_odometry_between_them_are_reported():
    o = (0, 0, 0)
    records = [("odom", o, 1.0), ("scan", [1.0], o, o, 1.0), ("scan", [1.0], (0, 0, 1.4), o, 4.0),
               ("odom", (0, 0, 1.4), 4.1), ("scan", [1.0], (0, 0, 1.4), o, 4.2)]
    assert c2b.odometry_gaps(records, [r[-1] for r in records]) == [(1.0, 4.0)]


def test_carmen_beam_spacing():
    assert c2b.beam_increment(180) == pytest.approx(math.radians(1.0))
    assert c2b.beam_increment(181) == pytest.approx(math.radians(1.0))
    assert c2b.beam_increment(361) == pytest.approx(math.radians(0.5))


def test_revisit_relations_pair_a_scan_with_the_first_later_scan_near_it():
    # Out along x and back: scan i and scan 2n-i are at the same place.
    n = 30
    xs = list(range(n)) + list(range(n - 1, -1, -1))
    reference = [(float(i), (float(x), 0.0, 0.0 if i < n else math.pi)) for i, x in enumerate(xs)]
    consecutive, revisit = c2b.relations(reference, revisit_radius=0.5, revisit_min_gap=20)
    assert len(consecutive) == len(reference) - 1
    # Scan i (x = i) first meets a scan within 0.5 m at least 20 on at x = i on the way back.
    assert [(t1, t2) for t1, t2, _ in revisit] == [(float(i), float(2 * n - 1 - i)) for i in range(n - 10)]
    for _, _, p in revisit:
        assert close(p, (0.0, 0.0, math.pi), 1e-9) or close(p, (0.0, 0.0, -math.pi), 1e-9)


def test_the_whole_tool_writes_a_bag_slam_replay_reads(tmp_path):
    rosbag = pytest.importorskip("rosbag")
    log = tmp_path / "small-corrected.log.gz"
    with gzip.open(str(log), "wt") as f:
        f.write("\n".join(corrected_log(RAW, CORRECTED)) + "\n")
    bag = tmp_path / "small.bag"
    assert c2b.main([str(log), str(bag), "--reference", str(tmp_path / "ref.tum"),
                     "--relations", str(tmp_path / "small")]) == 0
    topics = {}
    with rosbag.Bag(str(bag)) as b:
        for topic, m, _ in b.read_messages():
            topics.setdefault(topic, []).append(m)
    assert len(topics["/scan"]) == 4 and len(topics["/tf_static"]) == 1
    assert len(topics["/odom"]) == 9  # 3 records for each of the 3 steps; the echoes dropped
    scan = topics["/scan"][0]
    assert scan.angle_min == pytest.approx(-math.pi / 2)
    assert scan.angle_increment == pytest.approx(math.radians(1.0))
    assert len(scan.ranges) == 180
    assert topics["/tf_static"][0].transforms[0].transform.translation.x == pytest.approx(-0.04)
    # The relations: 3 consecutive, none revisiting (4 scans).
    lines = [ln for ln in open(str(tmp_path / "small.consecutive.relations")) if not ln.startswith("#")]
    assert len(lines) == 3
    x, y, yaw = (float(v) for v in (lines[0].split()[2], lines[0].split()[3], lines[0].split()[7]))
    assert close((x, y, yaw), c2b.between(CORRECTED[0], CORRECTED[1]), 1e-5)


def test_a_raw_logs_scans_take_the_odometry_their_flaser_carries(tmp_path):
    rosbag = pytest.importorskip("rosbag")
    # A raw .clf: FLASER x y theta (the laser's pose by odometry) and odom_x... (CARMEN's odometry
    # interpolated to the scan's time) between ODOM records logged before and after it.
    log = tmp_path / "raw.clf"
    log.write_text("\n".join([
        odom((0.0, 0.0, 0.0), 1.0),
        "FLASER 180 %s 0.55 0 0.05 0.5 0 0.05 1.05 pippo 1.05" % " ".join(["2.0"] * 180),
        odom((1.0, 0.0, 0.1), 1.1),
    ]) + "\n")
    records, _ = c2b.parse(open(str(log)), "raw.clf")
    assert not c2b.is_corrected(records)
    assert records[1][3] == pytest.approx((0.5, 0.0, 0.05))
    assert c2b.main([str(log), str(tmp_path / "raw.bag")]) == 0
    with rosbag.Bag(str(tmp_path / "raw.bag")) as b:
        order = [(topic, m) for topic, m, _ in b.read_messages(topics=["/odom", "/scan"])]
    # In bag order: the ODOM before, the scan's own odometry at its stamp, the scan, the ODOM after.
    assert [topic for topic, _ in order] == ["/odom", "/odom", "/scan", "/odom"]
    at_scan = order[1][1]
    assert at_scan.header.stamp.to_sec() == pytest.approx(1.05)
    assert at_scan.pose.pose.position.x == pytest.approx(0.5)


def test_a_log_with_no_reference_is_refused_when_one_is_asked_for(tmp_path, capsys):
    log = tmp_path / "raw.log"
    log.write_text("\n".join([odom((0, 0, 0), 1.0), flaser(180, (0.5, 0, 0), 1.1), odom((0.1, 0, 0), 1.2)]) + "\n")
    assert c2b.main([str(log), str(tmp_path / "raw.bag"), "--reference", str(tmp_path / "r.tum")]) == 1
    assert "not a corrected log" in capsys.readouterr().err
