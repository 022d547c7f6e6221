"""FCLib local problems: file round trips, the faceted-LCP import, the
exact-cone residual on hand-built Coulomb solutions, export from the
simulator, and bad input."""

from __future__ import annotations

import json

import h5py
import numpy as np
import pytest

from lcpsim import faceting, scenes
from lcpsim.cli import main
from lcpsim.io import fclib
from lcpsim.io.fclib import FclibError, FclibLocal, FclibSolution
from lcpsim.io.capture import load_record


def _random_problem(nc: int = 3, seed: int = 0) -> FclibLocal:
    rng = np.random.default_rng(seed)
    J = rng.standard_normal((3 * nc, 4 * nc))
    W = J @ J.T
    W[np.abs(W) < 0.5] = 0.0  # some sparsity, still symmetric
    q = rng.standard_normal(3 * nc)
    sol = FclibSolution(u=rng.standard_normal(3 * nc), r=rng.standard_normal(3 * nc))
    guesses = [FclibSolution(u=rng.standard_normal(3 * nc), r=rng.standard_normal(3 * nc)) for _ in range(2)]
    return FclibLocal(
        W=W, q=q, mu=rng.uniform(0.1, 1.0, nc), title="random", description="a test", math_info="none",
        solution=sol, guesses=guesses,
    )


@pytest.mark.parametrize("storage", ["csc", "csr", "triplet"])
def test_round_trip_every_storage(tmp_path, storage):
    p = _random_problem()
    path = fclib.write_fclib(tmp_path / "p.hdf5", p, storage=storage)
    with h5py.File(path, "r") as f:
        nz = int(f["fclib_local/W/nz"][0])
    assert nz == {"csc": -1, "csr": -2}.get(storage, p.W.nnz)
    back = fclib.read_fclib(path)
    assert back.storage == storage
    np.testing.assert_array_equal(back.dense_W(), p.dense_W())
    for k in ("q", "mu"):
        np.testing.assert_array_equal(getattr(back, k), getattr(p, k))
    assert (back.title, back.description, back.math_info) == ("random", "a test", "none")
    np.testing.assert_array_equal(back.solution.u, p.solution.u)
    np.testing.assert_array_equal(back.solution.r, p.solution.r)
    assert len(back.guesses) == 2
    for g, h in zip(back.guesses, p.guesses):
        np.testing.assert_array_equal(g.r, h.r)
        np.testing.assert_array_equal(g.u, h.u)


# ---------------------------------------------------------------- exact-cone residual


def test_residual_zero_at_sticking_and_sliding_solutions():
    W = np.diag([2.0, 1.0, 1.0])
    mu = np.array([0.5])
    # Sticking: u = 0 needs r = −W⁻¹q = (1, −0.2, 0.1), inside the cone (‖r_T‖ = 0.22 ≤ 0.5).
    q = np.array([-2.0, 0.2, -0.1])
    r = np.array([1.0, -0.2, 0.1])
    np.testing.assert_allclose(W @ r + q, 0.0)
    assert faceting.exact_cone_residual(W, q, mu, r) == pytest.approx(0.0, abs=1e-15)
    # Sliding: q_T = (2, 0) is more than μ r_N can stop; r = (1, −0.5, 0), u = (0, 1.5, 0): friction opposes u_T.
    q = np.array([-2.0, 2.0, 0.0])
    r = np.array([1.0, -0.5, 0.0])
    u = W @ r + q
    np.testing.assert_allclose(u, [0.0, 1.5, 0.0])
    assert faceting.exact_cone_residual(W, q, mu, r) == pytest.approx(0.0, abs=1e-15)
    # Sliding diagonally: friction of full magnitude against the slip direction.
    q = np.array([-2.0, 3.0, 4.0])
    r = np.array([1.0, -0.3, -0.4])
    assert faceting.exact_cone_residual(W, q, mu, r) == pytest.approx(0.0, abs=1e-15)
    # Separating: q_N > 0, r = 0.
    assert faceting.exact_cone_residual(W, np.array([1.0, 5.0, 0.0]), mu, np.zeros(3)) == 0.0
    # Not solutions: friction not opposed to the slip, friction too weak, penetration.
    for bad in ([1.0, -0.4, -0.3], [1.0, -0.15, -0.2], [0.5, -0.15, -0.2]):
        assert faceting.exact_cone_residual(W, q, mu, np.array(bad)) > 1e-3


def test_faceted_answer_on_a_slip_between_facets_is_off_by_the_faceting_error():
    # One contact sliding at 22.5° from t1: k = 4 resists at a facet corner (wrong direction),
    # k = 8 puts 22.5° on an edge midpoint; k = 16 has a direction there: exact.
    W = np.eye(3)
    a = np.deg2rad(22.5)
    q = np.array([-1.0, 3 * np.cos(a), 3 * np.sin(a)])
    p = FclibLocal(W=W, q=q, mu=np.array([0.5]))
    res = {k: faceting.solve_fclib(p, k=k) for k in (4, 8, 16, 32)}
    assert all(r.ok for r in res.values())
    assert res[4].exact_residual > res[8].exact_residual > 1e-3
    assert res[16].exact_residual < 1e-12 and res[32].exact_residual < 1e-12
    # r is the LCP's impulse in FCLib order: normal first.
    assert res[16].r[0] == pytest.approx(1.0)
    np.testing.assert_allclose(res[16].r[1:], -0.5 * np.array([np.cos(a), np.sin(a)]), atol=1e-12)


# ---------------------------------------------------------------- LCP ↔ FCLib


def _first_lcp(world, tmp_path):
    world.run(1, capture=tmp_path / "first.h5")
    rec = load_record(tmp_path / "first.h5", 0)
    return rec.M, rec.q, rec.contacts, rec.friction_dirs, rec.scale, rec.z


@pytest.mark.parametrize("k,scale", [(4, None), (8, 1e-3), (6, 0.5)])
def test_simulator_lcp_round_trips_through_fclib(k, scale, tmp_path):
    s = scenes.cube_on_slope(25.0, 0.6, friction_dirs=k, cone_scale=scale)
    M, q, nc, kk, sc, z = _first_lcp(s.world, tmp_path)
    assert kk == k
    p = faceting.from_contact_lcp(M, q, nc, k, sc, z=z)
    back = faceting.to_lcp(p, k, sc)
    np.testing.assert_allclose(back.M, M, rtol=0, atol=1e-12 * np.abs(M).max())
    np.testing.assert_allclose(back.q, q, rtol=0, atol=1e-12 * np.abs(q).max())
    np.testing.assert_allclose(p.mu, 0.6)
    W = p.dense_W()
    np.testing.assert_allclose(W, W.T, atol=1e-12 * np.abs(W).max())
    assert np.all(np.linalg.eigvalsh(W) > -1e-12)
    # The simulator's answer, stored as guess 1, is the faceted LCP's answer in FCLib terms.
    g = p.guesses[0]
    np.testing.assert_allclose(g.u, p.W @ g.r + p.q)
    np.testing.assert_allclose(g.r, back.impulse(back.layout.unscale_z(z, sc)), atol=1e-15)


def test_k2_cannot_be_exported(tmp_path):
    s = scenes.cube_on_slope(10.0, 0.6, friction_dirs=2)
    M, q, nc, k, sc, _ = _first_lcp(s.world, tmp_path)
    with pytest.raises(FclibError, match="k ≥ 3"):
        faceting.from_contact_lcp(M, q, nc, k, sc)


def test_non_stewart_trinkle_matrix_is_refused(tmp_path):
    s = scenes.cube_on_slope(10.0, 0.6)
    M, q, nc, k, sc, _ = _first_lcp(s.world, tmp_path)
    M = M.copy()
    M[0, nc + 1] += 0.1 * np.abs(M).max()  # A01 no longer of the form W_nt Gᵀ
    with pytest.raises(FclibError, match="not a Stewart–Trinkle"):
        faceting.from_contact_lcp(M, q, nc, k, sc)


def _loaded_stack(steps: int, tmp_path):
    """A 3-box stack pushed at its bottom box by 0.97·μ·(3mg) at 20° from t1:
    Coulomb's cone holds it (it rests), the 4- and 8-facet cones do not."""
    s = scenes.box_stack(3, mu=0.5)
    a, F = np.deg2rad(20.0), 0.97 * 0.5 * 3 * 9.81
    s.world.apply_force(s.bodies[0], (F * np.cos(a), F * np.sin(a), 0.0))
    s.world.run(steps, fclib=tmp_path)
    return sorted(tmp_path.glob("*.hdf5"))


def test_resting_stack_exact_cone_residual_shrinks_with_k(tmp_path):
    files = _loaded_stack(1, tmp_path)
    assert [f.name for f in files] == ["step0000000-island000.hdf5"]
    p = fclib.read_fclib(files[0])
    assert p.nc == 12 and p.title.startswith("lcpsim box_stack")
    res = {k: faceting.solve_fclib(p, k=k) for k in (4, 8, 16, 32)}
    assert all(r.ok and r.residual < 1e-12 for r in res.values())
    e = {k: r.exact_residual for k, r in res.items()}
    assert e[4] > e[8] > 1e-4  # the load lies outside both polygons: they slide
    assert e[16] < 1e-10 and e[32] < 1e-10  # inside: the stack rests, as on the exact cone
    # The simulator's own k = 8 answer (guess 1) has the k = 8 error.
    assert faceting.exact_cone_residual(p.W, p.q, p.mu, p.guesses[0].r) == pytest.approx(e[8], rel=1e-6)
    # Scaling the cone does not change the answer.
    assert faceting.solve_fclib(p, k=8, scale=1e-4).exact_residual == pytest.approx(e[8], rel=1e-6)


def test_unloaded_resting_stack_is_exact_at_every_k(tmp_path):
    s = scenes.box_stack(3)
    s.world.run(3, fclib=tmp_path)
    p = fclib.read_fclib(sorted(tmp_path.glob("*.hdf5"))[-1])
    for k in (4, 8, 16):
        assert faceting.solve_fclib(p, k=k).exact_residual < 1e-12


def test_capture_export_matches_direct_export(tmp_path):
    s = scenes.box_stack(2)
    s.world.run(4, capture=tmp_path / "c.h5", fclib=tmp_path / "direct")
    paths = faceting.export_capture(tmp_path / "c.h5", tmp_path / "from_capture")
    assert [p.name for p in paths] == sorted(p.name for p in (tmp_path / "direct").glob("*.hdf5"))
    for p in paths:
        a, b = fclib.read_fclib(p), fclib.read_fclib(tmp_path / "direct" / p.name)
        np.testing.assert_array_equal(a.dense_W(), b.dense_W())
        np.testing.assert_array_equal(a.q, b.q)
        np.testing.assert_array_equal(a.guesses[0].r, b.guesses[0].r)


def test_format_1_capture_exports_too(tmp_path):
    s = scenes.box_stack(2)
    s.world.run(2, capture=tmp_path / "c.h5")
    with h5py.File(tmp_path / "c.h5", "r+") as f:
        del f["index/island"]
        f.attrs["format_version"] = 1
    paths = faceting.export_capture(tmp_path / "c.h5", tmp_path / "out")
    assert [p.name for p in paths] == ["step0000000-island000.hdf5", "step0000001-island000.hdf5"]
    p = fclib.read_fclib(paths[-1])
    assert p.nc == 8 and faceting.solve_fclib(p).ok


# ---------------------------------------------------------------- CLI


def test_cli_solve_export_and_simulate(tmp_path, capsys):
    assert main(["simulate", "box_stack", "--n", "2", "--steps", "3", "--capture", str(tmp_path / "c.h5"),
                 "--fclib", str(tmp_path / "sim"), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["fclib_files"] == 3
    assert main(["export-fclib", str(tmp_path / "c.h5"), "--out", str(tmp_path / "x"), "--index", "2"]) == 0
    capsys.readouterr()
    f = tmp_path / "x" / "step0000002-island000.hdf5"
    assert main(["solve", str(f), "--json", "--friction-dirs", "16", "--scale", "1e-3"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["format"] == "fclib" and out["k"] == 16 and out["scale"] == 1e-3 and out["ok"]
    assert out["residual"] < 1e-12 and 0 <= out["exact_residual"] < 1e-10
    assert main(["solve", str(f)]) == 0
    text = capsys.readouterr().out
    assert "exact-cone residual" in text and "LCP residual" in text
    assert main(["solve", str(f), "--friction-dirs", "1"]) == 2
    assert main(["solve", str(f), "--scale", "-1"]) == 2
    np.savez(tmp_path / "plain.npz", M=np.eye(2), q=-np.ones(2))
    assert main(["solve", str(tmp_path / "plain.npz"), "--friction-dirs", "4"]) == 2
    assert "FCLib files only" in capsys.readouterr().err


def _w_5x5(f):
    import scipy.sparse as sp

    del f["fclib_local/W"]
    fclib._write_matrix(f["fclib_local"].create_group("W"), sp.identity(5, format="csc"), "csc")


def _write_raw(path, mutate, storage="csr"):
    p = _random_problem(2)
    fclib.write_fclib(path, p, storage=storage)
    with h5py.File(path, "r+") as f:
        mutate(f)
    return path


@pytest.mark.parametrize(
    "name,mutate,needle",
    [
        ("global", lambda f: (f.move("fclib_local", "fclib_global")), "global problems"),
        ("not_fclib", lambda f: f.move("fclib_local", "something_else"), "not an FCLib file"),
        ("w_size", lambda f: (f["fclib_local/vectors"].pop("q"), f["fclib_local/vectors"].create_dataset("q", data=np.ones(5))), "/fclib_local/vectors/q"),
        ("w_not_3nc", _w_5x5, "/fclib_local/W has 5 rows, not a multiple of spacedim 3"),
        ("mu_negative", lambda f: f["fclib_local/vectors/mu"].__setitem__(0, -0.1), "/fclib_local/vectors/mu[0]"),
        ("nan", lambda f: f["fclib_local/vectors/q"].__setitem__(1, np.nan), "/fclib_local/vectors/q[1]"),
        ("nan_w", lambda f: f["fclib_local/W/x"].__setitem__(0, np.nan), "/fclib_local/W/x[0]"),
        ("csr_index", lambda f: f["fclib_local/W/i"].__setitem__(2, 99), "/fclib_local/W/i[2] = 99 is out of range"),
        ("missing", lambda f: f["fclib_local"].pop("W"), "/fclib_local/W is missing"),
    ],
)
def test_bad_input_names_the_dataset_and_exits_2(tmp_path, capsys, name, mutate, needle):
    path = _write_raw(tmp_path / f"{name}.hdf5", mutate)
    if name == "not_fclib":
        with pytest.raises(FclibError, match=needle):
            fclib.read_fclib(path)
        return  # `lcpsim solve` reads it as a plain HDF5 LCP file, which it isn't either (exit 2 too)
    with pytest.raises(FclibError) as e:
        fclib.read_fclib(path)
    assert needle in str(e.value)
    assert main(["solve", str(path)]) == 2
    err = capsys.readouterr().err
    assert needle in err and err.count("\n") == 1


@pytest.mark.parametrize(
    "storage,mutate,needle",
    [
        ("triplet", lambda f: f["fclib_local/W/p"].__setitem__(0, 6), "/fclib_local/W/p[0] = 6 is out of range: row indices"),
        ("triplet", lambda f: f["fclib_local/W/i"].__setitem__(1, -1), "/fclib_local/W/i[1] = -1 is out of range: column"),
        ("csc", lambda f: f["fclib_local/W/p"].__setitem__(1, 1000), "/fclib_local/W/p is not a pointer array"),
        ("csc", lambda f: f["fclib_local/W/nz"].__setitem__(0, -3), "/fclib_local/W/nz = -3"),
    ],
)
def test_bad_sparse_storage(tmp_path, capsys, storage, mutate, needle):
    path = _write_raw(tmp_path / "bad.hdf5", mutate, storage)
    assert main(["solve", str(path)]) == 2
    assert needle in capsys.readouterr().err


def test_not_fclib_file_through_cli_is_exit_2(tmp_path, capsys):
    path = tmp_path / "plain.hdf5"
    with h5py.File(path, "w") as f:
        f.create_dataset("something", data=[1.0])
    assert main(["solve", str(path)]) == 2
    assert main(["export-fclib", str(path), "--out", str(tmp_path / "o")]) == 2
    assert "not an lcpsim capture" in capsys.readouterr().err
