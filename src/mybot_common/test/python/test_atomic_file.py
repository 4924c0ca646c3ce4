import os
import signal
import subprocess
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "src"))
from mybot_common.atomic_file import (AtomicFileError, replaced_atomically,  # noqa: E402
                                      write_file_atomically, write_files_atomically)


def read(p):
    with open(p, "rb") as f:
        return f.read()


def test_writes_text_and_bytes(tmp_path):
    write_files_atomically([(str(tmp_path / "m.pgm"), b"P5\n\x00\x01"), (str(tmp_path / "m.yaml"), "image: m.pgm\n")])
    assert read(tmp_path / "m.pgm") == b"P5\n\x00\x01"
    assert read(tmp_path / "m.yaml") == b"image: m.pgm\n"
    assert sorted(os.listdir(tmp_path)) == ["m.pgm", "m.yaml"]


def test_replaces_old_content(tmp_path):
    p = str(tmp_path / "a")
    write_file_atomically(p, "old old old")
    write_file_atomically(p, "new")
    assert read(p) == b"new"


def test_permissions_follow_the_umask(tmp_path):
    old = os.umask(0o022)
    try:
        write_file_atomically(str(tmp_path / "a"), "x")
    finally:
        os.umask(old)
    assert os.stat(tmp_path / "a").st_mode & 0o777 == 0o644


def test_second_path_a_folder_leaves_the_old_pair(tmp_path):
    write_file_atomically(str(tmp_path / "m.pgm"), "old image")
    os.mkdir(tmp_path / "m.yaml")
    with pytest.raises(AtomicFileError, match="m.yaml.*directory"):
        write_files_atomically([(str(tmp_path / "m.pgm"), "new"), (str(tmp_path / "m.yaml"), "new")])
    assert read(tmp_path / "m.pgm") == b"old image"
    assert sorted(os.listdir(tmp_path)) == ["m.pgm", "m.yaml"]


def test_missing_folder_names_the_path(tmp_path):
    with pytest.raises(AtomicFileError, match="no/such/m.yaml"):
        write_file_atomically(str(tmp_path / "no" / "such" / "m.yaml"), "x")


def test_content_that_cannot_be_encoded_leaves_nothing(tmp_path):
    write_file_atomically(str(tmp_path / "a"), "old")
    with pytest.raises(TypeError):
        write_files_atomically([(str(tmp_path / "b"), "fine"), (str(tmp_path / "a"), object())])
    assert read(tmp_path / "a") == b"old"
    assert sorted(os.listdir(tmp_path)) == ["a"]


def test_sigkill_mid_write_leaves_the_old_file(tmp_path):
    """A writer killed while writing 200 MB: the old file is whole, whatever moment the kill hit."""
    target = tmp_path / "big.pgm"
    write_file_atomically(str(target), "old")
    src = os.path.join(os.path.dirname(__file__), "..", "..", "src")
    code = ("import sys; sys.path.insert(0, %r)\n"
            "from mybot_common.atomic_file import write_file_atomically\n"
            "print('start', flush=True)\n"
            "write_file_atomically(%r, b'x' * (200 << 20))\n" % (src, str(target)))
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE)
    assert p.stdout.readline() == b"start\n"
    p.send_signal(signal.SIGKILL)
    p.wait()
    assert read(target) in (b"old", b"x" * (200 << 20))


def test_a_writer_that_wants_a_name_replaces_the_file_when_it_is_done(tmp_path):
    p = str(tmp_path / "log.bag")
    write_file_atomically(p, "old")
    with replaced_atomically(p) as tmp:
        assert os.path.dirname(tmp) == str(tmp_path) and tmp != p
        with open(tmp, "w") as f:
            f.write("new")
        assert read(p) == b"old"  # nothing seen before the block ends
    assert read(p) == b"new"
    assert os.listdir(tmp_path) == ["log.bag"]


def test_a_writer_that_fails_leaves_the_old_file_and_no_temporary(tmp_path):
    p = str(tmp_path / "log.bag")
    write_file_atomically(p, "old")
    with pytest.raises(ValueError):
        with replaced_atomically(p) as tmp:
            with open(tmp, "w") as f:
                f.write("half")
            raise ValueError("a bad record")
    assert read(p) == b"old"
    assert os.listdir(tmp_path) == ["log.bag"]


def test_a_writer_into_a_missing_folder_names_the_path(tmp_path):
    p = str(tmp_path / "nowhere" / "log.bag")
    with pytest.raises(AtomicFileError, match="cannot write .*nowhere/log.bag"):
        with replaced_atomically(p):
            pass
