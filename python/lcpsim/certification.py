"""Exact certification of an LCP answer (issue 5).

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
:data:`ETA_CERTIFIED` (1e-14) is the threshold used by the experiments.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core

__all__ = ["Certificate", "certify", "certify_batch", "ETA_CERTIFIED", "CERT_STATUSES"]

#: Certificate statuses.
CERT_STATUSES: tuple[str, ...] = ("certified", "violated", "singular")

#: A backward error at or below this means: the exact solution of an LCP within
#: 1e-14 (relative, entrywise) of the one given.
ETA_CERTIFIED = 1e-14


@dataclass(frozen=True, slots=True)
class Certificate:
    """The exact check of one complementary basis.

    ``status``: ``"certified"`` (``z ≥ 0``, ``w ≥ 0``, ``z·w = 0`` hold
    exactly for the floats as given), ``"violated"`` (the basis solution
    breaks one of them; ``violation`` names the first: ``index``, ``kind``
    — ``negative_z``, ``negative_w`` or ``complementarity`` — and the exact
    ``value`` rounded) or ``"singular"`` (``M_αα`` is exactly singular).
    ``z``, ``w``: the exact basis solution rounded to nearest (empty when
    singular). ``natural_residual``: ‖min(z, w)‖∞ of the exact solution (0
    when certified, inf when singular). ``backward_error``: Oettli–Prager η
    (0 when certified). ``z_error``: max |z_exact − z_given| when a float z was
    given, else None. ``det_bits``: bit length of the exact (scaled)
    determinant, the size of the arithmetic.
    """

    status: str
    basis: NDArray[np.bool_]
    z: NDArray[np.float64]
    w: NDArray[np.float64]
    violations: int
    violation: dict[str, Any] | None
    natural_residual: float
    backward_error: float
    z_error: float | None
    det_bits: int

    def __repr__(self) -> str:
        v = "" if self.violation is None else f", violation={self.violation}"
        return (
            f"Certificate(status={self.status!r}, n={self.basis.shape[0]}, backward_error={self.backward_error:.3g}, "
            f"natural_residual={self.natural_residual:.3g}, violations={self.violations}{v}, z_error={self.z_error!r})"
        )

    @property
    def certified(self) -> bool:
        """True only when the exact check passed."""
        return self.status == "certified"

    def certified_within(self, eta: float = ETA_CERTIFIED) -> bool:
        """Certified, or the exact solution of an LCP within a relative ``eta`` of the given one."""
        return self.backward_error <= eta

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict (arrays as lists)."""
        return {
            "status": self.status,
            "certified": self.certified,
            "violations": self.violations,
            "violation": None if self.violation is None else dict(self.violation),
            "natural_residual": self.natural_residual,
            "backward_error": self.backward_error,
            "z_error": self.z_error,
            "det_bits": self.det_bits,
            "basis": self.basis.tolist(),
        }

    @classmethod
    def _from_core(cls, d: Mapping[str, Any]) -> Certificate:
        v = d["violation"]
        return cls(
            status=str(d["status"]),
            basis=np.asarray(d["basis"], dtype=bool),
            z=np.asarray(d["z"], dtype=np.float64),
            w=np.asarray(d["w"], dtype=np.float64),
            violations=int(d["violations"]),
            violation=None if v is None else {"index": int(v["index"]), "kind": str(v["kind"]), "value": float(v["value"])},
            natural_residual=float(d["natural_residual"]),
            backward_error=float(d["backward_error"]),
            z_error=None if d["z_error"] is None else float(d["z_error"]),
            det_bits=int(d["det_bits"]),
        )


def _as_float(x: ArrayLike, name: str, ndim: int) -> NDArray[np.float64]:
    from .lcp import _as_real_array

    return _as_real_array(x, name, ndim)


def _as_basis(b: ArrayLike, name: str = "basis") -> NDArray[np.bool_]:
    a = np.asarray(b)
    if a.dtype != np.bool_:
        raise ValueError(f"{name} must be a boolean array (z_j basic), got dtype {a.dtype}")
    return np.ascontiguousarray(a)


def certify(M: ArrayLike, q: ArrayLike, z_or_basis: Any, *, z: ArrayLike | None = None) -> Certificate:
    """Checks exactly whether a complementary basis solves the LCP ``(M, q)``
    of the floats as given.

    ``z_or_basis`` is a boolean basis (``basis[j]``: ``z_j`` basic; pass the
    float answer as ``z=`` to get ``z_error``), a float ``z`` (its support
    ``{j : z_j > 0}`` is the basis), or an :class:`~lcpsim.LcpResult` (its
    ``basis`` and ``z``). Takes milliseconds for n = 40; the cost grows with
    the size of the exact determinants. Raises ValueError on invalid input.
    """
    from .lcp import LcpResult

    M_ = _as_float(M, "M", 2)
    q_ = _as_float(q, "q", 1)
    if isinstance(z_or_basis, LcpResult):
        if z is not None:
            raise ValueError("certify: z= is taken from the LcpResult; do not pass it too")
        if z_or_basis.basis is None:
            return Certificate._from_core(_core.certify_lcp(M_, q_, None, _as_float(z_or_basis.z, "z", 1)))
        return Certificate._from_core(
            _core.certify_lcp(M_, q_, _as_basis(z_or_basis.basis), _as_float(z_or_basis.z, "z", 1))
        )
    a = np.asarray(z_or_basis)
    if a.dtype == np.bool_:
        zz = None if z is None else _as_float(z, "z", 1)
        return Certificate._from_core(_core.certify_lcp(M_, q_, _as_basis(a), zz))
    if z is not None:
        raise ValueError("certify: z= goes with a boolean basis; a float array is itself the z to certify")
    return Certificate._from_core(_core.certify_lcp(M_, q_, None, _as_float(a, "z", 1)))


def certify_batch(
    Ms: ArrayLike, qs: ArrayLike, bases: ArrayLike, zs: ArrayLike | None = None, *, threads: int = 1
) -> list[Certificate]:
    """:func:`certify` over a stack ``Ms`` (b, n, n), ``qs`` (b, n), ``bases``
    (b, n) bool, optionally ``zs`` (b, n); the GIL is released and
    ``threads`` workers (0 = one per core) share the batch."""
    Ms_ = _as_float(Ms, "Ms", 3)
    qs_ = _as_float(qs, "qs", 2)
    b = _as_basis(bases, "bases")
    zs_ = None if zs is None else _as_float(zs, "zs", 2)
    return [Certificate._from_core(d) for d in _core.certify_lcp_batch(Ms_, qs_, b, zs_, threads)]
