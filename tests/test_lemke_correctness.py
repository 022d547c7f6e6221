"""Lemke's answers checked independently: every `solved` result is verified by
recomputing w = M z + q with numpy (conftest.check_solution), small problems
are compared to a brute-force enumeration of complementary bases, problems
without a solution must never come back `solved`."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, note
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from scipy.optimize import linprog

from conftest import check_solution, enumerate_solutions
from lcpsim import solve_lcp
from lcpsim.examples import cube_on_slope_lcp

# No subnormal entries: with q = (−5e-324) and M = (2) the answer z = 2.5e-324 is not representable, and
# neither neighbour (0 or 5e-324) meets a tolerance relative to ‖q‖, so "numerical" is then the honest status.
unit = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False, allow_subnormal=False, width=64)
# Entries of a well-scaled matrix: 0 or 1e-3 ≤ |x| ≤ 1 (no 1e-300 that overflows z).
scaled = st.one_of(st.just(0.0), st.floats(1e-3, 1.0), st.floats(-1.0, -1e-3))
# q entries with exact zeros and repeated values on purpose (degeneracy).
q_entry = st.one_of(unit, st.sampled_from([0.0, -1.0, 1.0, -0.5]))


@st.composite
def p_matrix_lcp(draw, max_n: int = 8):
    """A positive-definite (hence P-) matrix M = B Bᵀ + (S − Sᵀ) + δI and a q:
    the LCP has exactly one solution."""
    n = draw(st.integers(1, max_n))
    B = draw(hnp.arrays(np.float64, (n, n), elements=scaled))
    S = draw(hnp.arrays(np.float64, (n, n), elements=scaled))
    delta = draw(st.floats(0.05, 2.0))
    M = B @ B.T + (S - S.T) + delta * np.eye(n)
    q = draw(hnp.arrays(np.float64, (n,), elements=q_entry))
    return M, q


@st.composite
def psd_feasible_lcp(draw, max_n: int = 8):
    """A positive-semidefinite, possibly singular M = B Bᵀ + (S − Sᵀ) with
    repeated rows, and q = w* − M z* built from a complementary pair (z*, w*)
    with zeros in both (degenerate): Lemke must solve it."""
    n = draw(st.integers(1, max_n))
    r = draw(st.integers(1, n))
    B = draw(hnp.arrays(np.float64, (n, r), elements=scaled))
    if n >= 2 and draw(st.booleans()):
        B[n - 1] = B[0]  # a repeated row (and column) of M
    S = draw(hnp.arrays(np.float64, (n, n), elements=scaled)) * draw(st.sampled_from([0.0, 1.0]))
    M = B @ B.T + (S - S.T)
    kind = draw(hnp.arrays(np.int8, (n,), elements=st.integers(0, 2)))  # 0: both zero, 1: z > 0, 2: w > 0
    mag = draw(hnp.arrays(np.float64, (n,), elements=st.floats(0.1, 2.0)))
    z_star = np.where(kind == 1, mag, 0.0)
    w_star = np.where(kind == 2, mag, 0.0)
    q = w_star - M @ z_star
    return M, q


# ---------------------------------------------------------------- properties


def assert_solved_and_verified(M, q, kind: str) -> None:
    """Lemke solves the LCP and its z passes the independent check."""
    res = solve_lcp(M, q)
    note(f"status={res.status} pivots={res.pivots} z={res.z}")
    assert res.ok, f"{kind} not solved: {res.status}"
    check_solution(M, q, res.z)


@given(p_matrix_lcp())
def test_p_matrix_solved_and_verified(data):
    assert_solved_and_verified(*data, "P-matrix LCP")


@given(p_matrix_lcp(max_n=8))
def test_p_matrix_matches_enumeration(data):
    M, q = data
    sols = enumerate_solutions(M, q)
    assume(len(sols) == 1)  # unique for a P-matrix, unless conditioning hid it
    res = solve_lcp(M, q)
    assert res.ok, res.status
    np.testing.assert_allclose(res.z, sols[0], rtol=1e-7, atol=1e-8 * (1 + np.abs(sols[0]).max()))


@given(psd_feasible_lcp())
def test_degenerate_psd_feasible_solved(data):
    assert_solved_and_verified(*data, "solvable copositive-plus LCP")


@given(st.integers(1, 6).flatmap(lambda n: st.tuples(
    hnp.arrays(np.float64, (n, n), elements=unit), hnp.arrays(np.float64, (n,), elements=q_entry))))
def test_general_matrix_never_lies(data):
    """Any M: Lemke may fail, but a `solved` must be a solution."""
    M, q = data
    for pivoting in ("lexicographic", "classic"):
        res = solve_lcp(M, q, pivoting=pivoting)
        assert res.z.shape == q.shape and res.w.shape == q.shape
        if res.ok and pivoting == "lexicographic":
            check_solution(M, q, res.z)
        if res.ok and pivoting == "classic":  # the source note's scheme trusts a 1e-6 user zero
            check_solution(M, q, res.z, rel=1e-5)


def _lp_feasible_with_margin(M, q, margin: float) -> bool:
    """Is {z ≥ 0 : M z + q ≥ margin} non-empty? (scipy's LP, independent of lcpsim)"""
    n = q.shape[0]
    r = linprog(np.zeros(n), A_ub=-M, b_ub=q - margin, bounds=[(0, None)] * n, method="highs")
    return r.status == 0


@given(st.integers(1, 6).flatmap(lambda n: st.tuples(
    st.integers(1, n).flatmap(lambda r: hnp.arrays(np.float64, (n, r), elements=scaled)),
    hnp.arrays(np.float64, (n,), elements=q_entry))))
def test_psd_ray_termination_only_when_infeasible(data):
    """For positive-semidefinite M, Lemke ends solved iff the LCP is feasible;
    a ray is a certificate of infeasibility, checked here by an LP (a problem
    feasible with a clear margin must never end in a ray)."""
    B, q = data
    M = B @ B.T
    res = solve_lcp(M, q)
    if res.ok:
        check_solution(M, q, res.z)
    else:
        assert res.status == "ray_termination", res.status
        assert not _lp_feasible_with_margin(M, q, 1e-6 * (1 + np.abs(q).max())), \
            "ray_termination on a feasible PSD LCP"


@pytest.mark.parametrize("method", ["lemke", "pgs", "newton_fb"])
@pytest.mark.parametrize("pivoting", ["lexicographic", "classic"])
@pytest.mark.parametrize("q0", [2.2250738585e-313, -2.2250738585e-313, 1e-300, 5e-324])
def test_tiny_q_does_not_break_the_solver(q0, pivoting, method):
    """Regression: a subnormal q made the equilibration's q-normalization
    overflow (1/‖q‖ = inf) and Lemke panic. Any tiny q must give a status."""
    kw = {"pivoting": pivoting} if method == "lemke" else {}
    for M in ([[0.0]], [[1.0]], [[1.0, 0.0], [0.0, 2.0]]):
        q = np.full(len(M), q0)
        res = solve_lcp(M, q, method=method, **kw)
        assert res.z.shape == q.shape
        if res.ok:
            check_solution(M, q, res.z)


# ---------------------------------------------------------------- infeasible


@pytest.mark.parametrize("pivoting", ["lexicographic", "classic"])
@pytest.mark.parametrize(
    "M, q",
    [
        ([[-1.0]], [-1.0]),  # w = −z − 1 < 0
        ([[0.0]], [-1.0]),  # w = −1
        ([[0.0, 1.0], [-1.0, 0.0]], [-1.0, -1.0]),  # skew (copositive-plus): w2 = −z1 − 1 < 0
        ([[1.0, -1.0], [-1.0, 1.0]], [-1.0, -1.0]),  # PSD: w1 + w2 = −2 < 0
    ],
    ids=["minus-one", "zero", "skew", "psd"],
)
def test_infeasible_reports_ray_termination(M, q, pivoting):
    res = solve_lcp(M, q, pivoting=pivoting)
    assert not res.ok
    assert res.status != "solved"
    assert res.status == "ray_termination"
    assert res.z.shape == (len(q),) and res.w.shape == (len(q),)


# ---------------------------------------------------------------- peers' failures


@pytest.mark.parametrize("pivoting", ["lexicographic", "classic"])
def test_dart_803_one_dimensional(pivoting):
    """DART #803: Lemke failed the 1-D LCP M = [1], q = [-9.8]."""
    res = solve_lcp([[1.0]], [-9.8], pivoting=pivoting)
    assert res.ok
    np.testing.assert_allclose(res.z, [9.8], rtol=1e-14)
    check_solution([[1.0]], [-9.8], res.z)
    res = solve_lcp([[1.0]], [2.0], pivoting=pivoting)  # q ≥ 0: z = 0
    assert res.ok and res.z[0] == 0.0
    res = solve_lcp([[2.0]], [0.0], pivoting=pivoting)  # degenerate q = 0
    assert res.ok and res.z[0] == 0.0
    assert not solve_lcp([[-2.0]], [-9.8], pivoting=pivoting).ok


@pytest.mark.parametrize("pivoting", ["lexicographic", "classic"])
def test_lcpsolve_3_two_by_two_pd(pivoting):
    """LCPSolve #3: z = 0 returned for this positive-definite 2×2 LCP."""
    M = np.array([[2.57023, -0.580137], [-0.580137, 2.59027]])
    q = np.array([-0.938699, -0.938699])
    res = solve_lcp(M, q, pivoting=pivoting)
    assert res.ok
    check_solution(M, q, res.z)
    np.testing.assert_allclose(res.z, np.linalg.solve(M, -q), rtol=1e-10)


def test_quantecon_768_spd_n10():
    """QuantEcon #768: lcp_lemke returned z with a negative entry."""
    rng = np.random.RandomState(0)
    A = rng.standard_normal((10, 10))
    M = A.T @ A + np.eye(10)
    q = rng.standard_normal(10)
    res = solve_lcp(M, q)
    assert res.ok
    assert res.z.min() >= 0.0
    check_solution(M, q, res.z)
    sols = enumerate_solutions(M, q)
    assert len(sols) == 1
    np.testing.assert_allclose(res.z, sols[0], atol=1e-9)


# ---------------------------------------------------------------- structured


def murty(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Murty's example: 1 on the diagonal, 2 below, q = −1; solution e₁."""
    return np.tril(2.0 * np.ones((n, n)), -1) + np.eye(n), -np.ones(n)


@pytest.mark.parametrize("n", [1, 2, 5, 8, 16, 30])
@pytest.mark.parametrize("transpose", [False, True], ids=["lower", "upper"])
def test_murty(n, transpose):
    M, q = murty(n)
    if transpose:
        M = M.T  # the same problem with the indices reversed: solution e_n
    res = solve_lcp(M, q, max_pivots=2 ** min(n + 1, 20))
    assert res.ok, res.status
    check_solution(M, q, res.z)
    expected = np.zeros(n)
    expected[-1 if transpose else 0] = 1.0
    np.testing.assert_allclose(res.z, expected, atol=1e-12)
    if n <= 8:
        sols = enumerate_solutions(M, q)
        assert len(sols) == 1 and np.allclose(sols[0], expected)


def test_zero_q_gives_zero():
    M, _ = murty(5)
    res = solve_lcp(M, np.zeros(5))
    assert res.ok
    np.testing.assert_array_equal(res.z, np.zeros(5))


@pytest.mark.parametrize("pivoting", ["lexicographic", "classic"])
def test_repeated_rows(pivoting):
    """M = [[1, 1], [1, 1]], q = [−1, −1]: a line of solutions z1 + z2 = 1."""
    M = np.array([[1.0, 1.0], [1.0, 1.0]])
    q = np.array([-1.0, -1.0])
    res = solve_lcp(M, q, pivoting=pivoting)
    assert res.ok, res.status
    check_solution(M, q, res.z)
    assert res.z.sum() == pytest.approx(1.0, abs=1e-12)


def test_repeated_rows_larger():
    """Three identical rows plus a PD block; q with zeros."""
    M = np.array([
        [2.0, 1.0, 1.0, 1.0, 0.0],
        [2.0, 1.0, 1.0, 1.0, 0.0],
        [2.0, 1.0, 1.0, 1.0, 0.0],
        [1.0, 0.0, 0.0, 3.0, 1.0],
        [0.0, 1.0, 0.0, 1.0, 2.0],
    ])
    M = M @ M.T  # PSD with repeated rows and columns
    q = np.array([-1.0, -1.0, -1.0, 0.0, 0.5])
    res = solve_lcp(M, q)
    assert res.ok, res.status
    check_solution(M, q, res.z)


@pytest.mark.parametrize("s", [1.0, 1e-1, 1e-3, 1e-6])
@pytest.mark.parametrize("theta, mu", [(0.0, 0.5), (20.0, 0.5), (30.0, 0.5), (45.2, 1.0), (45.0001, 1.0), (60.0, 0.3)])
@pytest.mark.parametrize("k", [4, 8])
def test_contact_lcps_solved_at_every_scale(theta, mu, s, k):
    """The λ rows have q = 0 (the degeneracy that makes exact-equality tie
    breaking report false rays). The default Lemke must solve every one."""
    c = cube_on_slope_lcp(theta, mu, k=k, s=s)
    res = solve_lcp(c.M, c.q)
    assert res.ok, f"{res.status} after {res.pivots} pivots"
    check_solution(c.M, c.q, res.z)
    fn, fd, lam = c.split(res.z)
    # Momentum balance along the normal: the cube ends the step at rest in z.
    assert fn.sum() == pytest.approx(c.mass * 9.81 * np.cos(np.deg2rad(theta)) * c.h, rel=1e-9)


@pytest.mark.parametrize("theta", [0.0, 10.0, 20.0, 26.0])
def test_contact_sticking_friction_exact(theta):
    """tan θ < μ = 0.5: static friction balances gravity exactly, λ = 0."""
    c = cube_on_slope_lcp(theta, 0.5)
    res = solve_lcp(c.M, c.q)
    assert res.ok
    fn, fd, lam = c.split(res.z)
    ang = 2 * np.pi * np.arange(c.k) / c.k
    fx = fd.sum(axis=0) @ np.cos(ang)
    fy = fd.sum(axis=0) @ np.sin(ang)
    mgh = c.mass * 9.81 * c.h
    assert fx == pytest.approx(-mgh * np.sin(np.deg2rad(theta)), abs=1e-12)
    assert fy == pytest.approx(0.0, abs=1e-12)
    assert np.all(lam <= 1e-12)


@pytest.mark.parametrize("s", [1.0, 1e-3, 1e-6])
def test_contact_sliding_scale_invariance(s):
    """30°, μ = 0.5 slides: friction = μ·fn, λ = sliding speed / s; fn and fd
    do not depend on the scale s."""
    ref = cube_on_slope_lcp(30.0, 0.5)
    c = cube_on_slope_lcp(30.0, 0.5, s=s)
    r0 = solve_lcp(ref.M, ref.q)
    r = solve_lcp(c.M, c.q)
    assert r0.ok and r.ok
    fn0, fd0, lam0 = ref.split(r0.z)
    fn, fd, lam = c.split(r.z)
    np.testing.assert_allclose(fn.sum(), fn0.sum(), rtol=1e-12)
    np.testing.assert_allclose(fd.sum(), fd0.sum(), rtol=1e-9)
    speed = 9.81 * (np.sin(np.deg2rad(30)) - 0.5 * np.cos(np.deg2rad(30))) * c.h
    np.testing.assert_allclose(lam.max() * s, speed, rtol=1e-9)


# ---------------------------------------------------------------- conformance matrix


DATASETS = {
    "spd10": (lambda r: (lambda A: (A @ A.T + np.eye(10), r.standard_normal(10)))(r.standard_normal((10, 10)))),
    "pd-nonsym8": (lambda r: (lambda A, S: (A @ A.T + S - S.T + 0.1 * np.eye(8), r.standard_normal(8)))(
        r.standard_normal((8, 8)), r.standard_normal((8, 8)))),
    "contact-flat": (lambda r: (lambda c: (c.M, c.q))(cube_on_slope_lcp(0.0, 0.5))),
    "contact-slide-1e-3": (lambda r: (lambda c: (c.M, c.q))(cube_on_slope_lcp(30.0, 0.5, s=1e-3))),
    "murty8": (lambda r: murty(8)),
}
SOLVERS = {
    "lemke": dict(method="lemke"),
    "lemke-classic": dict(method="lemke", pivoting="classic"),
    "pgs": dict(method="pgs"),
    "newton_fb": dict(method="newton_fb"),
}


@pytest.mark.parametrize("dataset", list(DATASETS))
@pytest.mark.parametrize("solver", list(SOLVERS))
def test_conformance_never_lies(solver, dataset):
    """Every solver on every dataset: `solved` must pass the independent check."""
    M, q = DATASETS[dataset](np.random.default_rng(11))
    res = solve_lcp(M, q, **SOLVERS[solver])
    assert res.status in {"solved", "ray_termination", "max_pivots", "max_iterations", "singular_basis",
                          "cycling", "numerical", "regularized"}
    np.testing.assert_allclose(res.w, np.asarray(M) @ res.z + q, rtol=0, atol=1e-12 * (1 + np.abs(q).max()))
    if res.ok:
        check_solution(M, q, res.z, rel=1e-5 if solver == "lemke-classic" else 1e-8)
    if solver == "lemke":
        assert res.ok, f"default Lemke failed on {dataset}: {res.status}"


def test_unrepresentable_answer_is_reported_not_solved():
    """z = 2.5e-324 lies between 0 and the smallest subnormal: neither meets the rule, and
    the result must say so rather than come back `solved`."""
    res = solve_lcp(np.array([[2.0]]), np.array([-5e-324]))
    assert not res.ok
    assert res.status != "solved"
