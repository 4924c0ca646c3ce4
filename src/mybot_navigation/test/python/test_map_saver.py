"""map_saver output format, checked byte for byte against what ROS's map_saver writes."""
import math
import os
import sys
import types

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", ".."))

from mybot_navigation.map_saver import check_thresholds, pgm_bytes, save_map, yaml_text  # noqa: E402


def grid(width, height, data, resolution=0.05, ox=-1.0, oy=2.5, yaw=0.0):
    ns = types.SimpleNamespace
    q = ns(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2))
    info = ns(width=width, height=height, resolution=resolution,
              origin=ns(position=ns(x=ox, y=oy, z=0.0), orientation=q))
    return ns(info=info, data=data)


def test_pgm_values_and_row_order():
    # Grid rows bottom-up: row 0 = [-1, 0, 25], row 1 = [26, 64, 65], row 2 = [100, 1, -1].
    data = [-1, 0, 25, 26, 64, 65, 100, 1, -1]
    b = pgm_bytes(data, 3, 3, 0.05)
    header = b"P5\n# CREATOR: map_saver.cpp 0.050 m/pix\n3 3\n255\n"
    assert b.startswith(header)
    pixels = list(b[len(header):])
    # Image rows top-down: grid row 2 first.
    assert pixels == [0, 254, 205, 205, 205, 0, 205, 254, 254]


def test_custom_thresholds():
    b = pgm_bytes([50, 10, 30], 3, 1, 0.1, occ=50, free=10)
    assert list(b[-3:]) == [0, 254, 205]
    assert check_thresholds(65, 25) is None
    assert "smaller" in check_thresholds(20, 30)
    assert "[0, 100]" in check_thresholds(120, 25)


def test_yaml_matches_map_saver_printf():
    assert yaml_text("m.pgm", 0.05, -1.0, 2.5, 0.0) == (
        "image: m.pgm\nresolution: 0.050000\norigin: [-1.000000, 2.500000, 0.000000]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n\n")


def test_save_map_writes_bare_image_name_and_yaw(tmp_path):
    base = str(tmp_path / "sub" / "test_map")
    os.makedirs(os.path.dirname(base))
    pgm, yml = save_map(grid(2, 1, [0, 100], yaw=0.5), base)
    assert pgm == base + ".pgm" and os.path.getsize(pgm) > 0
    text = open(yml).read()
    assert text.splitlines()[0] == "image: test_map.pgm"
    assert "origin: [-1.000000, 2.500000, 0.500000]" in text


def test_size_mismatch_is_an_error():
    try:
        pgm_bytes([0, 0], 3, 1, 0.05)
    except ValueError as e:
        assert "width*height" in str(e)
    else:
        raise AssertionError("expected ValueError")
