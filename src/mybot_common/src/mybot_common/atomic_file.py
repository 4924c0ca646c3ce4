"""Files replaced atomically: a reader, a crash or a kill -9 sees the old content or the new, never
a part. Several files (a map's NAME.pgm and NAME.yaml) are all written to temporaries beside
their paths and renamed into place only once every one is complete, so a failure before that
leaves the old set untouched. The C++ twin is mybot_common/atomic_file.h. No rospy."""
import contextlib
import errno
import os
import tempfile


class AtomicFileError(OSError):
    """The message names the file: "cannot write /x/map.yaml: Is a directory"."""


def _fail(path, err):
    raise AtomicFileError(err, "cannot write %s: %s" % (path, os.strerror(err)), path)


def _temporary_beside(path):
    """(fd, name) of a new empty file in path's folder, with the mode open(path, "w") would give."""
    if os.path.isdir(path):
        _fail(path, errno.EISDIR)
    folder = os.path.dirname(path) or "."
    try:
        fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".tmp-", dir=folder)
    except OSError as e:
        _fail(path, e.errno)
    # mkstemp makes the file 0600; give it what open(path, "w") would have.
    mask = os.umask(0)
    os.umask(mask)
    os.fchmod(fd, 0o666 & ~mask)
    return fd, tmp


def _write_temporary(path, content):
    fd, tmp = _temporary_beside(path)
    try:
        data = content.encode("utf-8") if isinstance(content, str) else bytes(content)
        view = memoryview(data)
        while view:
            view = view[os.write(fd, view):]
        # On disk before the rename, or a power cut could leave the new name on an empty file.
        os.fsync(fd)
    except BaseException as e:
        os.close(fd)
        os.unlink(tmp)
        if isinstance(e, OSError):
            _fail(path, e.errno)
        raise
    os.close(fd)
    return tmp


@contextlib.contextmanager
def replaced_atomically(path):
    """For a writer that wants a file name rather than content (rosbag.Bag): yields the name of a
    temporary beside `path` for the block to write and close, and renames it onto `path` once the
    block ends without an exception (flushed to disk first). On an exception, or a kill before the
    end, `path` keeps its old content; the temporary is removed on an exception."""
    fd, tmp = _temporary_beside(path)
    os.close(fd)
    try:
        yield tmp
        fd = os.open(tmp, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
        os.replace(tmp, path)
    except BaseException as e:
        if os.path.exists(tmp):
            os.unlink(tmp)
        if isinstance(e, OSError) and not isinstance(e, AtomicFileError):
            _fail(path, e.errno or errno.EIO)
        raise


def write_files_atomically(files):
    """files: (path, content) pairs, content str (written as UTF-8) or bytes. Raises
    AtomicFileError with every temporary removed and every path untouched if any cannot be
    written (a path that is a folder, a missing or read-only folder, a full disk)."""
    files = list(files)
    temporaries = []
    try:
        for path, content in files:
            temporaries.append(_write_temporary(path, content))
    except BaseException:
        for t in temporaries:
            os.unlink(t)
        raise
    for i, (path, _) in enumerate(files):
        try:
            os.replace(temporaries[i], path)
        except OSError as e:
            for t in temporaries[i:]:
                os.unlink(t)
            _fail(path, e.errno)


def write_file_atomically(path, content):
    write_files_atomically([(path, content)])
