import base64
import math
import zlib

import pytest

from mybot_web import views


def test_yaw_from_quaternion():
    for yaw in (0.0, 0.7, -2.5, math.pi / 2):
        assert views.yaw_from_quaternion(0, 0, math.sin(yaw / 2), math.cos(yaw / 2)) == pytest.approx(yaw)


def test_scan_points_in_the_global_frame():
    # Sensor at (1, 2) facing +y: a return 1 m straight ahead lands at (1, 3).
    pts = views.scan_points([1.0, float("inf"), 0.01, 2.0], -0.0, math.pi / 2, 0.1, 10.0,
                            (1.0, 2.0, math.pi / 2), 100)
    assert pts == pytest.approx([1.0, 3.0, 3.0, 2.0])  # inf and < range_min dropped


def test_scan_points_are_subsampled():
    pts = views.scan_points([1.0] * 1000, 0.0, 0.001, 0.1, 10.0, (0, 0, 0), 100)
    assert len(pts) // 2 == 100


def test_decimate_path_keeps_the_end():
    path = [(i * 0.1, 0.0) for i in range(1001)]
    out = views.decimate_path(path, 50)
    assert len(out) // 2 <= 51
    assert out[:2] == [0.0, 0.0] and out[-2:] == [100.0, 0.0]
    assert views.decimate_path([], 10) == []


def test_trail_spacing_and_frame_change():
    t = views.Trail(spacing=0.1, max_points=3)
    assert t.add("odom", 0, 0)
    assert not t.add("odom", 0.05, 0)
    assert t.add("odom", 0.2, 0)
    t.add("odom", 0.4, 0)
    t.add("odom", 0.6, 0)
    assert t.flat() == [0.2, 0, 0.4, 0, 0.6, 0]  # bounded
    t.add("map", 5, 5)
    assert t.flat() == [5, 5] and t.frame == "map"


def test_encode_grid_round_trip():
    cells = [-1, 0, 50, 100]
    raw = zlib.decompress(base64.b64decode(views.encode_grid(cells)))
    assert list(raw) == [255, 0, 50, 100]


STAT = "cpu  {u} 0 {s} {i} 0 0 0 0 0 0\ncpu0 1 2 3 4 5 6 7 8 9 10\n"


def test_cpu_meter():
    samples = iter([STAT.format(u=100, s=0, i=100), STAT.format(u=150, s=0, i=150), "garbage"])
    m = views.CpuMeter(read=lambda: next(samples))
    assert m.sample() is None  # first sample has no interval yet
    assert m.sample() == 50.0
    assert m.sample() is None  # unreadable


def test_parse_proc_stat_rejects_garbage():
    with pytest.raises(ValueError):
        views.parse_proc_stat("intr 1 2 3")


def test_parse_occupancy_grid_matches_rospy():
    from io import BytesIO

    from nav_msgs.msg import OccupancyGrid

    m = OccupancyGrid()
    m.header.seq, m.header.frame_id = 7, "map"
    m.info.resolution, m.info.width, m.info.height = 0.05, 3, 2
    m.info.origin.position.x, m.info.origin.position.y = -1.5, 2.0
    m.info.origin.orientation.z, m.info.origin.orientation.w = math.sin(0.2), math.cos(0.2)
    m.data = [-1, 0, 100, 50, 0, -1]
    buf = BytesIO()
    m.serialize(buf)
    raw = buf.getvalue()
    g = views.parse_occupancy_grid(raw)
    assert (g.frame_id, g.width, g.height) == ("map", 3, 2)
    assert g.resolution == pytest.approx(0.05)
    assert g.origin[:2] == (-1.5, 2.0)
    assert views.yaw_from_quaternion(*g.origin[3:]) == pytest.approx(0.4)
    assert list(g.data) == [255, 0, 100, 50, 0, 255]
    assert views.encode_grid(g.data) == views.encode_grid(m.data)
    with pytest.raises(ValueError):
        views.parse_occupancy_grid(raw[:-1])  # truncated cells
    with pytest.raises(ValueError):
        views.parse_occupancy_grid(raw[:20])  # truncated header
