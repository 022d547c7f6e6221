"""Compatibility with the reference implementation, libfclib (FCLib 3.1.0,
Debian's libfclib-dev, installed by .ci/run): files lcpsim writes are read by
libfclib with identical arrays and pass its merit function on a known
solution; files libfclib writes are read and solved by lcpsim. libfclib runs
in a child process (tests/libfclib_ctypes.py) so that its HDF5 and h5py's
never share a process."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
import scipy.sparse as sp

from lcpsim import faceting
from lcpsim.io import fclib
from lcpsim.io.fclib import FclibLocal, FclibSolution

HELPER = Path(__file__).with_name("libfclib_ctypes.py")


def _helper(*args: str, stdin: str | None = None) -> str:
    out = subprocess.run([sys.executable, str(HELPER), *args], input=stdin, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    return out.stdout


def _available() -> bool:
    try:
        return json.loads(_helper("available"))
    except AssertionError:
        return False


pytestmark = pytest.mark.skipif(
    not _available(),
    reason="libfclib (Debian package libfclib-dev, FCLib 3.1.0) is not installed: apt-get install libfclib-dev",
)


def _coulomb_problem() -> tuple[FclibLocal, FclibSolution]:
    """Two independent contacts with a known Coulomb solution: one sticking, one sliding."""
    W = sp.block_diag([np.diag([2.0, 1.0, 1.0]), np.diag([1.0, 0.5, 0.5])]).tocsc()
    q = np.array([-2.0, 0.2, -0.1, -1.0, 3.0, 4.0])
    # Contact 0 sticks (u = 0); contact 1 slides: r_T = −μ r_N (3, 4)/5, u_T ∥ (3, 4).
    r = np.array([1.0, -0.2, 0.1, 1.0, -0.3, -0.4])
    p = FclibLocal(W=W, q=q, mu=np.array([0.5, 0.5]), title="two contacts", description="stick and slide", math_info="exact")
    return p, FclibSolution(u=W @ r + q, r=r)


def _libfclib_read(path: Path, solution: bool = False, guesses: bool = False) -> dict:
    args = ["read", str(path)] + (["--solution"] if solution else []) + (["--guesses"] if guesses else [])
    return json.loads(_helper(*args))


@pytest.mark.parametrize("storage", ["csc", "csr", "triplet"])
def test_lcpsim_file_read_by_libfclib_identically(tmp_path, storage):
    rng = np.random.default_rng(3)
    W = rng.standard_normal((9, 12)) @ rng.standard_normal((12, 9))  # not symmetric: rows and columns tell apart
    W[np.abs(W) < 1.0] = 0.0
    p = FclibLocal(W=W, q=rng.standard_normal(9), mu=rng.uniform(0.1, 1, 3), title="t", description="d", math_info="m")
    p.solution = FclibSolution(u=rng.standard_normal(9), r=rng.standard_normal(9))
    p.guesses = [FclibSolution(u=rng.standard_normal(9), r=rng.standard_normal(9))]
    path = fclib.write_fclib(tmp_path / "p.hdf5", p, storage=storage)
    c = _libfclib_read(path, solution=True, guesses=True)
    with h5py.File(path, "r") as f:
        stored = {k: f[f"fclib_local/W/{k}"][()] for k in ("p", "i", "x")}
    for k in ("p", "i", "x"):
        np.testing.assert_array_equal(c["W"][k], stored[k])
    assert c["spacedim"] == 3 and (c["W"]["m"], c["W"]["n"]) == (9, 9)
    cp, ci, cx = (np.asarray(c["W"][k]) for k in ("p", "i", "x"))
    if storage == "triplet":
        assert c["W"]["nz"] == c["W"]["nzmax"] == np.count_nonzero(W)
        dense = sp.coo_matrix((cx, (cp, ci)), shape=(9, 9)).toarray()  # FCLib triplets: p rows, i columns
    else:
        assert c["W"]["nz"] == fclib.STORAGES[storage]
        cls = sp.csc_matrix if storage == "csc" else sp.csr_matrix
        dense = cls((cx, ci, cp), shape=(9, 9)).toarray()
    np.testing.assert_array_equal(dense, W)
    np.testing.assert_array_equal(c["q"], p.q)
    np.testing.assert_array_equal(c["mu"], p.mu)
    assert c["info"] == {"title": "t", "description": "d", "math_info": "m"}
    np.testing.assert_array_equal(c["solution"]["u"], p.solution.u)
    np.testing.assert_array_equal(c["solution"]["r"], p.solution.r)
    np.testing.assert_array_equal(c["guesses"][0]["r"], p.guesses[0].r)
    np.testing.assert_array_equal(c["guesses"][0]["u"], p.guesses[0].u)


def test_lcpsim_file_passes_libfclib_merit_on_a_known_solution(tmp_path):
    p, sol = _coulomb_problem()
    wrong = FclibSolution(u=sol.u, r=sol.r * np.array([1, 1, 1, 1, -1, 1]))  # friction along the slip on contact 1
    p.solution, p.guesses = sol, [wrong]
    path = fclib.write_fclib(tmp_path / "known.hdf5", p)  # CSC: what libfclib's merit function multiplies with
    c = _libfclib_read(path, solution=True, guesses=True)
    assert c["solution_merit"] < 1e-15
    assert faceting.exact_cone_residual(p.W, p.q, p.mu, sol.r) < 1e-15
    # The wrong answer: libfclib and lcpsim agree on the number (libfclib divides by 1 + sqrt‖q‖).
    assert c["guess_merits"][0] > 0.1
    assert faceting.fclib_merit(p.W, p.q, p.mu, wrong.r) == pytest.approx(c["guess_merits"][0], rel=1e-13)


def test_simulator_export_read_by_libfclib_and_merit_agrees(tmp_path):
    from lcpsim import scenes

    s = scenes.box_stack(2)
    s.world.run(2, fclib=tmp_path)
    path = sorted(tmp_path.glob("*.hdf5"))[-1]
    p = fclib.read_fclib(path)
    c = _libfclib_read(path, guesses=True)
    np.testing.assert_array_equal(c["W"]["x"], p.W.data)
    np.testing.assert_array_equal(c["q"], p.q)
    np.testing.assert_array_equal(c["mu"], p.mu)
    assert c["guess_merits"][0] == pytest.approx(faceting.fclib_merit(p.W, p.q, p.mu, p.guesses[0].r), rel=1e-9, abs=1e-15)


@pytest.mark.parametrize("nz", [-1, -2, None])
def test_libfclib_file_read_and_solved_by_lcpsim(tmp_path, nz):
    p, sol = _coulomb_problem()
    W = p.W
    if nz is None:
        coo = sp.coo_matrix(W)
        mat = {"nzmax": int(coo.nnz), "m": 6, "n": 6, "nz": int(coo.nnz), "p": coo.row.tolist(), "i": coo.col.tolist(), "x": coo.data.tolist()}
    else:
        c = sp.csc_matrix(W) if nz == -1 else sp.csr_matrix(W)
        mat = {"nzmax": int(c.nnz), "m": 6, "n": 6, "nz": nz, "p": c.indptr.tolist(), "i": c.indices.tolist(), "x": c.data.tolist()}
    spec = {
        "spacedim": 3, "W": mat, "q": p.q.tolist(), "mu": p.mu.tolist(),
        "info": {"title": "from libfclib", "description": "C writer", "math_info": "known solution"},
        "solution": {"u": sol.u.tolist(), "r": sol.r.tolist()},
        "guesses": [{"u": sol.u.tolist(), "r": (0 * sol.r).tolist()}],
    }
    path = tmp_path / "c.hdf5"
    _helper("write", str(path), stdin=json.dumps(spec))
    back = fclib.read_fclib(path)
    assert back.storage == {-1: "csc", -2: "csr", None: "triplet"}[nz]
    np.testing.assert_array_equal(back.dense_W(), W.toarray())
    np.testing.assert_array_equal(back.q, p.q)
    np.testing.assert_array_equal(back.mu, p.mu)
    assert (back.title, back.description, back.math_info) == ("from libfclib", "C writer", "known solution")
    np.testing.assert_array_equal(back.solution.r, sol.r)
    np.testing.assert_array_equal(back.guesses[0].r, 0 * sol.r)
    # Solved: contact 1 slides along (3, 4), between the facets of k = 8, on the facet d_… of none;
    # the exact-cone residual is that of the faceting and vanishes for the sticking contact.
    ans = faceting.solve_fclib(back, k=8)
    assert ans.ok and ans.residual < 1e-12
    np.testing.assert_allclose(ans.r[:3], sol.r[:3], atol=1e-12)
    assert 1e-4 < ans.exact_residual < 0.2
    assert faceting.solve_fclib(back, k=64).exact_residual < ans.exact_residual
