"""Faceting the friction cone: an FCLib problem (the friction-contact
community's exchange format, read and written by :mod:`lcpsim.io.fclib`) as
lcpsim's Stewart–Trinkle LCP with ``k`` friction directions and back, and the
exact-cone error of a faceted answer.

::

    from lcpsim import faceting
    from lcpsim.io.fclib import read_fclib
    p = read_fclib("BoxesStack1-i100-5.hdf5")            # W (3nc × 3nc), q, mu
    ans = faceting.solve_fclib(p, k=8)                   # faceted LCP, Lemke
    ans.lcp.status, ans.residual, ans.exact_residual     # the faceting error as a number
    faceting.exact_cone_residual(p.W, p.q, p.mu, ans.r)  # any r: natural map / ‖q‖

    s.world.run(500, fclib="out/")                       # every LCP the run solves, one file each
    faceting.export_capture("run.h5", "out/")            # the same from a capture

**The two problems.** An FCLib local problem is ``u = W r + q`` with, per
contact ``(normal, t1, t2)``, ``r`` in the Coulomb cone ``‖r_T‖ ≤ μ r_N`` and
``u + (μ‖u_T‖, 0, 0)`` in its dual, complementary to ``r``. lcpsim's contact
LCP uses ``k`` directions ``d_j = cos(2πj/k) t1 + sin(2πj/k) t2`` per contact
(``C`` = the k × 2 matrix of cosines and sines, ``G = blockdiag(C)``): with the
FCLib ordering split into normals ``n`` and tangents ``t``,

    A00 = W_nn,  A01 = W_nt Gᵀ,  A10 = G W_tn,  A11 = G W_tt Gᵀ,  b = [q_n; G q_t]

and ``μ``, ``E`` as in the simulator; the answer's impulse is
``r = (fn, Gᵀ fd)`` per contact. Conversely the simulator's LCP gives back
``W`` and ``q`` exactly (up to rounding) through ``C⁺ = (2/k) Cᵀ`` for
``k ≥ 3`` — the friction basis spans the tangent plane — which is how
``World.run(..., fclib=DIR)`` and :func:`export_capture` build the Delassus
matrix ``W = J M_b⁻¹ Jᵀ`` in the contact frames. ``k = 2`` spans one tangent
only and cannot be exported.

**Exact-cone residual** (Acary, Brémond & Huber 2018, natural map with
ρ = 1): ``‖r − P_K(r − (u + Φ(u)))‖₂ / ‖q‖₂`` over all contacts, zero exactly
at a Coulomb solution. libfclib's ``fclib_merit_local`` computes the same
numerator but divides by ``1 + sqrt(‖q‖)``: :func:`fclib_merit` reproduces it.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._core import ContactLayout
from .contact import ContactLcpMixin
from .io.fclib import FclibError, FclibLocal, FclibSolution, write_fclib
from .lcp import lcp_residual, solve_lcp
from .result import LcpResult

__all__ = [
    "friction_basis",
    "FacetedLcp",
    "to_lcp",
    "from_contact_lcp",
    "natural_map",
    "exact_cone_residual",
    "fclib_merit",
    "FclibAnswer",
    "solve_fclib",
    "FclibExporter",
    "export_capture",
]


def friction_basis(k: int) -> NDArray[np.float64]:
    """``C`` (k × 2): ``(cos 2πj/k, sin 2πj/k)``, with 0 and ±1 exact as in the simulator."""
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 2:
        raise ValueError(f"k (friction directions) must be an integer ≥ 2, got {k!r}")
    a = 2.0 * np.pi * np.arange(k) / k
    C = np.stack([np.cos(a), np.sin(a)], axis=1)
    C[np.abs(C) < 1e-15] = 0.0
    ones = np.abs(np.abs(C) - 1.0) < 1e-15
    C[ones] = np.sign(C[ones])
    return C


def _split_order(nc: int) -> NDArray[np.int64]:
    """FCLib index of ``[normals (nc); tangents (c, a) → nc + 2c + a]``."""
    c = np.arange(nc)
    return np.concatenate([3 * c, (3 * c[:, None] + 1 + np.arange(2)).reshape(-1)])


# ---------------------------------------------------------------- FCLib → LCP


@dataclass(frozen=True)
class FacetedLcp(ContactLcpMixin):
    """The Stewart–Trinkle LCP of an FCLib problem: ``M``, ``q`` at cone scale
    ``scale`` (``D M D``, ``D q``), ``unscaled_M``, ``unscaled_q`` at s = 1."""

    M: NDArray[np.float64]  # D M D at s = scale
    q: NDArray[np.float64]  # D q
    unscaled_M: NDArray[np.float64]  # at s = 1
    unscaled_q: NDArray[np.float64]  # at s = 1
    nc: int
    k: int
    scale: float

    def impulse(self, z: ArrayLike) -> NDArray[np.float64]:
        """FCLib's ``r`` (normal, t1, t2 per contact) of an LCP answer ``z``
        (fn and fd do not depend on the scale)."""
        return _impulse(np.asarray(z, dtype=np.float64), self.nc, self.k)


def _impulse(z: NDArray[np.float64], nc: int, k: int) -> NDArray[np.float64]:
    lay = ContactLayout(nc, k)
    r = np.empty(3 * nc)
    r[0::3] = z[lay.fn]
    rt = z[lay.fd].reshape(nc, k) @ friction_basis(k)
    r[1::3], r[2::3] = rt[:, 0], rt[:, 1]
    return r


def to_lcp(problem: FclibLocal, k: int = 8, scale: float | None = None) -> FacetedLcp:
    """The faceted LCP (``k`` directions per contact in its tangent frame,
    ``d_0 = t1``) of an FCLib local problem, at cone scale ``scale`` (None = 1)."""
    if problem.V is not None:
        raise FclibError("local problems with equality constraints (V, R) are not supported by the faceted LCP")
    s = _scale(scale)
    nc = problem.nc
    o = _split_order(nc)
    M, q = _assemble(problem.dense_W()[np.ix_(o, o)], np.asarray(problem.q)[o], problem.mu, k)
    Ms, qs = ContactLayout(nc, k).scale_lcp(M, q, s)
    return FacetedLcp(M=Ms, q=qs, unscaled_M=M, unscaled_q=q, nc=nc, k=k, scale=s)


def _assemble(
    W: NDArray[np.float64], qq: NDArray[np.float64], mu: NDArray[np.float64], k: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The unscaled LCP ``(M, q)`` of ``W``, ``q`` split as ``[normals; tangents]`` (:func:`_split_order`)."""
    nc = mu.shape[0]
    C = friction_basis(k)
    n_, t_ = slice(0, nc), slice(nc, 3 * nc)
    lay = ContactLayout(nc, k)
    M = np.zeros((lay.n, lay.n))
    fn, fd, lam = lay.fn, lay.fd, lay.lam
    M[fn, fn] = W[n_, n_]
    M[fn, fd] = (W[n_, t_].reshape(nc, nc, 2) @ C.T).reshape(nc, nc * k)
    M[fd, fn] = np.einsum("ja,cai->cji", C, W[t_, n_].reshape(nc, 2, nc)).reshape(nc * k, nc)
    Wtt = W[t_, t_].reshape(nc, 2, nc, 2)
    M[fd, fd] = np.einsum("ia,cadb,jb->cidj", C, Wtt, C, optimize=True).reshape(nc * k, nc * k)
    E = np.kron(np.eye(nc), np.ones((k, 1)))
    M[fd, lam] = E
    M[lam, fd] = -E.T
    M[lam, fn] = np.diag(mu)
    q = np.zeros(lay.n)
    q[fn] = qq[n_]
    q[fd] = (qq[t_].reshape(nc, 2) @ C.T).reshape(-1)
    return M, q


def _scale(scale: Any) -> float:
    if scale is None:
        return 1.0
    if isinstance(scale, bool) or not isinstance(scale, (int, float, np.integer, np.floating)):
        raise ValueError(f"scale must be a positive number or None (an FCLib problem has no time step), got {scale!r}")
    s = float(scale)
    if not (np.isfinite(s) and s > 0):
        raise ValueError(f"scale must be a positive finite number, got {scale!r}")
    return s


# ---------------------------------------------------------------- LCP → FCLib


def from_contact_lcp(
    M: ArrayLike,
    q: ArrayLike,
    nc: int,
    k: int,
    scale: float = 1.0,
    *,
    z: ArrayLike | None = None,
    tol: float = 1e-9,
    title: str | None = None,
    description: str | None = None,
    math_info: str | None = None,
) -> FclibLocal:
    """The FCLib local problem of a simulator contact LCP (``M``, ``q`` at cone
    scale ``scale``, as captured): ``W`` and ``q`` in the contact frames, ``μ``.
    Checks that ``M`` has the Stewart–Trinkle structure with the simulator's
    friction basis (relative tolerance ``tol``). With ``z`` (the solver's
    answer) the faceted answer ``(u, r)`` is stored as guess 1 — not as the
    solution: it solves the faceted problem, not necessarily the Coulomb one.
    ``title``, ``description``, ``math_info``: the file's info strings."""
    if k < 3:
        raise FclibError(f"an LCP with k = {k} friction directions spans one tangent only; FCLib needs both (k ≥ 3)")
    lay = ContactLayout(nc, k)
    Ms = np.asarray(M, dtype=np.float64)
    qs = np.asarray(q, dtype=np.float64)
    if Ms.shape != (lay.n, lay.n) or qs.shape != (lay.n,):
        raise FclibError(f"M is {Ms.shape} and q {qs.shape}; nc = {nc}, k = {k} needs n = {lay.n}")
    d = 1.0 / lay.cone_diagonal(scale)
    M1, q1 = d[:, None] * Ms * d[None, :], d * qs  # the physical (s = 1) LCP
    fn, fd, lam = lay.fn, lay.fd, lay.lam
    C = friction_basis(k)
    Cp = np.linalg.pinv(C)  # (2/k) Cᵀ for k ≥ 3
    Wnt = (M1[fn, fd].reshape(nc, nc, k) @ Cp.T).reshape(nc, 2 * nc)
    Wtn = np.einsum("aj,cji->cai", Cp, M1[fd, fn].reshape(nc, k, nc)).reshape(2 * nc, nc)
    Wtt4 = np.einsum("ai,cidj,bj->cadb", Cp, M1[fd, fd].reshape(nc, k, nc, k), Cp, optimize=True)
    qt = (q1[fd].reshape(nc, k) @ Cp.T).reshape(-1)
    mu = np.diag(M1[lam, fn]).copy()
    W = np.block([[M1[fn, fn], Wnt], [Wtn, Wtt4.reshape(2 * nc, 2 * nc)]])
    qsplit = np.concatenate([q1[fn], qt])
    Mb, qb = _assemble(W, qsplit, np.abs(mu), k)
    err = max(np.abs(Mb - M1).max(initial=0.0), np.abs(qb - q1).max(initial=0.0))
    size = np.abs(M1).max(initial=0.0) + np.abs(q1).max(initial=0.0)
    if np.any(mu < 0) or err > tol * max(size, 1e-300):
        raise FclibError(
            f"M is not a Stewart–Trinkle contact LCP with nc = {nc}, k = {k} and the friction basis "
            f"d_j = cos(2πj/k) t1 + sin(2πj/k) t2 (rebuilt from its W it differs by {err:.3e})"
        )
    # Entries that are zero in exact arithmetic come back as ±1e-17 from the basis change: keep W sparse.
    W[np.abs(W) <= 1e-14 * np.abs(W).max(initial=0.0)] = 0.0
    prob = FclibLocal(
        W=_fclib_order(W, nc), q=_fclib_vec(qsplit, nc), mu=mu,
        title=title, description=description, math_info=math_info,
    )
    if z is not None:
        zz = lay.unscale_z(np.asarray(z, dtype=np.float64), scale)
        if np.all(np.isfinite(zz)):
            r = _impulse(zz, nc, k)
            prob.guesses.append(FclibSolution(u=prob.W @ r + prob.q, r=r))
    return prob


def _fclib_order(Wsplit: NDArray[np.float64], nc: int) -> NDArray[np.float64]:
    o = _split_order(nc)
    W = np.empty_like(Wsplit)
    W[np.ix_(o, o)] = Wsplit
    return W


def _fclib_vec(v: NDArray[np.float64], nc: int) -> NDArray[np.float64]:
    out = np.empty_like(v)
    out[_split_order(nc)] = v
    return out


# ---------------------------------------------------------------- residuals


def _project_cone(x: NDArray[np.float64], mu: NDArray[np.float64]) -> NDArray[np.float64]:
    """Projection of each row ``(x_N, x_T1, x_T2)`` onto ``‖r_T‖ ≤ μ r_N``."""
    xn, xt = x[:, 0], x[:, 1:]
    nt = np.hypot(xt[:, 0], xt[:, 1])
    out = x.copy()
    polar = mu * nt <= -xn
    inside = nt <= mu * xn
    side = ~(polar | inside)
    rn = (mu * nt + xn) / (mu * mu + 1.0)
    out[polar] = 0.0
    out[side, 0] = rn[side]
    with np.errstate(invalid="ignore", divide="ignore"):
        out[side, 1:] = (mu * rn / nt)[side, None] * xt[side]
    return out


def natural_map(W: Any, q: ArrayLike, mu: ArrayLike, r: ArrayLike) -> NDArray[np.float64]:
    """``F(r) = r − P_K(r − (u + Φ(u)))`` per contact (nc × 3), ``u = W r + q``,
    ``Φ(u) = (μ‖u_T‖, 0, 0)``: zero iff ``r`` solves the Coulomb problem."""
    r = np.asarray(r, dtype=np.float64).reshape(-1)
    mu = np.asarray(mu, dtype=np.float64).reshape(-1)
    u = (W @ r + np.asarray(q, dtype=np.float64)).reshape(-1, 3)
    r3 = r.reshape(-1, 3)
    uh = u.copy()
    uh[:, 0] += mu * np.hypot(u[:, 1], u[:, 2])
    return r3 - _project_cone(r3 - uh, mu)


def exact_cone_residual(W: Any, q: ArrayLike, mu: ArrayLike, r: ArrayLike) -> float:
    """``‖natural_map‖₂ / ‖q‖₂`` (Acary et al. 2018; ‖q‖ = 0 → unnormalised)."""
    F = natural_map(W, q, mu, r)
    nq = float(np.linalg.norm(q))
    return float(np.linalg.norm(F)) / (nq if nq > 0 else 1.0)


def fclib_merit(W: Any, q: ArrayLike, mu: ArrayLike, r: ArrayLike) -> float:
    """libfclib's ``fclib_merit_local(…, MERIT_1, …)``: the same numerator over ``1 + sqrt(‖q‖₂)``."""
    return float(np.linalg.norm(natural_map(W, q, mu, r))) / (1.0 + np.sqrt(np.linalg.norm(q)))


# ---------------------------------------------------------------- solve


@dataclass(frozen=True)
class FclibAnswer:
    """The faceted LCP's answer to an FCLib problem. ``lcp``: the solver's
    result on the scaled LCP; ``residual``: ‖min(z, Mz+q)‖∞ of the
    physical z on the unscaled LCP; ``r``, ``u``: FCLib impulse and velocity;
    ``exact_residual``: :func:`exact_cone_residual` of ``r``."""

    lcp: LcpResult
    faceted: FacetedLcp
    r: NDArray[np.float64]
    u: NDArray[np.float64]
    residual: float
    exact_residual: float

    @property
    def ok(self) -> bool:
        return self.lcp.ok

    def to_dict(self) -> dict[str, Any]:
        return {
            "status": self.lcp.status,
            "ok": self.lcp.ok,
            "pivots": self.lcp.pivots,
            "k": self.faceted.k,
            "scale": self.faceted.scale,
            "contacts": self.faceted.nc,
            "lcp_size": int(self.faceted.q.shape[0]),
            "residual": self.residual,
            "exact_residual": self.exact_residual,
            "r": self.r.tolist(),
            "u": self.u.tolist(),
        }


def solve_fclib(problem: FclibLocal, k: int = 8, scale: float | None = None, **options: Any) -> FclibAnswer:
    """Solves an FCLib local problem as the faceted LCP (``k`` directions, cone
    scale ``scale``) with :func:`lcpsim.solve_lcp` (``options`` as there)."""
    lcp = to_lcp(problem, k, scale)
    res = solve_lcp(lcp.M, lcp.q, **options)
    z = lcp.layout.unscale_z(res.z, lcp.scale)
    r = lcp.impulse(z)
    u = np.asarray(problem.W @ r + problem.q, dtype=np.float64)
    return FclibAnswer(
        lcp=res,
        faceted=lcp,
        r=r,
        u=u,
        residual=float(lcp_residual(lcp.unscaled_M, lcp.unscaled_q, z)),
        exact_residual=exact_cone_residual(problem.W, problem.q, problem.mu, r),
    )


# ---------------------------------------------------------------- export


class FclibExporter:
    """Writes every LCP of a run as an FCLib file in ``directory`` — the
    capture sink of ``World.run(..., fclib=DIR)``: one file per step and
    island, ``step0000123-island000.hdf5`` (``runN-`` before it from the
    second run on), with the solver's faceted answer as guess 1."""

    def __init__(self, directory: str | os.PathLike[str], metadata: Mapping[str, Any] | None = None, *, storage: str = "csc") -> None:
        self.directory = Path(directory)
        self.directory.mkdir(parents=True, exist_ok=True)
        self.storage = storage
        self.paths: list[Path] = []
        self._run = -1
        self._meta = dict(metadata or {})

    def begin_run(self, metadata: Mapping[str, Any] | None = None) -> int:
        self._run += 1
        if metadata:
            self._meta = dict(metadata)
        return self._run

    def _name(self, step: int, island: int, index: int | None = None) -> Path:
        run = f"run{self._run}-" if self._run > 0 else ""
        if step < 0:  # not from a simulation: the capture's record number
            return self.directory / f"{run}lcp{index or 0:07d}.hdf5"
        return self.directory / f"{run}step{step:07d}-island{island:03d}.hdf5"

    def append(self, captured: Mapping[str, Any]) -> int:
        """A batch in the compiled module's capture layout (see :class:`lcpsim.CaptureWriter`)."""
        n = np.asarray(captured["n"], dtype=np.int64)
        M, q, z = (np.asarray(captured[key], dtype=np.float64) for key in ("M", "q", "z"))
        mo = vo = 0
        for b, nb in enumerate(n.tolist()):
            Mb, qb, zb = M[mo : mo + nb * nb].reshape(nb, nb), q[vo : vo + nb], z[vo : vo + nb]
            mo, vo = mo + nb * nb, vo + nb
            step, island = int(captured["step"][b]), int(captured["island"][b])
            self._write(Mb, qb, zb, int(captured["contacts"][b]), int(captured["friction_dirs"][b]),
                        float(captured["scale"][b]), step, island, float(captured["time"][b]))
        return int(n.size)

    def _write(
        self, M: Any, q: Any, z: Any, nc: int, k: int, s: float, step: int, island: int, time: float,
        index: int | None = None,
    ) -> None:
        if nc == 0:
            return
        from . import __version__

        scene = self._meta.get("scene") or "simulation"
        prob = from_contact_lcp(
            M, q, nc, k, s, z=z,
            title=f"lcpsim {scene}: step {step}, island {island}",
            description=f"time {time:.6g} s, {nc} contacts; simulator LCP with k = {k} friction directions, cone scale {s:g}",
            math_info=f"written by lcpsim {__version__}; W = J M_b^-1 J^T in the contact frames (normal, t1, t2); "
            "guess 1 is lcpsim's faceted-cone answer",
        )
        self.paths.append(write_fclib(self._name(step, island, index), prob, storage=self.storage))

    def flush(self) -> None:
        """Every file is complete when written."""

    def close(self) -> None:
        """Nothing held open."""


def export_capture(
    capture: str | os.PathLike[str],
    directory: str | os.PathLike[str],
    *,
    indices: Sequence[int] | None = None,
    storage: str = "csc",
) -> list[Path]:
    """Writes LCPs of a capture (all, or ``indices``) as FCLib files into
    ``directory``; returns their paths. Any capture version works: the Delassus
    matrix is rebuilt from the captured ``M`` (needs ``k ≥ 3``)."""
    from .io.capture import open_capture

    out = FclibExporter(directory, storage=storage)
    with open_capture(capture) as c:
        out.begin_run(c.metadata)
        records = c.records() if indices is None else (c[i] for i in indices)
        for rec in records:
            out._run = rec.run
            out._write(
                rec.M, rec.q, rec.z, rec.contacts, rec.friction_dirs, rec.scale, rec.step, rec.island, rec.time,
                rec.index,
            )
    return out.paths
