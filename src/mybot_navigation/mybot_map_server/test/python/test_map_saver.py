"""map_saver: its thresholds, its save of an OccupancyGrid (the file pair is mybot_common.map_file's,
tested there byte for byte), and that a failed save never destroys the map you had."""
import math
import os
import signal
import subprocess
import sys
import types

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "src"))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "..", "mybot_common", "src"))

from mybot_common.map_file import map_pgm  # noqa: E402
from mybot_map_server.map_saver import check_thresholds, save_map  # noqa: E402


def grid(width, height, data, resolution=0.05, ox=-1.0, oy=2.5, yaw=0.0):
    ns = types.SimpleNamespace
    q = ns(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2))
    info = ns(width=width, height=height, resolution=resolution,
              origin=ns(position=ns(x=ox, y=oy, z=0.0), orientation=q))
    return ns(info=info, data=data)


def test_custom_thresholds():
    b = map_pgm([50, 10, 30], 3, 1, 0.1, occ=50, free=10)
    assert list(b[-3:]) == [0, 254, 205]
    assert check_thresholds(65, 25) is None
    assert "smaller" in check_thresholds(20, 30)
    assert "[0, 100]" in check_thresholds(120, 25)


def test_save_map_writes_bare_image_name_and_yaw(tmp_path):
    base = str(tmp_path / "sub" / "test_map")
    os.makedirs(os.path.dirname(base))
    pgm, yml = save_map(grid(2, 1, [0, 100], yaw=0.5), base)
    assert pgm == base + ".pgm" and os.path.getsize(pgm) > 0
    text = open(yml).read()
    assert text.splitlines()[0] == "image: test_map.pgm"
    assert "origin: [-1.000000, 2.500000, 0.500000]" in text


def _old_pair(tmp_path):
    base = str(tmp_path / "map")
    save_map(grid(2, 1, [0, 100]), base)
    return base, open(base + ".pgm", "rb").read(), open(base + ".yaml").read()


def _intact(base, pgm, yml):
    assert open(base + ".pgm", "rb").read() == pgm
    assert open(base + ".yaml").read() == yml


@pytest.mark.parametrize("bad, message", [
    (grid(3, 3, [0, 0]), "width\\*height"),
    (grid(2, 1, [0, 0], resolution=float("nan")), "resolution"),
    (grid(2, 1, [0, 0], resolution=0.0), "resolution"),
    (grid(2, 1, [0, 0], ox=float("inf")), "origin.position.x"),
    (grid(2, 1, [0, 0], yaw=float("nan")), "origin.orientation"),
])
def test_malformed_map_leaves_the_old_pair(tmp_path, bad, message):
    base, pgm, yml = _old_pair(tmp_path)
    with pytest.raises(ValueError, match=message):
        save_map(bad, base)
    _intact(base, pgm, yml)


def test_yaml_path_a_folder_leaves_the_old_pair(tmp_path):
    base, pgm, yml = _old_pair(tmp_path)
    os.rename(base + ".yaml", base + ".yaml.old")
    os.mkdir(base + ".yaml")
    with pytest.raises(OSError, match="map.yaml"):
        save_map(grid(2, 1, [100, 100]), base)
    assert open(base + ".pgm", "rb").read() == pgm  # no new image beside the old metadata
    assert sorted(os.listdir(tmp_path)) == ["map.pgm", "map.yaml", "map.yaml.old"]


def test_sigkill_mid_save_leaves_the_old_pair(tmp_path):
    """A 9-megapixel save killed 0.3 s in (while composing or writing): old pair or new, whole."""
    base, pgm, yml = _old_pair(tmp_path)
    here = os.path.dirname(os.path.abspath(__file__))
    code = ("import sys, types; sys.path[:0] = [%r, %r]\n"
            "from test_map_saver import grid\n"
            "from mybot_map_server.map_saver import save_map\n"
            "print('start', flush=True)\n"
            "save_map(grid(3000, 3000, [100] * 9000000), %r)\n"
            % (here, os.path.join(here, "..", "..", "src"), base))
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE)
    assert p.stdout.readline() == b"start\n"
    try:
        p.wait(timeout=0.3)
    except subprocess.TimeoutExpired:
        p.send_signal(signal.SIGKILL)
        p.wait()
    # Old or new, never a part: the old 2x1 image, or the whole 3000x3000 one (the YAML is the
    # same text for both: same resolution and origin).
    new_pgm = open(base + ".pgm", "rb").read()
    assert new_pgm == pgm or (new_pgm.startswith(b"P5\n") and b"\n3000 3000\n" in new_pgm[:80]
                              and len(new_pgm) == new_pgm.index(b"255\n") + 4 + 9000000)
    assert open(base + ".yaml").read() == yml
