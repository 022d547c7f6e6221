"""LCP corpora: capture round-trip (bit for bit), metadata, the loader, a run
killed mid-write leaves a readable file, `lcpsim solve FILE --index K`."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time

import h5py
import numpy as np
import pytest

import lcpsim
from lcpsim import _core, open_capture, scenes
from lcpsim.io.capture import CaptureError, CaptureWriter, is_capture, load_captured_lcp, load_record
from lcpsim.io import LcpFileError
from lcpsim.io import load_lcp as io_load_lcp

H = 1e-3


def drain_reference(scene: scenes.Scene, steps: int) -> dict:
    """The same LCPs captured in memory, without any file."""
    core = scene.world._core
    core.start_capture()
    core.run(steps)
    core.stop_capture()
    return core.drain_capture()


@pytest.fixture(scope="module")
def slope_corpus(tmp_path_factory):
    path = tmp_path_factory.mktemp("corpus") / "slope.h5"
    s = scenes.cube_on_slope(45.2, 1.0, cone_scale="dt")
    ref = scenes.cube_on_slope(45.2, 1.0, cone_scale="dt")
    traj = s.world.run(300, capture=path, chunk_steps=64)
    return path, traj, drain_reference(ref, 300)


def test_round_trip_is_bit_for_bit(slope_corpus):
    path, traj, ref = slope_corpus
    with open_capture(path) as c:
        assert len(c) == 300
        n = ref["n"]
        mo = np.concatenate([[0], np.cumsum(n * n)])
        vo = np.concatenate([[0], np.cumsum(n)])
        for i, rec in enumerate(c):
            assert rec.index == i and rec.n == n[i] == 40
            assert np.array_equal(rec.M.ravel(), ref["M"][mo[i] : mo[i + 1]])
            assert np.array_equal(rec.q, ref["q"][vo[i] : vo[i + 1]])
            assert np.array_equal(rec.z, ref["z"][vo[i] : vo[i + 1]])
            assert np.array_equal(rec.w, ref["w"][vo[i] : vo[i + 1]])
            assert rec.status == _core.STATUSES[ref["status"][i]] == "solved"
            assert rec.step == ref["step"][i] == i and rec.time == ref["time"][i]
            assert rec.scale == H and rec.contacts == 4 and rec.friction_dirs == 8
            assert rec.pivots == ref["pivots"][i] == traj.pivots[i] and rec.method == "lemke"
        # Random access agrees with iteration.
        a, b = c[123], list(c.records(123, 124))[0]
        assert np.array_equal(a.M, b.M) and np.array_equal(a.z, b.z)
        assert np.array_equal(c[-1].q, c[299].q)
        np.testing.assert_array_equal(c.step, np.arange(300))
        assert (c.status == "solved").all() and (c.n == 40).all() and (c.method == "lemke").all()


def test_records_solve_and_unscale(slope_corpus):
    path, traj, _ = slope_corpus
    with open_capture(path) as c:
        rec = c[150]
    # The stored z solves the stored (scaled) LCP, and solving it again agrees.
    assert lcpsim.lcp_residual(rec.M, rec.q, rec.z) < 1e-9
    again = lcpsim.solve_lcp(rec.M, rec.q)
    assert again.ok
    # Unscaled: D⁻¹ M D⁻¹ with D = diag(I, I, s I); λ back in physical units.
    M1, q1 = rec.unscaled()
    d = np.r_[np.ones(36), np.full(4, H)]
    np.testing.assert_allclose(M1 * d[:, None] * d[None, :], rec.M, rtol=1e-15, atol=0)
    z1 = rec.physical_z()
    np.testing.assert_allclose(z1[36:], rec.z[36:] * H)
    assert lcpsim.lcp_residual(M1, q1, z1) == pytest.approx(traj.residual[150], abs=1e-12)
    # Physical λ ≈ the sliding speed.
    assert z1[36:].max() == pytest.approx(np.linalg.norm(traj.velocities[150, 1, :3]), rel=1e-6)


def test_metadata(slope_corpus):
    path, _, _ = slope_corpus
    with open_capture(path) as c:
        assert c.metadata["scene"] == "cube_on_slope"
        assert c.metadata["scene_params"]["angle_deg"] == 45.2
        assert c.metadata["params"]["cone_scale"] == "dt" and c.metadata["method"] == "lemke"
        assert c.lcpsim_version == lcpsim.__version__ and c.format_version == 2 and c.created
        assert len(c.runs) == 1 and c.runs[0]["scene"] == "cube_on_slope" and (c.run == 0).all()
    with h5py.File(path, "r") as f:
        assert f.attrs["format"] == "lcpsim-corpus"
        assert json.loads(f.attrs["status_names"]) == list(lcpsim.STATUSES)
        assert f["data/M"].shape == (300 * 1600,) and f["index/n"].shape == (300,)


def test_loader_and_io(slope_corpus):
    path, _, _ = slope_corpus
    M, q = load_captured_lcp(path, 3)
    with open_capture(path) as c:
        assert np.array_equal(M, c[3].M) and np.array_equal(q, c[3].q)
    M2, q2 = io_load_lcp(path, 3)
    assert np.array_equal(M2, M) and np.array_equal(q2, q)
    assert load_record(path, -1).step == 299
    assert is_capture(path)
    with pytest.raises(LcpFileError, match="corpus of 300 problems"):
        io_load_lcp(path)
    with pytest.raises(LcpFileError, match="out of range"):
        io_load_lcp(path, 300)
    with pytest.raises(CaptureError, match="out of range"):
        load_captured_lcp(path, -301)


def test_not_a_corpus(tmp_path):
    p = tmp_path / "single.h5"
    lcpsim.io.save_lcp(p, np.eye(2), [-1.0, 1.0])
    assert not is_capture(p)
    with pytest.raises(CaptureError, match="not an lcpsim LCP corpus"):
        open_capture(p)
    with pytest.raises(LcpFileError, match="single LCP"):
        io_load_lcp(p, 0)
    junk = tmp_path / "junk.h5"
    junk.write_bytes(b"not hdf5 at all")
    assert not is_capture(junk)
    with pytest.raises(CaptureError):
        open_capture(junk)
    with pytest.raises(FileNotFoundError):
        open_capture(tmp_path / "missing.h5")


def test_writer_add_runs_and_small_chunks(tmp_path):
    p = tmp_path / "w.h5"
    with CaptureWriter(p, metadata={"experiment": "manual", "seed": 7}) as w:
        assert w.add(np.eye(3), [-1.0, 2.0, 0.5], status="solved", scale=0.5, step=4) == 0
        w.begin_run({"part": 2})
        w.add([[2.0]], [-1.0], z=[0.5], w=[0.0], status="ray_termination", pivots=3)
        with pytest.raises(CaptureError):
            w.add(np.eye(2), [1.0])
        with pytest.raises(CaptureError):
            w.add(np.eye(1), [1.0], status="bogus")
        assert len(w) == 2 and w.runs == 2
    with pytest.raises(CaptureError, match="closed"):
        w.add(np.eye(1), [1.0])
    with open_capture(p) as c:
        assert c.metadata == {"experiment": "manual", "seed": 7}
        assert [r["part"] for r in c.runs[1:]] == [2]
        a, b = c[0], c[1]
        assert a.n == 3 and np.isnan(a.z).all() and a.scale == 0.5 and a.step == 4 and a.run == 0
        assert b.status == "ray_termination" and b.pivots == 3 and b.run == 1 and b.z[0] == 0.5
        assert a.method == "custom"
    # Capture drained after every step still gives every LCP, in order.
    s = scenes.box_stack(2)
    traj = s.world.run(20, capture=tmp_path / "tiny.h5", chunk_bytes=1)
    assert s.world._core.captured_count() == 0 and not s.world._core.capturing
    with open_capture(tmp_path / "tiny.h5") as c:
        assert len(c) == 20 and c.step.tolist() == list(range(20))
        assert (c.n == traj.lcp_size).all()
    # One writer for two runs.
    with CaptureWriter(tmp_path / "two.h5", metadata={"study": "two"}) as w:
        s1, s2 = scenes.resting_cube(), scenes.pushed_cube(9.0, 1.0)
        s1.world.run(5, capture=w)
        s2.world.run(7, capture=w)
    with open_capture(tmp_path / "two.h5") as c:
        assert len(c) == 12 and c.run.tolist() == [0] * 5 + [1] * 7
        assert [r["scene"] for r in c.runs] == ["resting_cube", "pushed_cube"]


_WRITER = textwrap.dedent(
    """
    import os, signal, sys
    import numpy as np
    from lcpsim import scenes
    from lcpsim.io.capture import CaptureWriter
    path, mode = sys.argv[1], sys.argv[2]
    s = scenes.cube_on_slope(30.0, 0.5, cone_scale="dt")
    if mode == "abandon":
        w = CaptureWriter(path, metadata={"scene": "cube_on_slope", "mode": mode})
        w.begin_run({})
        core = s.world._core
        core.start_capture()
        for chunk in range(5):                  # 5 flushed chunks of 40 LCPs
            core.run(40)
            w.append(core.drain_capture())
            w.flush()
        core.run(40)                            # 40 more, written but never flushed
        w.append(core.drain_capture())
        os.kill(os.getpid(), signal.SIGKILL)    # no close, no atexit
    else:
        print("start", flush=True)
        s.world.run(10**7, capture=path, chunk_steps=100)
    """
)


def _writer(tmp_path, mode: str) -> tuple[subprocess.Popen, str]:
    script = tmp_path / "writer.py"
    script.write_text(_WRITER)
    path = str(tmp_path / f"{mode}.h5")
    p = subprocess.Popen([sys.executable, str(script), path, mode], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    return p, path


def _check_consistent(path: str, minimum: int) -> int:
    with open_capture(path) as c:
        count = len(c)
        assert count >= minimum
        assert c.metadata["scene"] == "cube_on_slope"
        np.testing.assert_array_equal(c.step, np.arange(count))
        for rec in c:
            assert rec.M.shape == (40, 40) and np.isfinite(rec.M).all() and np.isfinite(rec.z).all()
            assert rec.status == "solved" and lcpsim.lcp_residual(rec.M, rec.q, rec.z) < 1e-9
    return count


def test_killed_writer_leaves_a_readable_file(tmp_path):
    p, target = _writer(tmp_path, "abandon")
    _, err = p.communicate(timeout=120)
    assert p.returncode == -signal.SIGKILL, err.decode()
    # The data is in the documented partial file; the target was never created.
    path = target + ".partial"
    assert not os.path.exists(target)
    count = _check_consistent(path, 200)
    assert count <= 240  # everything up to the last flush (the unflushed 40 may or may not be there)
    # Plain h5py cannot open it (the writer never closed it), our reader can.
    assert is_capture(path)
    M, q = io_load_lcp(path, 199)
    assert M.shape == (40, 40)


def test_run_killed_from_outside_leaves_a_readable_file(tmp_path):
    p, path = _writer(tmp_path, "run")
    try:
        assert p.stdout is not None and p.stdout.readline().strip() == b"start"
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            time.sleep(0.05)
            try:
                with open_capture(path + ".partial") as c:
                    if len(c) >= 300:
                        break
            except (CaptureError, OSError, KeyError):
                pass
        os.kill(p.pid, signal.SIGKILL)
    finally:
        p.wait(timeout=60)
    assert not os.path.exists(path)
    _check_consistent(path + ".partial", 300)


@pytest.mark.slow
def test_cli_solve_index(slope_corpus):
    path, _, _ = slope_corpus
    from lcpsim.cli import main

    out = subprocess.run(
        [sys.executable, "-m", "lcpsim", "solve", str(path), "--index", "3", "--json"],
        capture_output=True, text=True, timeout=120,
    )
    assert out.returncode == 0, out.stderr
    d = json.loads(out.stdout)
    assert d["index"] == 3 and d["n"] == 40 and d["status"] == "solved"
    M, q = load_captured_lcp(path, 3)
    np.testing.assert_array_equal(d["z"], lcpsim.solve_lcp(M, q).z)
    assert main(["solve", str(path), "--index", "3"]) == 0
    assert main(["solve", str(path)]) == 2
    assert main(["solve", str(path), "--index", "300"]) == 2


def test_captured_scaled_lcp_is_d_m_d_of_the_unscaled_one():
    """Same state, two cone scales: M_s = D M_1 D and q_s = D q_1 with D = diag(I, I, s I)."""
    caps = {}
    for s in (1.0, 1e-3):
        sc = scenes.cube_on_slope(30.0, 0.5, speed=0.2, cone_scale=None if s == 1.0 else s)
        caps[s] = drain_reference(sc, 1)
    d = np.r_[np.ones(36), np.full(4, 1e-3)]
    M1, Ms = caps[1.0]["M"].reshape(40, 40), caps[1e-3]["M"].reshape(40, 40)
    np.testing.assert_allclose(Ms, d[:, None] * M1 * d[None, :], rtol=1e-14, atol=0)
    np.testing.assert_allclose(caps[1e-3]["q"], d * caps[1.0]["q"], rtol=1e-14, atol=0)
    # fn and fd agree; λ_scaled = λ / s.
    z1, zs = caps[1.0]["z"], caps[1e-3]["z"]
    np.testing.assert_allclose(zs[:36], z1[:36], rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(zs[36:] * 1e-3, z1[36:], rtol=1e-9)


def test_one_lcp_per_island_with_its_island(tmp_path):
    """Separate towers are separate islands, each captured as its own LCP."""
    path = tmp_path / "pile.h5"
    s = scenes.box_pile(2, 1, 2)
    traj = s.world.run(5, capture=path)
    with open_capture(path) as c:
        assert len(c) == 10 and (traj.islands == 2).all()
        assert c.island.tolist() == [0, 1] * 5 and c.step.tolist() == [0, 0, 1, 1, 2, 2, 3, 3, 4, 4]
        assert (c.n == 80).all() and [r.island for r in c] == [0, 1] * 5
        # The islands' LCPs add up to the step's.
        assert (c.n.reshape(5, 2).sum(axis=1) == traj.lcp_size).all()


def test_version_1_files_still_read(slope_corpus, tmp_path):
    """A version-1 corpus (no /index/island) reads, every LCP in island 0."""
    path, _, ref = slope_corpus
    old = tmp_path / "v1.h5"
    old.write_bytes(path.read_bytes())
    with h5py.File(old, "r+") as f:
        del f["index/island"]
        f.attrs["format_version"] = 1
    with open_capture(old) as c:
        assert c.format_version == 1 and len(c) == 300
        assert (c.island == 0).all() and c[7].island == 0
        assert np.array_equal(c[7].q, ref["q"][7 * 40 : 8 * 40])


def test_batches_in_the_old_layout_still_append(slope_corpus, tmp_path):
    """A batch drained by an older lcpsim says `iterations` where the compiled
    module now says `pivots`; the writer stores them as the same pivots."""
    _, traj, ref = slope_corpus
    old = {key: value for key, value in ref.items() if key != "pivots"}
    old["iterations"] = ref["pivots"]
    with CaptureWriter(tmp_path / "old.h5") as w:
        assert w.append(old) == 300
    with open_capture(tmp_path / "old.h5") as c:
        assert c.pivots.tolist() == traj.pivots.tolist() and (c.pivots > 0).any()
        assert np.array_equal(c[9].z, ref["z"][9 * 40 : 10 * 40])
