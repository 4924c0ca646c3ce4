"""world_to_map from the command line, as a user runs it: the map of a world file, and one message
naming the option for a bad value."""
import os
import subprocess

import pytest

from mybot_common.node_process import executable

WORLDS = os.path.join(os.path.dirname(__file__), "..", "..", "worlds")


def world_to_map():
    return executable("mybot_gazebo_lite", "world_to_map")


def test_writes_the_map_server_pair_of_a_world(tmp_path):
    run = subprocess.run(world_to_map() + [os.path.join(WORLDS, "mybot.world"), str(tmp_path / "truth"),
                                           "--resolution", "0.1"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    yaml = (tmp_path / "truth.yaml").read_text()
    assert "resolution: 0.1" in yaml and "truth.pgm" in yaml
    assert (tmp_path / "truth.pgm").read_bytes().startswith(b"P5")


@pytest.mark.parametrize("args, message", [
    (["--resolution", "-1"], "--resolution must be > 0 (resolution -1,"),
    (["--resolution", "0"], "--resolution must be > 0 (resolution 0,"),
    (["--z-min", "1", "--z-max", "0.5"], "--z-max must be >= --z-min (resolution 0.05, z-min 1, z-max 0.5,"),
    (["--margin", "-0.5"], "--margin must be >= 0 ("),
    (["--resolution", "fine"], "--resolution: not a number: fine"),
])
def test_a_bad_value_is_named_and_nothing_is_written(tmp_path, args, message):
    run = subprocess.run(world_to_map() + [os.path.join(WORLDS, "mybot.world"), str(tmp_path / "truth")] + args,
                         capture_output=True, text=True)
    lines = run.stderr.strip().splitlines()
    assert run.returncode == 2
    assert len(lines) == 1 and lines[0].startswith("world_to_map: ") and message in lines[0], run.stderr
    assert list(tmp_path.iterdir()) == []
