"""Seeded test LCPs from the Rust generators (``lcp::generate``).

Every generator is deterministic per seed, across platforms, and returns a
:class:`GeneratedLcp`: ``M`` (n×n), ``q`` (n), a ``label`` naming the
generator and its arguments, and for contact LCPs the layout ``(nc, k)`` and
the friction-cone scale ``s``::

    from lcpsim import generate
    p = generate.contact_lcp(nc=4, scale=1e-3, seed=7)   # 40×40, z = [fn; fd; λ]
    res = lcpsim.solve_lcp(p.M, p.q)
    p.physical_residual(res.z)     # ‖min(z, w)‖∞ of D z on the unscaled (s = 1) problem

A contact LCP at scale ``s`` is ``D M₁ D, D q₁`` with ``D = diag(I, I, s·I)``
and ``(M₁, q₁)`` the same scene unscaled: its solutions map back as
``z_phys = D z`` (``fn``, ``fd`` unchanged, ``λ = s·λ_scaled``).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core

__all__ = [
    "HARD_KINDS",
    "GeneratedLcp",
    "contact_lcp",
    "spd_lcp",
    "p_matrix_lcp",
    "hard_contact_lcp",
    "hard_corpus",
]

#: The hard-contact families of :func:`hard_contact_lcp`.
HARD_KINDS: tuple[str, ...] = tuple(_core.HARD_KINDS)

_HARD_LABEL = re.compile(r"^(?P<kind>[a-z_]+)/k(?P<k>\d+)/nc(?P<nc>\d+)/seed(?P<seed>\d+)$")


@dataclass(frozen=True)
class GeneratedLcp:
    """One generated LCP ``(M, q)`` and how it was made.

    ``nc`` and ``k`` are the contact layout (``None`` for non-contact LCPs),
    ``scale`` the friction-cone scale ``s`` (1.0 for non-contact LCPs).
    """

    M: NDArray[np.float64]
    q: NDArray[np.float64]
    label: str
    nc: int | None = None
    k: int | None = None
    scale: float = 1.0
    # Regenerates the same scene at another scale (contact LCPs).
    _regen: Callable[[float], GeneratedLcp] | None = field(default=None, repr=False, compare=False)

    @property
    def n(self) -> int:
        """Problem size."""
        return int(self.q.shape[0])

    @property
    def is_contact(self) -> bool:
        """Whether the problem has the contact structure ``z = [fn; fd; λ]``."""
        return self.nc is not None and self.k is not None

    @property
    def layout(self) -> _core.ContactLayout | None:
        """Where fn, fd, λ live in ``z`` (None if not a contact LCP)."""
        return None if self.nc is None or self.k is None else _core.ContactLayout(self.nc, self.k)

    def cone_diagonal(self) -> NDArray[np.float64]:
        """``D = diag(I, I, s·I)`` of the friction-cone scaling (all ones if not a contact LCP)."""
        lay = self.layout
        return np.ones(self.n) if lay is None else lay.cone_diagonal(self.scale)

    def to_physical(self, z: ArrayLike) -> NDArray[np.float64]:
        """``z_phys = D z``: impulses of the unscaled problem (λ multiplied by ``s``)."""
        return self.cone_diagonal() * np.asarray(z, dtype=np.float64)

    def at_scale(self, scale: float) -> GeneratedLcp:
        """The same problem (same scene) at friction-cone scale ``scale``.

        Non-contact problems have no scale and are returned unchanged.
        """
        if not self.is_contact:
            return self
        if scale == self.scale:
            return self
        if self._regen is None:
            raise ValueError(f"cannot regenerate {self.label!r} at another scale")
        return self._regen(scale)

    def residual(self, z: ArrayLike) -> float:
        """‖min(z, M z + q)‖∞ in the units of this (possibly scaled) problem."""
        z = np.asarray(z, dtype=np.float64)
        return float(np.max(np.abs(np.minimum(z, self.M @ z + self.q))))

    def physical_residual(self, z: ArrayLike) -> float:
        """‖min(z_phys, M₁ z_phys + q₁)‖∞ with ``z_phys = D z`` on the unscaled
        problem ``(M₁, q₁)`` (regenerated at s = 1): impulses in N·s, velocities in m/s.
        Equal to :meth:`residual` for a non-contact or unscaled problem.
        """
        if not self.is_contact or self.scale == 1.0:
            return self.residual(z)
        return self.at_scale(1.0).residual(self.to_physical(z))


def _contact(
    t: tuple[NDArray[np.float64], NDArray[np.float64], str, int, int],
    scale: float,
    regen: Callable[[float], GeneratedLcp],
) -> GeneratedLcp:
    m, q, label, nc, k = t
    return GeneratedLcp(m, q, label, nc=nc, k=k, scale=float(scale), _regen=regen)


def contact_lcp(nc: int, k: int = 8, scale: float = 1.0, seed: int = 0) -> GeneratedLcp:
    """The contact LCP of a 1 kg unit cube on a random slope (0–60°),
    ``nc`` contacts on its bottom face (corners first), ``k`` friction directions,
    random μ in [0.1, 1.5] and velocity, h = 0.01, friction-cone scale ``scale``.
    Size ``nc·(k + 2)``.
    """
    t = _core.contact_lcp(nc, k, scale, seed)  # the glue checks the integers
    return _contact(t, scale, lambda s: contact_lcp(nc, k, s, seed))


def spd_lcp(n: int, seed: int = 0) -> GeneratedLcp:
    """Random LCP with ``M = A Aᵀ/n + 0.1 I`` (symmetric positive definite), ``q`` uniform in [−1, 1]."""
    m, q, label = _core.spd_lcp(n, seed)
    return GeneratedLcp(m, q, label)


def p_matrix_lcp(n: int, seed: int = 0) -> GeneratedLcp:
    """Random LCP with a nonsymmetric positive definite (hence P) matrix: a unique solution."""
    m, q, label = _core.p_matrix_lcp(n, seed)
    return GeneratedLcp(m, q, label)


def hard_contact_lcp(kind: str, scale: float = 1.0, seed: int = 0, k: int = 8) -> GeneratedLcp:
    """A hard contact LCP of family ``kind`` (one of :data:`HARD_KINDS`): many,
    duplicate, nearly parallel or collinear contacts, mass ratios to 1e4,
    ill-conditioned bodies, μ in [0, 2]. The label is ``kind/kK/ncN/seedS``.
    """
    t = _core.hard_contact_lcp(kind, scale, seed, k)
    return _contact(t, scale, lambda s: hard_contact_lcp(kind, s, seed, k))


def hard_corpus(seed: int, count: int, scale: float = 1.0) -> list[GeneratedLcp]:
    """``count`` hard contact LCPs cycling through the families (k = 8 mostly, some 4 and 16).
    The same ``seed`` gives the same scenes at every scale.
    """
    out = []
    for t in _core.hard_corpus(seed, count, scale):
        match = _HARD_LABEL.match(t[2])
        if match is None:  # pragma: no cover - the Rust label format is fixed
            raise RuntimeError(f"unexpected hard-corpus label {t[2]!r}")
        kind, item_seed, k = match["kind"], int(match["seed"]), int(match["k"])
        out.append(_contact(t, scale, partial(hard_contact_lcp, kind, seed=item_seed, k=k)))
    return out
