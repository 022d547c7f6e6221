"""solve_lcp_batch equals solve_lcp on each problem, releases the GIL, and
validates its input like solve_lcp."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from lcpsim import LcpBatchResult, LcpResult, solve_lcp, solve_lcp_batch
from lcpsim.examples import cube_on_slope_lcp


def _random_problems(b, n, seed):
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((b, n, n))
    Ms = A @ A.transpose(0, 2, 1) + 0.1 * np.eye(n)
    qs = rng.standard_normal((b, n))
    return Ms, qs


def _assert_same(r: LcpResult, s: LcpResult):
    assert r.status == s.status
    assert r.ok == s.ok
    assert r.pivots == s.pivots
    np.testing.assert_array_equal(r.z, s.z)
    np.testing.assert_array_equal(r.w, s.w)
    assert r.residual == s.residual
    assert r.min_z == s.min_z and r.min_w == s.min_w
    assert r.max_complementarity == s.max_complementarity
    assert r.method == s.method
    if r.basis is None:
        assert s.basis is None
    else:
        np.testing.assert_array_equal(r.basis, s.basis)


@pytest.mark.parametrize(
    "method, kwargs",
    [
        ("lemke", {}),
        ("lemke", {"pivoting": "classic"}),
        ("pgs", {"max_iterations": 200}),
        ("newton_fb", {}),
    ],
)
@pytest.mark.parametrize("threads", [1, 2, 0])
def test_batch_equals_per_call(method, kwargs, threads):
    Ms, qs = _random_problems(12, 6, seed=7)
    batch = solve_lcp_batch(Ms, qs, method=method, threads=threads, **kwargs)
    assert isinstance(batch, LcpBatchResult)
    assert len(batch) == 12
    assert batch.z.shape == (12, 6) and batch.w.shape == (12, 6)
    assert batch.pivots.shape == (12,) and batch.residual.shape == (12,)
    assert batch.ok.dtype == np.bool_
    for i, r in enumerate(batch):
        _assert_same(r, solve_lcp(Ms[i], qs[i], method=method, **kwargs))
    assert sum(batch.by_status.values()) == 12


def test_batch_of_contact_lcps_equals_per_call():
    lcps = [cube_on_slope_lcp(th, 0.5, s=s) for th in (0.0, 20.0, 30.0) for s in (1.0, 1e-3)]
    Ms = np.stack([c.M for c in lcps])
    qs = np.stack([c.q for c in lcps])
    batch = solve_lcp_batch(Ms, qs)
    for i, c in enumerate(lcps):
        _assert_same(batch[i], solve_lcp(c.M, c.q))
    assert batch[-1].status == batch.status[-1]


def test_batch_indexing():
    Ms, qs = _random_problems(3, 4, seed=1)
    batch = solve_lcp_batch(Ms, qs)
    assert batch[-1].status == batch.status[2]
    with pytest.raises(IndexError):
        batch[3]


def test_empty_batch():
    batch = solve_lcp_batch(np.zeros((0, 3, 3)), np.zeros((0, 3)))
    assert len(batch) == 0
    assert batch.z.shape == (0, 3)


def test_batch_accepts_int_and_fortran():
    Ms, qs = _random_problems(4, 3, seed=2)
    Mi = np.round(Ms * 10).astype(np.int64)
    qi = np.round(qs * 10).astype(np.int32)
    b1 = solve_lcp_batch(np.asfortranarray(Mi), qi)
    b2 = solve_lcp_batch(Mi.astype(float), qi.astype(float))
    np.testing.assert_array_equal(b1.z, b2.z)


@pytest.mark.parametrize(
    "Ms, qs, parts",
    [
        (np.ones((2, 3, 3)), np.ones((3, 3)), ["Ms", "qs", "(2, 3, 3)", "(3, 3)"]),
        (np.ones((2, 3, 4)), np.ones((2, 3)), ["square", "(3, 4)"]),
        (np.ones((2, 3, 3)), np.ones((2, 4)), ["q", "length 4"]),
        (np.ones((3, 3)), np.ones((3,)), ["Ms", "3-D", "(3, 3)"]),
        (np.ones((2, 3, 3)), np.ones((2, 3, 1)), ["qs", "2-D"]),
        (np.where(np.arange(18).reshape(2, 3, 3) == 13, np.nan, 1.0), np.ones((2, 3)), ["problem 1", "M[1, 1]", "nan"]),
        (np.ones((2, 3, 3)), np.array([[1.0, 1.0, 1.0], [1.0, np.inf, 1.0]]), ["problem 1", "q[1]", "inf"]),
    ],
)
def test_batch_invalid_input(Ms, qs, parts):
    with pytest.raises(ValueError) as info:
        solve_lcp_batch(Ms, qs)
    for p in parts:
        assert p in str(info.value), (p, str(info.value))


@pytest.mark.parametrize("threads", [-1, 1.5, "2", True])
def test_batch_invalid_threads(threads):
    with pytest.raises(ValueError, match="threads"):
        solve_lcp_batch(np.ones((1, 1, 1)), np.ones((1, 1)), threads=threads)


def test_batch_invalid_options():
    with pytest.raises(ValueError, match="piv_tol"):
        solve_lcp_batch(np.ones((1, 1, 1)), np.ones((1, 1)), piv_tol=-1.0)
    with pytest.raises(ValueError, match="unknown method"):
        solve_lcp_batch(np.ones((1, 1, 1)), np.ones((1, 1)), method="x")


@pytest.mark.slow
def test_batch_releases_the_gil():
    # While a long batch runs, another Python thread must keep making progress.
    # Only ticks made during the batch count: with the GIL held they would be
    # 0–2 whatever the machine's load; released, a thread that only yields
    # makes thousands even on a busy machine.
    Ms, qs = _random_problems(1200, 60, seed=3)
    ticks = 0
    done = threading.Event()

    def counter():
        nonlocal ticks
        while not done.is_set():
            ticks += 1
            time.sleep(0)

    t = threading.Thread(target=counter)
    t.start()
    try:
        before = ticks
        t0 = time.perf_counter()
        solve_lcp_batch(Ms, qs)
        elapsed = time.perf_counter() - t0
        during = ticks - before
    finally:
        done.set()
        t.join()
    if elapsed < 0.02:
        pytest.skip(f"batch too fast ({elapsed:.4f} s) to observe GIL release")
    assert during > 10, f"only {during} ticks in {elapsed:.3f} s: the GIL was held"
