import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "src"))
from mybot_move_base.trajectory import sideways_distance  # noqa: E402


def arc(v, w, vy=0.0, n=2000, dt=0.01):
    """Integrates a constant body twist; an arc's chord points along the mid-step heading."""
    x = y = th = 0.0
    rows = [(0.0, x, y, th)]
    for i in range(1, n + 1):
        h = th + 0.5 * w * dt
        x += (v * math.cos(h) - vy * math.sin(h)) * dt
        y += (v * math.sin(h) + vy * math.cos(h)) * dt
        th = math.atan2(math.sin(th + w * dt), math.cos(th + w * dt))
        rows.append((i * dt, x, y, th))
    return rows


def test_diff_drive_arc_has_no_sideways_motion():
    side, total = sideways_distance(arc(0.5, 0.7))  # 10 m on circles, heading wrapping past pi
    assert abs(total - 10.0) < 1e-6
    assert side < 1e-3


def test_strafe_is_all_sideways_whatever_the_heading():
    rows = [(i * 0.1, 0.0, -0.05 * i, -math.pi / 2) for i in range(41)]  # facing -y... moving -y: forward
    assert sideways_distance(rows)[0] < 1e-9
    rows = [(i * 0.1, 0.05 * i, 0.0, -math.pi / 2) for i in range(41)]  # facing -y, moving +x: to its left
    side, total = sideways_distance(rows)
    assert abs(side - 2.0) < 1e-9 and abs(total - 2.0) < 1e-9


def test_mixed_twist_and_short_input():
    side, total = sideways_distance(arc(0.3, 0.2, vy=0.4))
    assert abs(side / total - 0.8) < 1e-3  # |vy| / |v| of the body twist
    assert sideways_distance([(0, 1, 2, 3)]) == (0.0, 0.0)
    assert sideways_distance(np.empty((0, 4))) == (0.0, 0.0)
