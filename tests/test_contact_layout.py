"""lcpsim.ContactLayout: where fn, fd, λ live in z, the friction-cone scaling
against an explicit D M D, and the one zero rule of the sign patterns."""

from __future__ import annotations

import numpy as np
import pytest

import lcpsim
from lcpsim import ContactLayout, _core
from lcpsim.generate import contact_lcp


@pytest.mark.parametrize("nc, k", [(1, 1), (1, 8), (2, 4), (3, 8), (5, 16)])
def test_slices_tile_z_in_order(nc: int, k: int) -> None:
    lay = ContactLayout(nc, k)
    assert (lay.nc, lay.k, lay.n, lay.impulses) == (nc, k, nc * (k + 2), nc * (k + 1))
    idx = np.arange(lay.n)
    assert np.array_equal(np.concatenate([idx[lay.fn], idx[lay.fd], idx[lay.lam]]), idx)
    assert (len(idx[lay.fn]), len(idx[lay.fd]), len(idx[lay.lam])) == (nc, nc * k, nc)
    assert np.array_equal(idx[lay.force], idx[: nc * (k + 1)])
    # Contact-major fd: contact c's slice is row c of fd reshaped (nc, k).
    fd = idx[lay.fd].reshape(nc, k)
    for c in range(nc):
        assert np.array_equal(idx[lay.fd_of(c)], fd[c])
        assert [lay.fd_index(c, j) for j in range(k)] == list(fd[c])
        assert lay.lambda_index(c) == idx[lay.lam][c]


def test_bad_layouts_and_indices_are_value_errors() -> None:
    with pytest.raises(ValueError, match="nc = 0"):
        ContactLayout(0, 8)
    with pytest.raises(ValueError, match="k = 0"):
        ContactLayout(2, 0)
    lay = ContactLayout(2, 4)
    with pytest.raises(ValueError, match="c = 2"):
        lay.lambda_index(2)
    with pytest.raises(ValueError, match="j = 4"):
        lay.fd_index(0, 4)
    with pytest.raises(ValueError, match="z must have shape"):
        lay.unscale_z(np.zeros(11), 0.5)
    with pytest.raises(ValueError, match="M must have shape"):
        lay.scale_lcp(np.zeros((12, 11)), np.zeros(12), 0.5)
    with pytest.raises(ValueError, match="not finite"):
        lay.scale_lcp(np.full((12, 12), np.nan), np.zeros(12), 0.5)


@pytest.mark.parametrize("s", [1.0, 0.5, 1e-3, 1e-8, 0.0])
def test_cone_scaling_is_the_explicit_d_m_d(s: float) -> None:
    nc, k = 3, 4
    lay = ContactLayout(nc, k)
    rng = np.random.default_rng(3)
    M = rng.standard_normal((lay.n, lay.n))
    q = rng.standard_normal(lay.n)
    d = np.r_[np.ones(nc * (k + 1)), np.full(nc, s)]
    assert np.array_equal(lay.cone_diagonal(s), d)
    Ms, qs = lay.scale_lcp(M, q, s)
    assert np.array_equal(Ms, np.diag(d) @ M @ np.diag(d))
    assert np.array_equal(qs, d * q)
    # Batches: leading dimensions pass through.
    Mb, qb = lay.scale_lcp(np.stack([M, 2 * M]), np.stack([q, -q]), s)
    assert np.array_equal(Mb[1], np.diag(d) @ (2 * M) @ np.diag(d)) and np.array_equal(qb[1], -d * q)
    # Unscaling multiplies λ by s, nothing else.
    z = rng.random(lay.n)
    assert np.array_equal(lay.unscale_z(z, s), d * z)
    assert np.array_equal(lay.unscale_z(np.stack([z, z]), s)[1], d * z)


def test_generated_contact_lcp_is_its_own_scaling() -> None:
    p1 = contact_lcp(2, 8, 1.0, seed=5)
    p = contact_lcp(2, 8, 1e-3, seed=5)
    lay = p.layout
    assert lay is not None and lay.n == p.n
    Ms, qs = lay.scale_lcp(p1.M, p1.q, 1e-3)
    assert np.array_equal(Ms, p.M) and np.array_equal(qs, p.q)


def test_patterns_are_strictly_above_the_threshold_with_friction_summed() -> None:
    lay = ContactLayout(2, 2)  # z = [fn0, fn1, fd00, fd01, fd10, fd11, λ0, λ1]
    assert list(ContactLayout.PATTERNS) == ["000", "00+", "0+0", "0++", "+00", "+0+", "++0", "+++"]
    z = np.array([1.0, 0.0, 0.5, 0.5, 0.0, 0.0, 2.0, 0.0])
    assert [ContactLayout.PATTERNS[c] for c in lay.patterns(z)] == ["+++", "000"]
    # Equal to the threshold is zero; a negative round-off sum of fd is zero.
    z = np.array([1e-9, 0.0, 2e-9, -3e-9, 0.0, 0.0, 1e-6, 0.0])
    assert list(lay.patterns(z, 1e-9, 1e-6)) == [0, 0]
    # Separate thresholds for impulses and λ, one per row of a batch.
    z = np.array([[1e-7, 0.0, 0.0, 0.0, 0.0, 0.0, 1e-7, 0.0], [1e-7, 0.0, 0.0, 0.0, 0.0, 0.0, 1e-7, 0.0]])
    codes = lay.patterns(z, np.array([1e-9, 1e-6]), np.array([1e-6, 1e-9]))
    assert codes.shape == (2, 2)
    assert [ContactLayout.PATTERNS[c] for c in codes[:, 0]] == ["+00", "00+"]


def test_zero_levels_follow_the_lcps_scales() -> None:
    lay = ContactLayout(1, 2)
    M = np.zeros((4, 4))
    M[[0, 1, 2], [0, 1, 2]] = [2.0, 4.0, 8.0]
    M[3, 0] = 100.0  # the cone row is not part of A
    q = np.array([-3.0, 1.0, 0.5, 0.0])
    imp, vel = lay.zero_levels(M[None], q[None], np.array([[0.25, 0.0, 0.125, 7.0]]), 1e-9)
    assert (imp[0], vel[0]) == (1e-9 * (3.0 / 8.0), 1e-9 * 3.0)
    imp, _ = lay.zero_levels(M[None], q[None], np.array([[5.0, 0.0, 0.125, 70.0]]), 1e-9)
    assert imp[0] == 1e-9 * 5.0


def test_step_record_patterns_use_the_layout_rule() -> None:
    w = lcpsim.World(dt=1e-3)
    w.add_ground(mu=0.5)
    w.add_box((0.5, 0.5, 0.5), position=(0.0, 0.0, 0.5), velocity=(1.0, 0.0, 0.0))
    r = w.step()
    pats = r.patterns()
    lay = ContactLayout(r.contacts, r.friction_dirs)
    codes = lay.patterns(r.z, 1e-12)
    assert np.array_equal(pats, (codes[:, None] & np.array([4, 2, 1])) != 0)
    assert np.array_equal(pats, np.stack([r.fn > 1e-12, r.fd.sum(axis=1) > 1e-12, r.lam > 1e-12], axis=1))
    assert pats[:, 2].all()  # sliding


def test_quaternion_helpers_are_rotations() -> None:
    q = np.asarray(_core.quat_from_axis_angle((0.0, 0.0, 2.0), np.pi / 2))
    R = _core.quat_to_matrix(q)
    assert np.allclose(R @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], atol=1e-15)
    assert np.allclose(np.asarray(_core.quat_from_matrix(R)), q, atol=1e-15)
    p = np.asarray(_core.quat_from_axis_angle((1.0, 0.0, 0.0), 0.3))
    pq = np.asarray(_core.quat_mul(p, q))
    assert np.allclose(_core.quat_to_matrix(pq), _core.quat_to_matrix(p) @ R, atol=1e-15)
