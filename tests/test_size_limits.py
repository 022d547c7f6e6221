"""Every size that comes from a user or a file is checked
before anything is allocated — a clear ValueError saying how much memory the
request needs, never an abort. Requests that used to kill the interpreter
(SIGABRT on a 128 TB allocation) run in a subprocess, so that the suite
survives them on a build that still aborts."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import lcpsim
from lcpsim import World, generate
from lcpsim.io import LcpFileError, load_lcp

REPROS = Path(__file__).parent / "data" / "repros"


def _survives(code: str, timeout: float = 120) -> str:
    """Runs ``code`` in a fresh interpreter; it must exit normally. Returns stdout."""
    p = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=timeout)
    assert p.returncode == 0, f"exit {p.returncode}\nstdout: {p.stdout}\nstderr: {p.stderr[-2000:]}"
    return p.stdout


@pytest.mark.parametrize("k", [10**6, 2**62])
def test_friction_dirs_beyond_the_limit_is_a_value_error(k):
    out = _survives(
        f"""
        from lcpsim import World
        try:
            w = World(friction_dirs={k})
            w.add_ground()
            w.add_box(size=1.0, position=(0, 0, 0.5))
            w.step()
        except ValueError as e:
            print("ValueError:", e)
        """
    )
    assert "ValueError: friction_dirs must be even and in [2, 1024]" in out


def test_the_largest_friction_dirs_still_works():
    w = World(friction_dirs=1024)
    w.add_ground()
    w.add_box(size=1.0, position=(0, 0, 0.5))
    assert w.step().status == "solved"


def test_an_island_too_large_for_memory_fails_the_step_cleanly():
    """1000 boxes stacked, k = 1024: one island of 4,000 contacts, an LCP of
    4.1 million unknowns (134 TB), refused before assembly."""
    out = _survives(
        """
        from lcpsim import World
        w = World(friction_dirs=1024)
        w.add_ground()
        for i in range(1000):
            w.add_box(size=1.0, position=(0, 0, 0.5 + i))
        try:
            w.step()
        except ValueError as e:
            print("ValueError:", e)
        """
    )
    assert "ValueError: step 0, contact island 0: a contact LCP of 4000 contacts" in out
    assert "TiB, more than this machine's" in out


def test_a_run_longer_than_memory_is_refused():
    out = _survives(
        """
        from lcpsim import World
        w = World()
        w.add_box(size=1.0)
        try:
            w._core.run(2**62)
        except ValueError as e:
            print("ValueError:", e)
        """
    )
    assert "a trajectory of 4611686018427387904 steps of 1 bodies needs" in out


@pytest.mark.parametrize(
    "call, needle",
    [
        ("generate.contact_lcp(2**40)", "needs"),
        ("generate.contact_lcp(4, k=2**40)", "at most 1024"),
        ("generate.spd_lcp(10**7)", "needs"),
        ("generate.p_matrix_lcp(2**40)", "needs"),
        ("generate.hard_corpus(0, 2**62)", "needs"),
        ("generate.hard_contact_lcp('many_contacts', k=2**40)", "at most 1024"),
    ],
)
def test_generator_sizes_are_checked(call, needle):
    out = _survives(
        f"""
        from lcpsim import generate
        try:
            {call}
        except ValueError as e:
            print("ValueError:", e)
        """
    )
    assert "ValueError:" in out and needle in out


def test_scene_sizes_are_checked():
    with pytest.raises(ValueError, match=r"box_stack \(100000 boxes.*needs .*TiB"):
        lcpsim.scenes.box_stack(100_000)
    with pytest.raises(ValueError, match=r"nx\*ny\*nz must be in \[1, 1000000\] bodies, got 1\.3\d*e36"):
        lcpsim.scenes.box_pile(nx=2**40, ny=2**40, nz=2**40)
    with pytest.raises(ValueError, match="cube_heap"):
        lcpsim.scenes.cube_heap(n=900_000)


def test_contact_layout_that_overflows_is_refused():
    with pytest.raises(ValueError, match="too large"):
        lcpsim.ContactLayout(2**62, 8)
    with pytest.raises(ValueError, match="nc must be a non-negative integer"):
        lcpsim.ContactLayout(2**64, 8)


@pytest.mark.parametrize(
    "name, needle",
    [
        ("hugehdr.npz", r"claims shape \(1000000, 1000000\) \(7.28 TiB\) but the file holds"),
        ("huge2.h5", r"dataset '/M' of shape \(200000, 200000\) needs 298 GiB"),
        ("ext.h5", "external link"),
    ],
)
def test_file_sizes_and_links_are_checked_before_reading(name, needle):
    with pytest.raises(LcpFileError, match=needle):
        load_lcp(REPROS / name)


def test_hdf5_external_storage_is_refused(tmp_path):
    import h5py

    raw = tmp_path / "raw.bin"
    np.eye(2).tofile(raw)
    path = tmp_path / "x.h5"
    with h5py.File(path, "w") as f:
        f.create_dataset("M", shape=(2, 2), dtype="f8", external=[(str(raw), 0, 32)])
        f["q"] = np.array([-1.0, -1.0])
    with pytest.raises(LcpFileError, match="outside the file"):
        load_lcp(path)


def test_a_valid_file_still_loads(tmp_path):
    M, q = np.array([[2.0, 1.0], [1.0, 2.0]]), np.array([-1.0, -1.0])
    for suffix in (".npz", ".h5"):
        p = lcpsim.io.save_lcp(tmp_path / f"x{suffix}", M, q)
        M2, q2 = load_lcp(p)
        np.testing.assert_array_equal(M2, M)
        np.testing.assert_array_equal(q2, q)
