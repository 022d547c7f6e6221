"""The file readers on damaged input (the Python side of the
fuzzing; ``scripts/fuzz_readers.py`` runs the same readers on mutated files
for a fixed time). A reader returns or raises a clean error — a ValueError
(``LcpFileError``, ``CaptureError``) or an OSError — within seconds; never
another exception, never a hang. ``data/fuzz/`` keeps what the fuzzer found."""

from __future__ import annotations

import faulthandler
import gzip
import random
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lcpsim import open_capture, scenes, solve_lcp
from lcpsim.io import load_dump, load_lcp, save_lcp
from lcpsim.io.capture import CaptureWriter
from lcpsim.io.fclib import read_fclib
from lcpsim.trajectory import Trajectory

FOUND = Path(__file__).parent / "data" / "fuzz"
CLEAN = (ValueError, OSError)


def _read_all(path: Path) -> None:
    """Every reader on ``path``; only clean errors may escape each."""
    # (The trajectory reader in this process: its child-process probe is tested below.)
    trajectory = lambda p: Trajectory.load(p, probe=False)  # noqa: E731
    for read in (load_lcp, lambda p: load_lcp(p, 0), load_dump, _capture_records, trajectory, read_fclib):
        try:
            read(path)
        except CLEAN:
            pass


def _capture_records(path: Path) -> None:
    with open_capture(path) as c:
        for rec in c:
            rec.unscaled()


@pytest.mark.parametrize("name", sorted(p.name for p in FOUND.glob("*.gz")))
def test_inputs_the_fuzzer_found(tmp_path, name):
    """Each once hung a reader (HDF5's SWMR reader retries a bad checksum with
    exponential back-off; a truncated file sent to it hangs too; a global heap
    whose free space has size 0 stalls HDF5 itself) or raised RuntimeError,
    KeyError or NotImplementedError. Run in a subprocess with a
    deadline, so a regression fails instead of hanging the suite."""
    path = tmp_path / name[:-3]
    path.write_bytes(gzip.decompress((FOUND / name).read_bytes()))
    code = f"""
        import faulthandler, sys
        faulthandler.dump_traceback_later(30, exit=True)
        sys.path[:0] = {sys.path[:1]!r}
        from pathlib import Path
        from test_fuzz_readers import _read_all
        _read_all(Path({str(path)!r}))
        print("clean")
    """
    p = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=60,
        cwd=Path(__file__).parent,
    )
    assert p.returncode == 0 and p.stdout.strip() == "clean", p.stderr[-3000:]


@pytest.fixture(scope="module")
def valid_files(tmp_path_factory) -> dict[str, bytes]:
    d = tmp_path_factory.mktemp("valid")
    M, q = np.array([[2.0, 1.0], [1.0, 2.0]]), np.array([-1.0, -1.0])
    out = {"npz": save_lcp(d / "p.npz", M, q).read_bytes(), "h5": save_lcp(d / "p.h5", M, q).read_bytes()}
    with CaptureWriter(d / "c.h5") as w:
        w.add(M, q, np.array([1 / 3, 1 / 3]), np.zeros(2))
    out["capture"] = (d / "c.h5").read_bytes()
    out["dump"] = Path(solve_lcp(-np.eye(2), q, dump=str(d)).dump_path).read_bytes()
    out["trajectory"] = Path(scenes.resting_cube().world.run(2, record_contacts=True).save(d / "t.h5")).read_bytes()
    return out


@settings(max_examples=100, deadline=None)
@given(data=st.binary(max_size=2048), suffix=st.sampled_from([".npz", ".h5", ".bin"]))
def test_arbitrary_bytes(tmp_path_factory, data, suffix):
    path = tmp_path_factory.mktemp("bytes") / f"x{suffix}"
    path.write_bytes(data)
    _read_all(path)


@settings(max_examples=100, deadline=None)
@given(
    kind=st.sampled_from(["npz", "h5", "capture", "dump", "trajectory"]),
    seed=st.integers(0, 2**32 - 1),
    edits=st.integers(1, 16),
)
def test_mutated_valid_files(tmp_path_factory, valid_files, kind, seed, edits):
    rng = random.Random(seed)
    b = bytearray(valid_files[kind])
    for _ in range(edits):
        i = rng.randrange(len(b))
        if rng.random() < 0.2:
            del b[rng.randrange(len(b)) :]
            if not b:
                break
        else:
            b[i] = rng.randrange(256)
    path = tmp_path_factory.mktemp("mutated") / ("x.npz" if kind == "npz" else "x.h5")
    path.write_bytes(bytes(b))
    faulthandler.dump_traceback_later(60, exit=True)  # a hang fails the run instead of stalling it
    try:
        _read_all(path)
    finally:
        faulthandler.cancel_dump_traceback_later()


@pytest.mark.slow
def test_probe_turns_a_crash_or_a_hang_into_an_error(tmp_path, monkeypatch):
    """``lcpsim solve`` reads HDF5 files in a child first (``hdf5_check.probe``):
    the HDF5 library can crash (the fuzzer found a segmentation fault reading a
    damaged attribute) or loop where no Python exception reaches."""
    from lcpsim.io import hdf5_check

    path = save_lcp(tmp_path / "p.h5", np.eye(2), -np.ones(2))
    hdf5_check.probe(path)  # a sound file passes
    monkeypatch.setattr(hdf5_check, "_PROBE", "import os, signal; os.kill(os.getpid(), signal.SIGSEGV)")
    with pytest.raises(hdf5_check.DamagedHdf5Error, match="crashes the HDF5 library"):
        hdf5_check.probe(path)
    monkeypatch.setattr(hdf5_check, "_PROBE", "import time; time.sleep(60)")
    with pytest.raises(hdf5_check.DamagedHdf5Error, match="did not finish in 1 s"):
        hdf5_check.probe(path, timeout=1.0)


@pytest.mark.parametrize("name", sorted(p.name for p in (FOUND.parent / "fuzz_crash").glob("*.gz")))
def test_lcpsim_solve_survives_a_file_that_crashes_hdf5(tmp_path, name):
    """Damaged attributes on which the HDF5 library itself segfaults (found by
    the reader fuzzer in two runs; no in-process guard can catch it):
    ``lcpsim solve`` reads the file in a child first and exits 2 with one line."""
    path = tmp_path / "crash.h5"
    path.write_bytes(gzip.decompress((FOUND.parent / "fuzz_crash" / name).read_bytes()))
    p = subprocess.run(
        [sys.executable, "-m", "lcpsim", "solve", str(path), "--index", "0"], capture_output=True, text=True, timeout=120
    )
    assert p.returncode == 2, (p.stdout, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "crashes the HDF5 library" in lines[0], p.stderr


def test_trajectory_load_and_lcpsim_view_survive_a_file_that_crashes_hdf5(tmp_path):
    """The same file as a trajectory: ``Trajectory.load`` (and so ``lcpsim
    view``) read it in a child first too — a ``TrajectoryFileError``, and exit
    2 with one line, instead of a segmentation fault."""
    path = tmp_path / "crash.h5"
    path.write_bytes(gzip.decompress((FOUND.parent / "fuzz_crash" / "segfault_attribute.h5.gz").read_bytes()))
    code = f"""
        import sys
        sys.path[:0] = {sys.path[:1]!r}
        from lcpsim import Trajectory
        from lcpsim.io.trajectory_file import TrajectoryFileError
        try:
            Trajectory.load({str(path)!r})
        except TrajectoryFileError as e:
            print("clean:", e)
    """
    p = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and "crashes the HDF5 library" in p.stdout, (p.returncode, p.stdout, p.stderr[-2000:])
    p = subprocess.run(
        [sys.executable, "-m", "lcpsim", "view", str(path), "--out", str(tmp_path / "v.html")],
        capture_output=True, text=True, timeout=120,
    )
    assert p.returncode == 2, (p.stdout, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "crashes the HDF5 library" in lines[0], p.stderr
    assert not (tmp_path / "v.html").exists()


def test_open_capture_can_probe_a_file_first(tmp_path, monkeypatch):
    """``open_capture(path, probe=True)`` opens the corpus in a child first: a
    sound corpus opens as without it; a crash or a hang of the HDF5 library in
    the child is a ``DamagedHdf5Error`` (a ``ValueError``) here."""
    from lcpsim.io import hdf5_check

    s = scenes.box_stack(2)
    path = tmp_path / "c.h5"
    s.world.run(5, capture=path)
    with open_capture(path, probe=True) as c, open_capture(path) as d:
        assert len(c) == len(d) > 0 and np.array_equal(c[0].M, d[0].M)
    monkeypatch.setattr(hdf5_check, "_PROBE", "import os, signal; os.kill(os.getpid(), signal.SIGSEGV)")
    with pytest.raises(hdf5_check.DamagedHdf5Error, match="crashes the HDF5 library"):
        open_capture(path, probe=True)
    with open_capture(path) as c:  # without the probe, the file is read as it is
        assert len(c) > 0


@pytest.mark.parametrize("name", sorted(p.name for p in (FOUND.parent / "fuzz_crash").glob("*.gz")))
def test_open_capture_with_probe_survives_a_file_that_crashes_hdf5(tmp_path, name):
    """The damaged files on which HDF5 segfaults, opened as corpora with the
    probe: a clean ``ValueError`` (whichever reader stage refuses them), never
    a dead interpreter."""
    path = tmp_path / "crash.h5"
    path.write_bytes(gzip.decompress((FOUND.parent / "fuzz_crash" / name).read_bytes()))
    code = f"""
        import sys
        sys.path[:0] = {sys.path[:1]!r}
        from lcpsim import open_capture
        try:
            open_capture({str(path)!r}, probe=True)
        except ValueError as e:
            print("clean:", type(e).__name__, e)
    """
    p = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and p.stdout.startswith("clean:"), (p.returncode, p.stdout, p.stderr[-2000:])


# ----- the shape constructors and the MJCF reader on arbitrary input -----

_REAL = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True, width=64),
    st.sampled_from([0.0, 1.0, -1.0, 1e-300, 1e300, 0.5]),
)


def _unchanged_or_one_more(w, before: int, add) -> None:
    """``add(w)`` adds one valid body or raises a ValueError and adds nothing."""
    try:
        i = add(w)
    except ValueError as e:
        assert "\n" not in str(e).strip() and w.body_count == before, str(e)
        return
    assert w.body_count == before + 1 and i == before
    b = w.body(i)
    assert np.all(np.isfinite(b.position)) and (b.is_static or (b.mass > 0 and np.all(np.isfinite(b.inertia))))


@settings(max_examples=150, deadline=None)
@given(points=st.lists(st.tuples(_REAL, _REAL, _REAL), max_size=12))
def test_add_convex_on_any_points_adds_a_valid_hull_or_nothing(points):
    from lcpsim import World

    w = World()
    w.add_ground()
    _unchanged_or_one_more(w, 1, lambda w: w.add_convex(np.array(points, dtype=float).reshape(-1, 3)))


@settings(max_examples=150, deadline=None)
@given(
    points=st.lists(st.tuples(_REAL, _REAL, _REAL), max_size=8),
    faces=st.lists(st.tuples(*[st.integers(-2, 9)] * 3), max_size=6),
)
def test_add_mesh_on_any_vertices_and_faces_adds_a_valid_mesh_or_nothing(points, faces):
    from lcpsim import World

    w = World()
    _unchanged_or_one_more(
        w, 0, lambda w: w.add_mesh(np.array(points, dtype=float).reshape(-1, 3), np.array(faces, dtype=np.int64).reshape(-1, 3))
    )


_MJCF = """<mujoco><option timestep="0.002"/><asset><mesh name="m" vertex="0 0 0 1 0 0 0 1 0 0 0 1"/></asset>
<worldbody><geom type="plane" size="1 1 1"/><geom type="box" size=".1 .2 .3" pos="1 0 0"/>
<body name="a" pos="0 0 1"><freejoint/><geom type="capsule" size=".1 .2" contype="2" conaffinity="3"/></body>
<body name="b" pos="0 1 1"><freejoint/><geom type="mesh" mesh="m"/></body></worldbody></mujoco>"""


# Joints, nested bodies, an actuator, an explicit pair and an exclude: the parts of the reader
# beyond free bodies and static geoms.
_MJCF_JOINTED = """<mujoco><option timestep="0.002"/><worldbody><geom name="floor" type="plane" size="2 2 .1"/>
<body name="arm" pos="0 0 .5"><joint name="h" type="hinge" axis="0 1 0" range="-30 30" limited="true"/>
<geom name="link" type="capsule" size=".05 .2" euler="0 90 0"/>
<body name="tip" pos=".3 0 0"><joint name="s" type="slide" axis="1 0 0" range="-.1 .1"/><geom type="box" size=".05 .05 .05"/>
<body name="ball" pos=".1 0 0"><joint type="ball"/><geom type="sphere" size=".04"/></body></body></body>
<body name="cube" pos=".5 0 .1"><freejoint/><geom name="cube" type="box" size=".1 .1 .1" contype="0"/></body></worldbody>
<contact><pair geom1="cube" geom2="floor" friction=".8 .8"/><exclude body1="arm" body2="cube"/></contact>
<actuator><velocity name="v" joint="s" kv="50" forcerange="-20 20" forcelimited="true"/></actuator></mujoco>"""


@settings(max_examples=150, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), edits=st.integers(1, 6), template=st.sampled_from([_MJCF, _MJCF_JOINTED]))
def test_from_mjcf_on_mutated_xml_builds_a_world_or_raises_mjcf_error(seed, edits, template):
    pytest.importorskip("mujoco")
    from lcpsim import World
    from lcpsim.mjcf import MjcfError

    rng = random.Random(seed)
    s = list(template)
    for _ in range(edits):
        k = rng.randrange(len(s))
        op = rng.randrange(3)
        if op == 0:
            del s[k]
        elif op == 1:
            s.insert(k, rng.choice('<>/="-. 019aefxyz'))
        else:
            s[k] = rng.choice('<>/="-. 019aefxyz')
    try:
        w = World.from_mjcf("".join(s))
    except MjcfError as e:
        assert "\n" not in str(e).strip()
        return
    w.run(3)
