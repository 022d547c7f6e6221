"""What the solvers and the exact check return: :class:`LcpResult` (one
solve), :class:`LcpBatchResult` (a batch) and :class:`Certificate` (the exact
check of a basis, :mod:`lcpsim.certification`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Iterator, Mapping

import numpy as np
from numpy.typing import NDArray

__all__ = ["LcpResult", "LcpBatchResult", "Certificate", "ETA_CERTIFIED", "CERT_STATUSES"]

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


@dataclass(frozen=True)
class LcpResult:
    """The outcome of one LCP solve.

    ``status`` is one of :data:`STATUSES`; ``ok`` is true only for
    ``"solved"`` with an answer inside the acceptance rule (each row judged on
    its own scale, see the README); classic pivoting's ``"solved"`` is its
    own absolute check, so there ``ok`` can be False. ``z`` and ``w = M z + q`` always have length n (the last iterate when not
    solved). ``residual`` is the natural residual ``‖min(z, w)‖∞`` in the units
    of the problem as given; ``min_z``, ``min_w`` (negative means infeasible)
    and ``max_complementarity = max |z_i w_i|`` complete the picture.
    ``pivots`` counts Lemke pivots, or iterations for PGS and Newton–FB.
    ``basis`` (Lemke only) marks the ``z_j`` basic at the end, else None.

    ``certified`` (``solve_lcp(..., certify=True)``): True when the final
    basis solves the LCP of the floats as given exactly (rational
    arithmetic), False when it does not, None when not attempted (no
    ``certify=True``, or no basis); ``certificate`` holds the details
    (:class:`~lcpsim.result.Certificate`: status, backward error η,
    exact natural residual, violations). ``dump_path``
    (``solve_lcp(..., dump=DIR)``): the failure dump written for this
    result, else None.
    """

    z: NDArray[np.float64]  # (n,)
    w: NDArray[np.float64]  # (n,) M z + q
    status: str
    ok: bool
    pivots: int
    residual: float  # ‖min(z, w)‖∞
    min_z: float  # min_i z_i
    min_w: float  # min_i w_i
    max_complementarity: float
    method: str
    basis: NDArray[np.bool_] | None = None
    certified: bool | None = None
    certificate: Certificate | None = None
    dump_path: str | None = None

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict (arrays as lists)."""
        return {
            "status": self.status,
            "ok": self.ok,
            "method": self.method,
            "pivots": self.pivots,
            "residual": self.residual,
            "min_z": self.min_z,
            "min_w": self.min_w,
            "max_complementarity": self.max_complementarity,
            "z": self.z.tolist(),
            "w": self.w.tolist(),
            "basis": None if self.basis is None else self.basis.tolist(),
            "certified": self.certified,
            "certificate": None if self.certificate is None else self.certificate.to_dict(),
            "dump_path": self.dump_path,
        }


@dataclass(frozen=True, slots=True)
class LcpBatchResult:
    """The outcome of :func:`solve_lcp_batch`: the fields of :class:`LcpResult`
    stacked over the batch (``z``, ``w`` of shape (b, n); the rest of shape
    (b,)). Indexing or iterating yields one :class:`LcpResult` per problem.
    ``basis`` is a (b, n) array when every solve returned a basis, else None."""

    z: NDArray[np.float64]  # (b, n)
    w: NDArray[np.float64]  # (b, n)
    status: tuple[str, ...]  # (b,) from here on
    ok: NDArray[np.bool_]
    pivots: NDArray[np.int64]
    residual: NDArray[np.float64]  # ‖min(z, w)‖∞ per problem
    min_z: NDArray[np.float64]
    min_w: NDArray[np.float64]
    max_complementarity: NDArray[np.float64]
    method: str
    basis: NDArray[np.bool_] | None = None

    def __len__(self) -> int:
        return len(self.status)

    def __getitem__(self, i: int) -> LcpResult:
        if not -len(self) <= i < len(self):
            raise IndexError(f"batch index {i} out of range for a batch of {len(self)}")
        return LcpResult(
            z=self.z[i],
            w=self.w[i],
            status=self.status[i],
            ok=bool(self.ok[i]),
            pivots=int(self.pivots[i]),
            residual=float(self.residual[i]),
            min_z=float(self.min_z[i]),
            min_w=float(self.min_w[i]),
            max_complementarity=float(self.max_complementarity[i]),
            method=self.method,
            basis=None if self.basis is None else self.basis[i],
        )

    def __iter__(self) -> Iterator[LcpResult]:
        return (self[i] for i in range(len(self)))

    @property
    def by_status(self) -> dict[str, int]:
        """How many problems ended with each status (only statuses that occur)."""
        counts: dict[str, int] = {}
        for s in self.status:
            counts[s] = counts.get(s, 0) + 1
        return counts
