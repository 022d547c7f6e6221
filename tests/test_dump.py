"""Failure forensics: solve_lcp(dump=DIR) writes a dump of every
failure; `lcpsim solve DUMP` and lcpsim.io.forensics.replay reproduce it."""

from __future__ import annotations

import json
import os

import h5py
import numpy as np
import pytest

import lcpsim
from lcpsim import solve_lcp
from lcpsim.cli import main
from lcpsim.io.dump import DUMP_FORMAT, TRACE_FIELDS, load_dump, variable_name
from lcpsim.io.forensics import replay
from lcpsim.generate import hard_corpus, spd_lcp
from lcpsim.io import is_dump, load_lcp


def classic_failure():
    """The first hard LCP (s = 1e-4, n ≤ 60) on which classic Lemke fails with z ≠ 0."""
    for p in hard_corpus(0, 60, 1e-4):
        if p.n <= 60:
            r = solve_lcp(p.M, p.q, pivoting="classic")
            if not r.ok and r.pivots > 1 and np.abs(r.z).max() > 0:
                return p
    raise AssertionError("classic Lemke solves the whole hard corpus")  # pragma: no cover


def _failures():
    spd = spd_lcp(20, seed=1)
    hard = classic_failure()
    return {
        "max_pivots": (spd.M, spd.q, dict(max_pivots=1)),
        "ray_termination": (np.array([[1.0, -1.0], [-1.0, 1.0]]), np.array([-1.0, -1.0]), {}),
        "classic": (hard.M, hard.q, dict(pivoting="classic", piv_tol=1e-12, zero_tol=1e-6)),
        "pgs": (spd.M, spd.q, dict(method="pgs", max_iterations=3)),
    }


@pytest.mark.parametrize("case", ["max_pivots", "ray_termination", "classic", "pgs"])
def test_dump_holds_everything_and_replays(tmp_path, case):
    M, q, kw = _failures()[case]
    res = solve_lcp(M, q, dump=tmp_path, **kw)
    assert not res.ok and res.dump_path is not None and os.path.isfile(res.dump_path)
    assert os.path.dirname(res.dump_path) == str(tmp_path) and res.status in os.path.basename(res.dump_path)
    assert is_dump(res.dump_path)
    lemke = kw.get("method", "lemke") == "lemke"
    with h5py.File(res.dump_path, "r") as f:
        assert f.attrs["format"] == DUMP_FORMAT and f.attrs["lcpsim_version"] == lcpsim.__version__
        assert f.attrs["status"] == res.status and f.attrs["method"] == kw.get("method", "lemke")
        opts = json.loads(f.attrs["options"])
        for k, v in kw.items():
            if k != "method":
                assert opts[k] == v
        for k in ("M", "q", "z", "w"):
            assert k in f
        np.testing.assert_array_equal(f["M"][()], M)
        np.testing.assert_array_equal(f["z"][()], res.z)
        assert f.attrs["residual"] == res.residual and f.attrs["pivots"] == res.pivots
        assert ("trace" in f) == lemke
        if lemke:
            lengths = {len(f["trace"][k]) for k in TRACE_FIELDS}
            assert len(lengths) == 1 and f.attrs["trace_status"] == res.status
    d = load_dump(res.dump_path)
    assert d.status == res.status and np.array_equal(d.q, q) and d.n == len(q)
    if lemke:
        n = d.n
        t = d.trace
        assert t is not None
        if case == "max_pivots":
            assert len(t["rung"]) == res.pivots == 1
        assert ((t["entering"] >= 0) & (t["entering"] <= 2 * n)).all() and ((t["leaving"] <= 2 * n)).all()
        assert "pivot trace" in d.trace_summary()
    # load_lcp reads a dump like any LCP file.
    M2, q2 = load_lcp(res.dump_path)
    assert np.array_equal(M2, M) and np.array_equal(q2, q)
    rep = replay(res.dump_path)
    assert rep.reproduced and rep.same_status and rep.same_z and not rep.overridden
    assert rep.result.status == res.status and np.array_equal(rep.result.z, res.z)


def test_classic_failure_trace_and_nonzero_z(tmp_path):
    M, q, kw = _failures()["classic"]
    res = solve_lcp(M, q, dump=tmp_path, **kw)
    d = load_dump(res.dump_path)
    assert not res.ok and np.abs(d.z).max() > 0
    assert len(d.trace["rung"]) == res.pivots > 0
    assert (d.trace["entering"] == 2 * d.n).sum() == 1  # z0 enters once, first
    assert d.trace["entering"][0] == 2 * d.n


def test_solved_writes_no_dump(tmp_path):
    p = spd_lcp(10, seed=0)
    res = solve_lcp(p.M, p.q, dump=tmp_path / "sub")
    assert res.ok and res.dump_path is None and not (tmp_path / "sub").exists()


def test_dump_directory_must_be_a_directory(tmp_path):
    f = tmp_path / "file"
    f.write_text("x")
    p = spd_lcp(10, seed=0)
    with pytest.raises(ValueError, match="not a directory"):
        solve_lcp(p.M, p.q, max_pivots=1, dump=f)


def test_cli_replays_dump(tmp_path, capsys):
    M, q, kw = _failures()["classic"]
    res = solve_lcp(M, q, dump=tmp_path, **kw)
    assert main(["solve", res.dump_path]) == 1
    out = capsys.readouterr().out
    assert f"reproduces the dump (status '{res.status}', z identical)" in out and "pivot trace:" in out
    assert main(["solve", res.dump_path, "--json"]) == 1
    j = json.loads(capsys.readouterr().out)
    assert j["status"] == res.status and j["replay"]["reproduced"] and j["pivoting"] == "classic"
    assert np.array_equal(np.array(j["z"]), res.z)
    # Overridden options: the robust rule solves it, and says the options changed.
    assert main(["solve", res.dump_path, "--pivoting", "lexicographic", "--certify"]) == 0
    out = capsys.readouterr().out
    assert "with changed options: status 'solved'" in out and "certified:" in out


def test_cli_solve_dump_flag(tmp_path, capsys):
    p = spd_lcp(20, seed=1)
    path = tmp_path / "lcp.npz"
    lcpsim.io.save_lcp(path, p.M, p.q)
    assert main(["solve", str(path), "--max-pivots", "1", "--dump", str(tmp_path / "d"), "--json"]) == 1
    j = json.loads(capsys.readouterr().out)
    assert j["dump_path"] and is_dump(j["dump_path"])
    assert main(["solve", j["dump_path"], "--index", "0"]) == 2
    assert "does not apply" in capsys.readouterr().err


def test_variable_names():
    assert [variable_name(i, 3) for i in (0, 2, 3, 5, 6)] == ["w[0]", "w[2]", "z[0]", "z[2]", "z0"]
    assert not is_dump(os.devnull)
