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
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core
from ._validate import as_real_array
from .result import Certificate, LcpBatchResult, LcpResult

__all__ = [
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

# solve_lcp builds its LcpResult from the compiled solver's dict, which holds
# every field but certified, certificate and dump_path (their class defaults,
# None, apply): the dict becomes the instance's __dict__, as pydantic's
# model_construct does. LcpResult.__init__ would set the fields one
# object.__setattr__ at a time, over a microsecond per solve.
_new_object = object.__new__
_set_attribute = object.__setattr__
_FLOAT64 = np.dtype(np.float64)


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
        as in the source note; kept to reproduce its findings).
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
    # passed costs about 0.1 µs against a solve of 10-20 µs: Lemke
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
    M_ = M if type(M) is np.ndarray and M.dtype is _FLOAT64 and M.ndim == 2 else as_real_array(M, "M", 2)
    q_ = q if type(q) is np.ndarray and q.dtype is _FLOAT64 and q.ndim == 1 else as_real_array(q, "q", 1)
    if certify is not False and certify is not True and not isinstance(certify, np.bool_):
        raise ValueError(f"certify must be True or False, got {certify!r}")
    if dump is not None and not isinstance(dump, (str, os.PathLike)):
        raise ValueError(f"dump must be a directory path (str or os.PathLike), got {dump!r}")
    res = _new_object(LcpResult)
    _set_attribute(res, "__dict__", _core.solve_lcp(M_, q_) if defaults else _core.solve_lcp(M_, q_, method, **opts))
    if certify and res.basis is not None:
        cert = Certificate._from_core(_core.certify_lcp(M_, q_, np.ascontiguousarray(res.basis, dtype=bool), res.z))
        res = replace(res, certified=cert.certified, certificate=cert)
    if dump is not None and not res.ok:
        from .io.dump import write_dump

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
    Ms_ = as_real_array(Ms, "Ms", 3)
    qs_ = as_real_array(qs, "qs", 2)
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
    return float(_core.lcp_residual(as_real_array(M, "M", 2), as_real_array(q, "q", 1), as_real_array(z, "z", 1)))


def lcp_residuals(M: ArrayLike, q: ArrayLike, z: ArrayLike) -> dict[str, Any]:
    """All error measures of ``z``: ``w``, ``residual`` (the natural residual, as
    :func:`lcp_residual`), ``min_z``, ``min_w``, ``max_complementarity``.
    ``natural`` is the old key of ``residual`` (deprecated, kept)."""
    d = dict(_core.lcp_residuals(as_real_array(M, "M", 2), as_real_array(q, "q", 1), as_real_array(z, "z", 1)))
    d["natural"] = d["residual"]
    return d
