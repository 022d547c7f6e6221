"""Typed wrappers over the compiled LCP solvers.

An LCP ``(M, q)`` asks for ``z >= 0`` with ``w = M z + q >= 0`` and ``z·w = 0``.
:func:`solve_lcp` solves one, :func:`solve_lcp_batch` many of one size with the
GIL released, :func:`lcp_residual` measures any candidate ``z``.

Input is validated here so that every mistake is a :class:`ValueError` naming
the argument and its value; the compiled module validates again (it never
panics into Python).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, Iterator

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core

if TYPE_CHECKING:
    from .certification import Certificate

__all__ = [
    "LcpResult",
    "LcpBatchResult",
    "solve_lcp",
    "solve_lcp_batch",
    "lcp_residual",
    "METHODS",
    "PIVOTINGS",
    "STATUSES",
]

#: Solver names accepted by ``method=``.
METHODS: tuple[str, ...] = tuple(_core.METHODS)
#: Lemke pivoting rules accepted by ``pivoting=``.
PIVOTINGS: tuple[str, ...] = tuple(_core.PIVOTINGS)
#: Every status a solve can end with; ``ok`` (solved and accepted by the rule) means ``z`` solves the LCP.
STATUSES: tuple[str, ...] = tuple(_core.STATUSES)

# Lemke's option defaults, declared once in Rust (crates/lcp's LemkeOptions);
# solve_lcp's keyword defaults are these very objects.
_LEMKE_DEFAULTS: dict[str, Any] = _core.LEMKE_DEFAULTS

# dtype kinds that convert to float64 without loss of meaning:
# bool, signed and unsigned integers, floats.
_REAL_KINDS = frozenset("biuf")


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
    (:class:`~lcpsim.certification.Certificate`: status, backward error η,
    exact natural residual, violations). ``dump_path``
    (``solve_lcp(..., dump=DIR)``): the failure dump written for this
    result, else None.
    """

    z: NDArray[np.float64]
    w: NDArray[np.float64]
    status: str
    ok: bool
    pivots: int
    residual: float
    min_z: float
    min_w: float
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

    z: NDArray[np.float64]
    w: NDArray[np.float64]
    status: tuple[str, ...]
    ok: NDArray[np.bool_]
    pivots: NDArray[np.int64]
    residual: NDArray[np.float64]
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

    def status_counts(self) -> dict[str, int]:
        """Deprecated name of :attr:`by_status`."""
        from ._deprecated import warn

        warn("LcpBatchResult.status_counts()", "LcpBatchResult.by_status")
        return self.by_status


# solve_lcp builds its LcpResult from the compiled solver's dict, which holds
# every field but certified, certificate and dump_path (their class defaults,
# None, apply): the dict becomes the instance's __dict__, as pydantic's
# model_construct does. LcpResult.__init__ would set the fields one
# object.__setattr__ at a time, over a microsecond per solve (issue 2).
_new_object = object.__new__
_set_attribute = object.__setattr__
_FLOAT64 = np.dtype(np.float64)


def _as_real_array(x: ArrayLike, name: str, ndim: int) -> NDArray[np.float64]:
    """``x`` as a float64 array with ``ndim`` dimensions, or a ValueError naming ``name``."""
    if isinstance(x, np.ndarray) and x.dtype == np.float64 and x.ndim == ndim:
        return x  # fast path: the compiled module copies what it needs
    try:
        a = np.asarray(x)
    except Exception as e:  # ragged lists and the like
        raise ValueError(f"{name} must be a {ndim}-D array of real numbers, got {_short_repr(x)}: {e}") from None
    if a.dtype.kind not in _REAL_KINDS:
        raise ValueError(
            f"{name} must hold real numbers, got dtype {a.dtype} ({_short_repr(x)})"
        )
    if a.ndim != ndim:
        raise ValueError(f"{name} must be {ndim}-D, got shape {a.shape} ({_short_repr(x)})")
    return a.astype(np.float64, copy=False)


def _short_repr(x: Any, limit: int = 60) -> str:
    r = np.array2string(x, threshold=6) if isinstance(x, np.ndarray) else repr(x)
    r = " ".join(r.split())
    return r if len(r) <= limit else r[: limit - 3] + "..."


def _check_method(method: Any) -> str:
    if not isinstance(method, str) or method not in METHODS:
        raise ValueError(f"unknown method {method!r} (valid: {', '.join(METHODS)})")
    return method


def _options(method: str, pivoting: Any, piv_tol: Any, zero_tol: Any, max_pivots: Any,
             extra: dict[str, Any]) -> dict[str, Any]:
    """The keyword options for the compiled solver of ``method``."""
    lemke_args = {"pivoting": pivoting, "piv_tol": piv_tol, "zero_tol": zero_tol, "max_pivots": max_pivots}
    if method == "lemke":
        if not isinstance(pivoting, str) or pivoting not in PIVOTINGS:
            raise ValueError(f"unknown pivoting {pivoting!r} (valid: {', '.join(PIVOTINGS)})")
        return {**lemke_args, **extra}
    for key, value in lemke_args.items():
        if value is not _LEMKE_DEFAULTS[key] and value != _LEMKE_DEFAULTS[key]:
            raise ValueError(f"option {key}={value!r} applies only to method 'lemke', not {method!r}")
    return extra


def solve_lcp(
    M: ArrayLike,
    q: ArrayLike,
    *,
    method: str = "lemke",
    pivoting: str = _LEMKE_DEFAULTS["pivoting"],
    piv_tol: float = _LEMKE_DEFAULTS["piv_tol"],
    zero_tol: float = _LEMKE_DEFAULTS["zero_tol"],
    max_pivots: int | None = _LEMKE_DEFAULTS["max_pivots"],
    certify: bool = False,
    dump: str | os.PathLike[str] | None = None,
    **options: Any,
) -> LcpResult:
    """Solve the LCP ``(M, q)``: ``z >= 0``, ``w = M z + q >= 0``, ``z·w = 0``.

    Parameters
    ----------
    M, q:
        An n×n matrix and a length-n vector (any real dtype, any memory layout).
    method:
        ``"lemke"`` (default), ``"pgs"`` (projected Gauss–Seidel) or
        ``"newton_fb"`` (damped Newton on the Fischer–Burmeister function).
    pivoting:
        Lemke only: ``"lexicographic"`` (robust default: equilibration,
        relative tie tolerance, answer accepted by its residual in the units
        given) or ``"classic"`` (absolute tolerances on the problem as given,
        as in the seed note; kept to reproduce its findings).
    piv_tol, zero_tol, max_pivots:
        Lemke only: smallest pivot, the user zero, the pivot limit
        (None means ``max(1000, 50 n)``).
    **options:
        Further options of the chosen method — lemke: ``accept_tol``,
        ``equilibrate``; pgs: ``omega``, ``max_iterations``, ``tol``;
        newton_fb: ``max_iterations``, ``tol``, ``armijo_sigma``, ``backtrack``,
        ``max_backtracks``, ``descent_rho``. A value of None means the default.
    certify:
        Recompute the final basis's solution in exact rational arithmetic from
        the floats as given and check ``z >= 0``, ``w >= 0``, ``z·w = 0``
        exactly: sets ``certified`` (None when there is no basis, e.g. PGS)
        and ``certificate`` (with the backward error η). Milliseconds at
        n = 40, growing quickly beyond.
    dump:
        A directory: when the result is not ``solved``, the LCP is re-solved
        with a pivot trace (Lemke) and a failure dump (HDF5: ``M``, ``q``,
        method and options, status, ``z``, ``w``, residuals, trace, lcpsim
        version) is written there; its path is ``dump_path``. Replay it with
        ``lcpsim solve DUMP`` or :func:`lcpsim.io.forensics.replay`.

    Raises
    ------
    ValueError
        For invalid input: non-finite entries, non-square ``M``, mismatched
        lengths, an empty problem, wrong dimensions or dtype, an unknown method
        or option, a negative tolerance or a wrongly typed option.
    """
    # The common case is recognised inline, as a helper call or an option
    # passed costs about 0.1 µs against a solve of 10-20 µs (issue 2): Lemke
    # with every option at its default (the very default objects, so no
    # comparison can misbehave) is called with no options, the compiled
    # defaults being the same (tested); arrays already float64 with the right
    # dimensions go as they are. The compiled module validates everything again.
    defaults = (
        method is _DEFAULT_METHOD
        and pivoting is _DEFAULT_PIVOTING
        and piv_tol is _DEFAULT_PIV_TOL
        and zero_tol is _DEFAULT_ZERO_TOL
        and max_pivots is None
        and not options
    )
    if not defaults:
        method = _check_method(method)
        opts = _options(method, pivoting, piv_tol, zero_tol, max_pivots, options)
    M_ = M if type(M) is np.ndarray and M.dtype is _FLOAT64 and M.ndim == 2 else _as_real_array(M, "M", 2)
    q_ = q if type(q) is np.ndarray and q.dtype is _FLOAT64 and q.ndim == 1 else _as_real_array(q, "q", 1)
    if certify is not False and certify is not True and not isinstance(certify, np.bool_):
        raise ValueError(f"certify must be True or False, got {certify!r}")
    if dump is not None and not isinstance(dump, (str, os.PathLike)):
        raise ValueError(f"dump must be a directory path (str or os.PathLike), got {dump!r}")
    res = _new_object(LcpResult)
    _set_attribute(res, "__dict__", _core.solve_lcp(M_, q_) if defaults else _core.solve_lcp(M_, q_, method, **opts))
    if certify and res.basis is not None:
        from .certification import Certificate

        cert = Certificate._from_core(_core.certify_lcp(M_, q_, np.ascontiguousarray(res.basis, dtype=bool), res.z))
        res = replace(res, certified=cert.certified, certificate=cert)
    if dump is not None and not res.ok:
        from .io.forensics import write_dump

        opts = _options(method, pivoting, piv_tol, zero_tol, max_pivots, options)
        path = write_dump(dump, M_, q_, method, opts, res)
        res = replace(res, dump_path=str(path))
    return res


# The objects Python passes for solve_lcp's keyword arguments the caller omits.
_DEFAULT_METHOD, _DEFAULT_PIVOTING, _DEFAULT_PIV_TOL, _DEFAULT_ZERO_TOL = (
    (solve_lcp.__kwdefaults__ or {})[k] for k in ("method", "pivoting", "piv_tol", "zero_tol")
)


def solve_lcp_batch(
    Ms: ArrayLike,
    qs: ArrayLike,
    *,
    method: str = "lemke",
    pivoting: str = _LEMKE_DEFAULTS["pivoting"],
    piv_tol: float = _LEMKE_DEFAULTS["piv_tol"],
    zero_tol: float = _LEMKE_DEFAULTS["zero_tol"],
    max_pivots: int | None = _LEMKE_DEFAULTS["max_pivots"],
    threads: int = 1,
    **options: Any,
) -> LcpBatchResult:
    """Solve ``b`` LCPs of one size n: ``Ms`` of shape (b, n, n), ``qs`` of
    shape (b, n). The GIL is released while solving; ``threads`` worker threads
    (0 = one per core) share the batch. Options as in :func:`solve_lcp`; the
    results equal ``solve_lcp`` on each problem."""
    method = _check_method(method)
    opts = _options(method, pivoting, piv_tol, zero_tol, max_pivots, options)
    Ms_ = _as_real_array(Ms, "Ms", 3)
    qs_ = _as_real_array(qs, "qs", 2)
    if Ms_.shape[0] != qs_.shape[0]:
        raise ValueError(
            f"Ms and qs hold different numbers of problems: Ms has shape {Ms_.shape}, qs has shape {qs_.shape}"
        )
    # The batch dict is keyed by the result's fields (`ok`: solved and accepted by the rule).
    d = _core.solve_lcp_batch(Ms_, qs_, method, threads, **opts)  # threads checked there
    return LcpBatchResult(**{**d, "status": tuple(d["status"])})


def lcp_residual(M: ArrayLike, q: ArrayLike, z: ArrayLike) -> float:
    """Natural residual ``‖min(z, M z + q)‖∞`` of ``z`` for ``(M, q)``, in the
    units of the problem as given (0 exactly when ``z`` solves the LCP)."""
    return float(_core.lcp_residual(_as_real_array(M, "M", 2), _as_real_array(q, "q", 1), _as_real_array(z, "z", 1)))


def lcp_residuals(M: ArrayLike, q: ArrayLike, z: ArrayLike) -> dict[str, Any]:
    """All error measures of ``z``: ``w``, ``residual`` (the natural residual, as
    :func:`lcp_residual`), ``min_z``, ``min_w``, ``max_complementarity``.
    ``natural`` is the old key of ``residual`` (deprecated, kept)."""
    d = dict(_core.lcp_residuals(_as_real_array(M, "M", 2), _as_real_array(q, "q", 1), _as_real_array(z, "z", 1)))
    d["natural"] = d["residual"]
    return d
