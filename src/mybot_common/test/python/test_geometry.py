import math
import os
import sys
import types

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "src"))
from mybot_common.geometry import between, compose, inverse, quaternion_from_yaw, wrap, yaw_from_quaternion, yaw_of  # noqa: E402


@pytest.mark.parametrize("yaw", [0.0, 0.3, -1.2, math.pi - 1e-9, -math.pi + 1e-9, 2.5])
def test_yaw_round_trips_through_a_quaternion(yaw):
    x, y, z, w = quaternion_from_yaw(yaw)
    assert yaw_from_quaternion(x, y, z, w) == pytest.approx(yaw)
    assert yaw_of(types.SimpleNamespace(x=x, y=y, z=z, w=w)) == pytest.approx(yaw)


def test_yaw_ignores_roll_and_pitch_of_a_tilted_base():
    # Rz(0.7) * Rx(0.1), a base rolled by 0.1 rad and heading 0.7: the heading is still 0.7.
    r, yw = 0.1, 0.7
    q = (math.sin(r / 2) * math.cos(yw / 2), math.sin(r / 2) * math.sin(yw / 2),
         math.cos(r / 2) * math.sin(yw / 2), math.cos(r / 2) * math.cos(yw / 2))
    assert yaw_from_quaternion(*q) == pytest.approx(0.7, abs=1e-9)


@pytest.mark.parametrize("a, wrapped", [(0.0, 0.0), (3 * math.pi / 2, -math.pi / 2), (-7.0, -7.0 + 2 * math.pi),
                                        (2 * math.pi, 0.0)])
def test_wrap(a, wrapped):
    assert wrap(a) == pytest.approx(wrapped, abs=1e-12)


def test_planar_poses_compose_invert_and_relate():
    a = (1.0, 2.0, 0.7)
    b = (-0.3, 0.5, -2.0)
    c = compose(a, b)
    assert compose(inverse(a), c) == pytest.approx(b)
    assert between(a, c) == pytest.approx(b)
    assert compose(a, inverse(a)) == pytest.approx((0.0, 0.0, 0.0))
    # A quarter turn, then a metre ahead: a metre along the world's y.
    assert compose((0.0, 0.0, math.pi / 2), (1.0, 0.0, 0.0)) == pytest.approx((0.0, 1.0, math.pi / 2))
