"""A capture never loses data. Lock first, refuse an existing
path unless asked, write ``PATH.partial`` and rename it atomically; a second
writer fails cleanly; readers never wait on a lock or hang on a damaged file.
Each test reproduces a defect of the earlier writer (which truncated the target
at open, let two writers interleave, and read whatever shape a file claimed)."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import time

import h5py
import numpy as np
import pytest

from lcpsim import open_capture, scenes
from lcpsim.io.capture import CaptureError, CaptureWriter
from lcpsim.io.safe_file import FileLockedError


def _capture(path, steps: int = 30, **kw) -> int:
    s = scenes.resting_cube()
    s.world.run(steps, capture=path, **kw)
    with open_capture(path) as c:
        return len(c)


def _python(code: str) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-c", textwrap.dedent(code)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )


def test_existing_capture_is_refused_and_kept(tmp_path):
    path = tmp_path / "c.h5"
    assert _capture(path, 30) == 30
    before = path.read_bytes()
    with pytest.raises(FileExistsError, match="already exists.*overwrite=True"):
        _capture(path, 50)
    assert path.read_bytes() == before
    # Asked to, it replaces the file (the new one complete, no partial left behind).
    assert _capture(path, 50, overwrite=True) == 50
    assert not (tmp_path / "c.h5.partial").exists() and not (tmp_path / "c.h5.lock").exists()


def test_capture_over_a_file_a_reader_holds_open(tmp_path):
    """The defect: a capture onto F, open in another process, truncated F to 0
    bytes and then failed with BlockingIOError."""
    path = tmp_path / "c.h5"
    assert _capture(path, 30) == 30
    size = path.stat().st_size
    reader = _python(
        f"""
        import sys, time, h5py
        f = h5py.File({str(path)!r}, "r")     # default HDF5 file locking
        print("open", flush=True)
        sys.stdin.readline() if False else time.sleep(30)
        """
    )
    try:
        assert reader.stdout is not None and reader.stdout.readline().strip() == "open"
        with pytest.raises(FileExistsError):
            _capture(path, 10)
        assert path.stat().st_size == size
        assert _capture(path, 40, overwrite=True) == 40  # a new file renamed over it
    finally:
        reader.kill()
        reader.wait(timeout=30)
    with open_capture(path) as c:
        assert len(c) == 40


_LONG_WRITER = """
import sys
from lcpsim import scenes
s = scenes.cube_on_slope(30.0, 0.5, cone_scale="dt")
print("start", flush=True)
s.world.run(4000, capture=sys.argv[1], chunk_steps=50)
print("done", flush=True)
"""


def test_second_writer_fails_cleanly_and_the_first_completes(tmp_path):
    """The defect: two writers of one path both exited 0 and left a file on
    which readers hung."""
    path = tmp_path / "two.h5"
    script = tmp_path / "writer.py"
    script.write_text(_LONG_WRITER)
    first = subprocess.Popen([sys.executable, str(script), str(path)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert first.stdout is not None and first.stdout.readline().strip() == "start"
        deadline = time.monotonic() + 60
        while not (tmp_path / "two.h5.partial").exists() and time.monotonic() < deadline:
            time.sleep(0.02)
        t0 = time.monotonic()
        with pytest.raises(FileLockedError, match="another process"):
            _capture(path, 10, overwrite=True)
        assert time.monotonic() - t0 < 5
        out, err = first.communicate(timeout=300)
    finally:
        first.kill()
    assert first.returncode == 0, err
    with open_capture(path) as c:
        assert len(c) == 4000
        np.testing.assert_array_equal(c.step, np.arange(4000))


def test_an_interrupted_writer_leaves_its_partial_file(tmp_path):
    path = tmp_path / "c.h5"
    with pytest.raises(RuntimeError, match="stop"):
        with CaptureWriter(path, {"scene": "x"}) as w:
            w.add(np.eye(2), np.array([-1.0, -1.0]))
            w.flush()
            raise RuntimeError("stop")
    partial = tmp_path / "c.h5.partial"
    assert not path.exists() and partial.exists()
    with open_capture(partial) as c:
        assert len(c) == 1
    # A new writer does not replace it silently.
    with pytest.raises(FileExistsError, match="interrupted"):
        CaptureWriter(path)
    with pytest.raises(FileNotFoundError, match="c.h5.partial"):
        open_capture(path)
    CaptureWriter(path, overwrite=True).close()
    assert path.exists() and not partial.exists()


def _in_subprocess_within(code: str, seconds: float) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=seconds)


def test_reader_refuses_a_damaged_file_claiming_huge_datasets(tmp_path):
    """A damaged index claiming 2⁴⁰ records: the reader must not try to read (allocate) them."""
    path = tmp_path / "c.h5"
    _capture(path, 20)
    with h5py.File(path, "a") as f:
        f["index/n"].resize((1 << 40,))
    p = _in_subprocess_within(
        f"""
        from lcpsim import open_capture
        from lcpsim.io.capture import CaptureError
        try:
            open_capture({str(path)!r})
        except CaptureError as e:
            print("refused:", e)
        """,
        60,
    )
    assert p.returncode == 0, p.stderr
    assert "refused:" in p.stdout and "damaged corpus" in p.stdout and "/index/n" in p.stdout


def test_reader_does_not_wait_for_a_writer_lock(tmp_path):
    """A file being written (HDF5's lock held, not SWMR): a reader answers at once."""
    path = tmp_path / "busy.h5"
    holder = _python(
        f"""
        import time, h5py
        f = h5py.File({str(path)!r}, "w")
        f.attrs["format"] = "lcpsim-corpus"
        f.flush()
        print("open", flush=True)
        time.sleep(60)
        """
    )
    try:
        assert holder.stdout is not None and holder.stdout.readline().strip() == "open"
        t0 = time.monotonic()
        with pytest.raises((CaptureError, OSError)):
            open_capture(path)
        assert time.monotonic() - t0 < 5
    finally:
        holder.kill()
        holder.wait(timeout=30)


def test_capture_into_a_missing_directory_is_a_clear_error(tmp_path):
    with pytest.raises(FileNotFoundError, match="no such directory"):
        CaptureWriter(tmp_path / "nowhere" / "c.h5")
    assert not os.path.exists(tmp_path / "nowhere")
