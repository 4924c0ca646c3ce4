"""The map_server file pair in Python (mybot_common.map_file), byte for byte as map_saver.cpp."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "src"))
from mybot_common.map_file import map_pgm, map_yaml, save_map_files  # noqa: E402


def test_pgm_values_and_row_order():
    # Grid rows bottom-up: row 0 = [-1, 0, 25], row 1 = [26, 64, 65], row 2 = [100, 1, -1].
    data = [-1, 0, 25, 26, 64, 65, 100, 1, -1]
    b = map_pgm(data, 3, 3, 0.05)
    header = b"P5\n# CREATOR: map_saver.cpp 0.050 m/pix\n3 3\n255\n"
    assert b.startswith(header)
    pixels = list(b[len(header):])
    # Image rows top-down: grid row 2 first.
    assert pixels == [0, 254, 205, 205, 205, 0, 205, 254, 254]


def test_yaml_matches_map_saver_printf():
    assert map_yaml("m.pgm", 0.05, -1.0, 2.5, 0.0) == (
        "image: m.pgm\nresolution: 0.050000\norigin: [-1.000000, 2.500000, 0.000000]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n\n")


def test_size_mismatch_is_an_error():
    try:
        map_pgm([0, 0], 3, 1, 0.05)
    except ValueError as e:
        assert "width*height" in str(e)
    else:
        raise AssertionError("expected ValueError")


# A failed save never destroys the map you had (the old pair is intact each time).


def test_creator_stays_one_comment_line():
    b = map_pgm([0], 1, 1, 0.05, creator="slam\nreplay")
    assert b.startswith(b"P5\n# CREATOR: slam replay 0.050 m/pix\n1 1\n255\n")


def test_save_writes_both_files_or_neither(tmp_path):
    base = str(tmp_path / "m")
    pgm, yml = save_map_files(base, [0, 100], 2, 1, 0.05, -1.0, 2.5, 0.5)
    assert open(yml).read().splitlines()[0] == "image: m.pgm"
    before = open(pgm, "rb").read()
    try:
        save_map_files(base, [0, 100, 0], 2, 1, 0.05, 0.0, 0.0, 0.0)  # malformed: nothing written
    except ValueError:
        pass
    else:
        raise AssertionError("expected ValueError")
    assert open(pgm, "rb").read() == before
