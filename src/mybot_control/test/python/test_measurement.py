import math
import os

import pytest

from mybot_control import measurement as m


def test_yaw_from_quaternion():
    assert m.yaw_from_quaternion(0, 0, math.sin(0.4), math.cos(0.4)) == pytest.approx(0.8)


def test_history_interpolation_and_reset():
    h = m.PoseHistory()
    h.add(1.0, (0.0, 0.0, math.pi - 0.1))
    h.add(2.0, (1.0, 2.0, -math.pi + 0.1))  # yaw wraps through pi
    mid = h.at(1.5)
    assert mid[:2] == pytest.approx((0.5, 1.0))
    assert abs(m.wrap(mid[2] - math.pi)) < 1e-9
    assert h.at(0.5) is None and h.at(2.5) is None
    h.add(0.1, (0, 0, 0))  # simulation reset
    assert h.t == [0.1]


def test_pose_error_aligned_to_start():
    tr = m.PoseErrorTracker(align_initial=True)
    # odom starts at 0 while the robot is at (2, 1) facing +y in the world
    assert tr.add(0.0, (0.0, 0.0, 0.0), (2.0, 1.0, math.pi / 2)) == pytest.approx((0.0, 0.0))
    # odom says 1 m forward; truth says it went 1.1 m along +y and turned slightly
    pos, yaw = tr.add(1.0, (1.0, 0.0, 0.0), (2.0, 2.1, math.pi / 2 + 0.05))
    assert pos == pytest.approx(0.1) and yaw == pytest.approx(-0.05)
    s = tr.summary()
    assert s["samples"] == 2 and s["position_max"] == pytest.approx(0.1)
    assert s["position_rms"] == pytest.approx(math.sqrt(0.01 / 2))
    assert s["yaw_final"] == pytest.approx(-0.05)


def test_pose_error_without_alignment():
    tr = m.PoseErrorTracker(align_initial=False)
    assert tr.add(0.0, (1.0, 0.0, 0.0), (1.0, 0.3, 0.0)) == pytest.approx((0.3, 0.0))
    assert m.PoseErrorTracker().summary() == {"samples": 0}


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


def test_cpu_load_from_fake_proc(tmp_path):
    stat = tmp_path / "stat"
    write(str(stat), "cpu  100 0 100 800 0 0 0 0 0 0\ncpu0 50 0 50 400 0 0 0 0 0 0\n")
    load = m.CpuLoad(str(tmp_path))
    write(str(stat), "cpu  150 0 150 900 0 0 0 0 0 0\n")
    assert load.sample() == pytest.approx(50.0)
    assert load.sample() == 0.0  # no time passed
    write(str(stat), "intr 1\n")
    with pytest.raises(ValueError):
        load.sample()


def test_thermal_zone_selection(tmp_path):
    sysr = str(tmp_path)
    assert m.find_thermal_zone(sysr) is None  # no thermal class at all
    base = os.path.join(sysr, "class", "thermal")
    write(os.path.join(base, "thermal_zone0", "type"), "acpitz\n")
    write(os.path.join(base, "thermal_zone0", "temp"), "27800\n")
    assert m.find_thermal_zone(sysr) == os.path.join(base, "thermal_zone0", "temp")
    write(os.path.join(base, "thermal_zone1", "type"), "cpu-thermal\n")
    write(os.path.join(base, "thermal_zone1", "temp"), "48312\n")
    path = m.find_thermal_zone(sysr)
    assert path.endswith("thermal_zone1/temp")
    assert m.read_temperature(path) == pytest.approx(48.312)
    assert m.find_thermal_zone(sysr, zone=0).endswith("thermal_zone0/temp")
    assert m.find_thermal_zone(sysr, zone=7) is None
