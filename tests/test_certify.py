"""Exact certification: solve_lcp(certify=True), lcpsim.certify,
certify_batch — on hand-made LCPs with known exact answers, SPD and contact LCPs,
and the corpora's LCPs of size up to 40."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

import lcpsim
from lcpsim import Certificate, certify, solve_lcp
from lcpsim.certification import certify_batch
from lcpsim.result import ETA_CERTIFIED
from lcpsim.experiments.cube_corpus import generate, scaled
from lcpsim.generate import contact_lcp, hard_corpus, spd_lcp


def test_exact_two_by_two():
    M = np.array([[2.0, 1.0], [1.0, 2.0]])
    q = np.array([-1.0, -1.0])
    res = solve_lcp(M, q, certify=True)
    assert res.ok and res.certified is True
    c = res.certificate
    assert isinstance(c, Certificate) and c.status == "certified" and c.certified
    assert c.backward_error == 0.0 and c.natural_residual == 0.0 and c.violations == 0 and c.violation is None
    # z = (1/3, 1/3) exactly, rounded to nearest.
    assert c.z.tolist() == [float(Fraction(1, 3))] * 2 and c.w.tolist() == [0.0, 0.0]
    assert c.z_error is not None and c.z_error <= 2 * np.spacing(1 / 3)
    assert c.basis.tolist() == [True, True] and c.det_bits > 0


def test_not_attempted_without_flag_or_basis():
    M, q, _ = spd_lcp(8, seed=1).M, spd_lcp(8, seed=1).q, None
    res = solve_lcp(M, q)
    assert res.certified is None and res.certificate is None
    for method in ("pgs", "newton_fb"):
        r = solve_lcp(M, q, method=method, certify=True)
        assert r.basis is None and r.certified is None and r.certificate is None
    d = solve_lcp(M, q, certify=True).to_dict()
    assert d["certified"] is True and d["certificate"]["status"] == "certified" and d["dump_path"] is None
    with pytest.raises(ValueError, match="certify"):
        solve_lcp(M, q, certify="yes")


def test_wrong_basis_is_violated_and_singular_is_singular():
    M = np.array([[2.0, 1.0], [1.0, 2.0]])
    q = np.array([-1.0, -1.0])
    c = certify(M, q, np.array([True, False]))
    # z_0 = 1/2, w_1 = 1/2 - 1 = -1/2 < 0.
    assert c.status == "violated" and not c.certified and c.violations == 1
    assert c.violation == {"index": 1, "kind": "negative_w", "value": -0.5}
    assert c.natural_residual == 0.5 and c.backward_error > 0.1 and not c.certified_within()
    s = certify(np.zeros((2, 2)), q, np.array([True, False]))
    assert s.status == "singular" and s.z.size == 0 and s.backward_error == np.inf and s.natural_residual == np.inf


def test_certify_accepts_z_basis_or_result():
    p = spd_lcp(20, seed=3)
    res = solve_lcp(p.M, p.q)
    a = certify(p.M, p.q, res)  # basis and z of the result
    b = certify(p.M, p.q, res.basis, z=res.z)
    c = certify(p.M, p.q, res.z)  # support of z
    for x in (a, b, c):
        assert x.certified and x.z_error is not None and x.z_error < 1e-12
    assert np.array_equal(a.z, b.z) and np.array_equal(a.z, c.z)
    assert certify(p.M, p.q, res.basis).z_error is None
    assert "certified" in repr(a) and a.to_dict()["certified"] is True


@pytest.mark.parametrize(
    "args, match",
    [
        ((np.eye(2), np.ones(2), np.array([True])), "basis has 1 entries"),
        ((np.eye(2), np.ones(2), np.array([1.0, np.nan])), "nan"),
        ((np.eye(2), np.ones(3), np.array([True, True])), "q"),
        ((np.eye(2), np.ones(2), np.array([1.0])), "z has 1 entries"),
    ],
)
def test_certify_invalid_input(args, match):
    with pytest.raises(ValueError, match=match):
        certify(*args)


def test_certify_z_keyword_only_with_basis():
    with pytest.raises(ValueError, match="z="):
        certify(np.eye(2), np.ones(2), np.ones(2), z=np.ones(2))


@pytest.mark.parametrize("nc", [1, 2, 4])
@pytest.mark.parametrize("scale", [1.0, 1e-3, 1e-8])
def test_contact_lcps_certified_or_backward_stable(nc, scale):
    """Robust Lemke on contact LCPs (n ≤ 40): every answer is certified exactly
    or, on rank-deficient data, the exact solution of an LCP within 1e-14."""
    for seed in range(6):
        p = contact_lcp(nc, scale=scale, seed=seed)
        res = solve_lcp(p.M, p.q, certify=True)
        assert res.ok and res.certified is not None
        c = res.certificate
        assert c is not None and c.status != "singular"
        assert c.certified or c.backward_error <= ETA_CERTIFIED, (p.label, c)


def test_cube_corpus_up_to_40_certified():
    """On the corpus: the robust default's answers on cube-corpus
    LCPs (n ≤ 40) at several scales, checked exactly; none is singular, each
    exact basis solution is backward stable (η ≤ 1e-14) or has a natural
    residual at round-off level (≤ 1e-14·(1 + ‖q‖∞): resting contacts whose
    tangential q is ±1e-17), as on the full corpus at every scale."""
    corp = generate({"n_random": 1, "steps": 120}).subsample(300, 0)
    for s in (1.0, 1e-4, 1e-8):
        exact = eta = total = 0
        for g in corp.groups:
            Ms, qs, _ = scaled(g.M, g.q, g.contacts, g.friction_dirs, s)
            res = lcpsim.solve_lcp_batch(Ms, qs)
            assert all(res.ok)
            certs = certify_batch(Ms, qs, res.basis, res.z)
            for c, qi in zip(certs, qs):
                assert c.status in ("certified", "violated")
                assert c.backward_error <= ETA_CERTIFIED or c.natural_residual <= 1e-14 * (1 + np.abs(qi).max()), c
            exact += sum(c.certified for c in certs)
            eta += sum(c.backward_error <= ETA_CERTIFIED for c in certs)
            total += len(certs)
        assert total == len(corp) and exact > 0.3 * total and eta >= exact


def test_hard_corpus_up_to_40():
    base = [p for p in hard_corpus(0, 60, 1e-3) if p.n <= 40]
    assert base
    for p in base:
        res = solve_lcp(p.M, p.q, certify=True)
        assert res.ok and res.certified is not None
        assert res.certificate.natural_residual <= 1e-12 * (1 + np.abs(p.q).max())


def test_batch_matches_single():
    ps = [spd_lcp(12, seed=s) for s in range(5)]
    Ms = np.stack([p.M for p in ps])
    qs = np.stack([p.q for p in ps])
    res = lcpsim.solve_lcp_batch(Ms, qs)
    many = certify_batch(Ms, qs, res.basis, res.z, threads=2)
    for i, c in enumerate(many):
        one = certify(ps[i].M, ps[i].q, res.basis[i], z=res.z[i])
        assert c.status == one.status and np.array_equal(c.z, one.z) and c.z_error == one.z_error
    with pytest.raises(ValueError):
        certify_batch(Ms, qs, res.basis[:, :5])


def test_classic_failure_basis_is_not_certified():
    """A failed classic solve has a basis, but not one that solves the LCP."""
    from test_dump import classic_failure

    p = classic_failure()
    res = solve_lcp(p.M, p.q, pivoting="classic", certify=True)
    assert not res.ok and res.certified is False and res.certificate.status in ("violated", "singular")
