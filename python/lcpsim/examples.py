"""Small built-in contact LCPs with the structure of DESIGN §1, for the demo,
the tests and quick experiments (the simulator will produce the real ones).

A unit cube resting on a plane tilted by ``theta`` (the plane's frame: x
downhill, z along the normal), four contacts at its bottom corners, ``k``
friction directions ``d_j = cos(2πj/k) x + sin(2πj/k) y`` (so the slope is
aligned with direction 0). Unknowns are impulses (N·s) ordered
``z = [fn (nc); fd (nc·k); λ (nc)]`` and the LCP is

    M = [[A00, A01, 0], [A10, A11, s·E], [s·μ·I, −s·Eᵀ, 0]],  q = [J_n v*; J_d v*; 0]

with ``A = J M_b⁻¹ Jᵀ``, ``v* = v0 + h g`` and the friction-cone scale ``s``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["ContactLcp", "cube_on_slope_lcp"]

G = 9.81


@dataclass(frozen=True)
class ContactLcp:
    """A contact LCP and what it was built from."""

    M: NDArray[np.float64]
    q: NDArray[np.float64]
    nc: int
    k: int
    mu: float
    h: float
    s: float
    theta_deg: float
    mass: float

    def split(self, z: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """``(fn, fd, λ)`` of a solution ``z``; ``fd`` has shape (nc, k)."""
        nc, k = self.nc, self.k
        return z[:nc], z[nc : nc + nc * k].reshape(nc, k), z[nc + nc * k :]


def _cross_matrix_rows(r: NDArray[np.float64], dirs: NDArray[np.float64]) -> NDArray[np.float64]:
    """Jacobian rows ``[d, r × d]`` for each direction ``d`` in ``dirs`` (m×3)."""
    return np.hstack([dirs, np.cross(r, dirs)])


def cube_on_slope_lcp(
    theta_deg: float = 0.0,
    mu: float = 0.5,
    *,
    h: float = 1e-3,
    k: int = 8,
    s: float = 1.0,
    mass: float = 1.0,
    side: float = 1.0,
    v0: tuple[float, float, float] = (0.0, 0.0, 0.0),
) -> ContactLcp:
    """The contact LCP of one time step of a cube at rest (or moving at ``v0``,
    in the plane's frame) on a plane tilted by ``theta_deg``. Size 4·(k + 2)."""
    th = np.deg2rad(theta_deg)
    g = G * np.array([np.sin(th), 0.0, -np.cos(th)])
    a = side / 2.0
    corners = np.array([[sx * a, sy * a, -a] for sx in (-1, 1) for sy in (-1, 1)])
    nc = len(corners)
    normal = np.array([[0.0, 0.0, 1.0]])
    ang = 2.0 * np.pi * np.arange(k) / k
    dirs = np.stack([np.cos(ang), np.sin(ang), np.zeros(k)], axis=1)

    # Contact Jacobians in the space of [v; ω] (6 dof).
    Jn = np.vstack([_cross_matrix_rows(r, normal) for r in corners])
    Jd = np.vstack([_cross_matrix_rows(r, dirs) for r in corners])
    inertia = mass * side**2 / 6.0
    Minv = np.diag([1 / mass] * 3 + [1 / inertia] * 3)
    v_star = np.concatenate([np.asarray(v0, dtype=float) + h * g, np.zeros(3)])

    J = np.vstack([Jn, Jd])
    A = J @ Minv @ J.T
    b = J @ v_star
    E = np.kron(np.eye(nc), np.ones((k, 1)))  # (nc·k) × nc

    nf = nc * k
    n = nc + nf + nc
    M = np.zeros((n, n))
    M[: nc + nf, : nc + nf] = A
    M[nc : nc + nf, nc + nf :] = s * E
    M[nc + nf :, :nc] = s * mu * np.eye(nc)
    M[nc + nf :, nc : nc + nf] = -s * E.T
    q = np.concatenate([b, np.zeros(nc)])
    return ContactLcp(M=M, q=q, nc=nc, k=k, mu=mu, h=h, s=s, theta_deg=theta_deg, mass=mass)
