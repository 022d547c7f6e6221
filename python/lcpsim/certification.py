"""Exact certification of an LCP answer.

Every finite float is a rational number, so the LCP given by the floats
``(M, q)`` has an exact meaning. :func:`certify` takes a complementary basis
(the ``z_j`` that are basic), solves ``M_αα z_α = −q_α`` in exact rational
arithmetic (Rust, ``lcp::certify``), and checks ``z ≥ 0``, ``w = M z + q ≥ 0``
and ``z_i w_i = 0`` with no tolerance at all. ``status == "certified"`` is a
proof that this basis solves the LCP of the floats as given.

On rank-deficient contact LCPs a right basis can still fail the exact check:
entries that are exactly 0 in real arithmetic come out as ±1e-17 after the
data were rounded to floats, and about half of them are negative. So the
certificate also carries the componentwise (Oettli–Prager) backward error
``backward_error`` (η): the answer is the exact solution of an LCP whose every
entry of ``M`` and ``q`` lies within a relative η of the one given. η of a
few 1e-16 means "exact up to the rounding already in the data";
:data:`lcpsim.result.ETA_CERTIFIED` (1e-14) is the threshold used by the experiments.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from . import _core
from ._validate import as_basis, as_real_array
from .result import Certificate, LcpResult

__all__ = ["certify", "certify_batch"]


def certify(M: ArrayLike, q: ArrayLike, z_or_basis: Any, *, z: ArrayLike | None = None) -> Certificate:
    """Checks exactly whether a complementary basis solves the LCP ``(M, q)``
    of the floats as given.

    ``z_or_basis`` is a boolean basis (``basis[j]``: ``z_j`` basic; pass the
    float answer as ``z=`` to get ``z_error``), a float ``z`` (its support
    ``{j : z_j > 0}`` is the basis), or an :class:`~lcpsim.LcpResult` (its
    ``basis`` and ``z``). Takes milliseconds for n = 40; the cost grows with
    the size of the exact determinants. Raises ValueError on invalid input.
    """
    M_ = as_real_array(M, "M", 2)
    q_ = as_real_array(q, "q", 1)
    if isinstance(z_or_basis, LcpResult):
        if z is not None:
            raise ValueError("certify: z= is taken from the LcpResult; do not pass it too")
        if z_or_basis.basis is None:
            return Certificate._from_core(_core.certify_lcp(M_, q_, None, as_real_array(z_or_basis.z, "z", 1)))
        return Certificate._from_core(
            _core.certify_lcp(M_, q_, as_basis(z_or_basis.basis), as_real_array(z_or_basis.z, "z", 1))
        )
    a = np.asarray(z_or_basis)
    if a.dtype == np.bool_:
        zz = None if z is None else as_real_array(z, "z", 1)
        return Certificate._from_core(_core.certify_lcp(M_, q_, as_basis(a), zz))
    if z is not None:
        raise ValueError("certify: z= goes with a boolean basis; a float array is itself the z to certify")
    return Certificate._from_core(_core.certify_lcp(M_, q_, None, as_real_array(a, "z", 1)))


def certify_batch(
    Ms: ArrayLike, qs: ArrayLike, bases: ArrayLike, zs: ArrayLike | None = None, *, threads: int = 1
) -> list[Certificate]:
    """:func:`certify` over a stack ``Ms`` (b, n, n), ``qs`` (b, n), ``bases``
    (b, n) bool, optionally ``zs`` (b, n); the GIL is released and
    ``threads`` workers (0 = one per core) share the batch."""
    Ms_ = as_real_array(Ms, "Ms", 3)
    qs_ = as_real_array(qs, "qs", 2)
    b = as_basis(bases, "bases")
    zs_ = None if zs is None else as_real_array(zs, "zs", 2)
    return [Certificate._from_core(d) for d in _core.certify_lcp_batch(Ms_, qs_, b, zs_, threads)]
