"""lcpsim.generate: the Rust LCP generators from Python — shapes, determinism,
the contact LCP's structure and the map back from a cone-scaled problem."""

from __future__ import annotations

import numpy as np
import pytest

import lcpsim
from lcpsim import generate


def blocks(p: generate.GeneratedLcp) -> tuple[slice, slice, slice]:
    lay = p.layout
    assert lay is not None and lay.n == p.n
    return lay.fn, lay.fd, lay.lam


@pytest.mark.parametrize("nc,k", [(1, 8), (2, 8), (4, 8), (3, 4), (5, 16)])
def test_contact_shapes_and_label(nc: int, k: int) -> None:
    p = generate.contact_lcp(nc, k, 1.0, seed=3)
    n = lcpsim.ContactLayout(nc, k).n
    assert p.M.shape == (n, n) and p.q.shape == (n,)
    assert p.M.dtype == np.float64 and p.q.dtype == np.float64
    assert (p.nc, p.k, p.scale, p.n) == (nc, k, 1.0, n)
    assert p.label == f"contact/nc{nc}/k{k}/seed3"
    assert p.is_contact


def test_contact_sizes_of_the_source_note() -> None:
    # 10·nc for k = 8 (the source note: 2 contacts → 20, 4 contacts → 40).
    assert [generate.contact_lcp(nc).n for nc in (1, 2, 4)] == [10, 20, 40]


def test_determinism_per_seed() -> None:
    a = generate.contact_lcp(4, scale=1e-3, seed=11)
    b = generate.contact_lcp(4, scale=1e-3, seed=11)
    c = generate.contact_lcp(4, scale=1e-3, seed=12)
    assert np.array_equal(a.M, b.M) and np.array_equal(a.q, b.q)
    assert not np.array_equal(a.q, c.q)
    s1, s2 = generate.spd_lcp(40, seed=5), generate.spd_lcp(40, seed=5)
    assert np.array_equal(s1.M, s2.M) and np.array_equal(s1.q, s2.q)
    h1 = generate.hard_corpus(9, 14, 1e-3)
    h2 = generate.hard_corpus(9, 14, 1e-3)
    assert [p.label for p in h1] == [p.label for p in h2]
    assert all(np.array_equal(x.M, y.M) and np.array_equal(x.q, y.q) for x, y in zip(h1, h2))


@pytest.mark.parametrize("scale", [1.0, 1e-3, 1e-6])
def test_contact_structure(scale: float) -> None:
    """M = [[A00, A01, 0], [A10, A11, sE], [sμ, −sEᵀ, 0]], q = [b0; b1; 0], A symmetric PSD."""
    p = generate.contact_lcp(4, 8, scale, seed=21)
    f, d, lam = blocks(p)
    nc, k = 4, 8
    M, q = p.M, p.q
    force = lcpsim.ContactLayout(nc, k).force
    A = M[force, force]
    assert np.array_equal(A, A.T)
    assert np.linalg.eigvalsh(A).min() > -1e-12 * np.abs(A).max()
    assert np.all(M[f, lam] == 0) and np.all(M[lam, lam] == 0)
    E = np.kron(np.eye(nc), np.ones((k, 1)))
    assert np.array_equal(M[d, lam], scale * E)
    assert np.array_equal(M[lam, d], -scale * E.T)
    mu = np.diag(M[lam, f]) / scale
    assert np.allclose(mu, mu[0]) and 0.1 <= mu[0] <= 1.5
    assert np.array_equal(M[lam, f], np.diag(np.diag(M[lam, f])))
    assert np.all(q[lam] == 0)
    # fn, fd rows do not depend on the scale: (M, q) = (D M₁ D, D q₁).
    p1 = p.at_scale(1.0)
    D = p.cone_diagonal()
    assert np.array_equal(D[f], np.ones(nc)) and np.array_equal(D[d], np.ones(nc * k))
    assert np.array_equal(D[lam], np.full(nc, scale))
    assert np.array_equal(p.M[force, force], p1.M[force, force])
    assert np.allclose(p.M, D[:, None] * p1.M * D[None, :], rtol=1e-15, atol=0)
    assert np.array_equal(p.q, p1.q)


def test_physical_residual_maps_lambda_back() -> None:
    p = generate.contact_lcp(2, 8, 1e-6, seed=4)
    res = lcpsim.solve_lcp(p.M, p.q)
    assert res.ok
    z_phys = p.to_physical(res.z)
    _, _, lam = blocks(p)
    assert np.array_equal(z_phys[lam], 1e-6 * res.z[lam])
    # The solution of the scaled problem solves the unscaled one after the map back.
    assert p.physical_residual(res.z) < 1e-9
    unscaled = generate.contact_lcp(2, 8, 1.0, seed=4)
    assert p.physical_residual(res.z) == unscaled.residual(z_phys)
    assert p.residual(res.z) == pytest.approx(res.residual, abs=1e-15)


def test_spd_and_p_matrix() -> None:
    s = generate.spd_lcp(40, seed=2)
    assert s.M.shape == (40, 40) and s.label == "spd/n40/seed2" and not s.is_contact
    assert np.array_equal(s.M, s.M.T) and np.linalg.eigvalsh(s.M).min() >= 0.1 - 1e-12
    assert np.all(np.abs(s.q) <= 1.0)
    assert s.at_scale(1e-3) is s and np.all(s.cone_diagonal() == 1.0)
    p = generate.p_matrix_lcp(12, seed=2)
    sym = 0.5 * (p.M + p.M.T)
    assert not np.array_equal(p.M, p.M.T) and np.linalg.eigvalsh(sym).min() > 0


def test_hard_contact_kinds() -> None:
    assert set(generate.HARD_KINDS) == {
        "many_contacts", "duplicate", "nearly_parallel", "collinear", "mass_ratio", "thin_rod", "mixed",
    }
    for kind in generate.HARD_KINDS:
        p = generate.hard_contact_lcp(kind, 1e-3, seed=8, k=4)
        assert p.label.startswith(f"{kind}/k4/nc{p.nc}/seed8")
        assert p.n == p.nc * 6 and 1 <= p.nc <= 16
        f, d, lam = blocks(p)
        assert np.all(p.q[lam] == 0) and np.all(p.M[lam, lam] == 0)
        force = p.layout.force
        A = p.M[force, force]
        assert np.array_equal(A, A.T)


def test_hard_corpus_regenerates_at_other_scales() -> None:
    corpus = generate.hard_corpus(1, 21, 1e-4)
    assert len(corpus) == 21
    assert {p.label.split("/")[0] for p in corpus} == set(generate.HARD_KINDS)
    unscaled = generate.hard_corpus(1, 21, 1.0)
    for p, u in zip(corpus, unscaled):
        assert p.label == u.label and (p.nc, p.k) == (u.nc, u.k)
        assert p.n == p.nc * (p.k + 2)
        r = p.at_scale(1.0)
        assert np.array_equal(r.M, u.M) and np.array_equal(r.q, u.q)


@pytest.mark.parametrize(
    "call",
    [
        lambda: generate.contact_lcp(0),
        lambda: generate.contact_lcp(2, k=0),
        lambda: generate.contact_lcp(2, scale=-1.0),
        lambda: generate.contact_lcp(2, scale=float("nan")),
        lambda: generate.spd_lcp(0),
        lambda: generate.hard_contact_lcp("no_such_kind"),
        lambda: generate.hard_corpus(0, 3, scale=float("inf")),
    ],
)
def test_invalid_arguments_raise_value_error(call) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ValueError):
        call()
