"""Small built-in contact LCPs for the demo, the tests and quick experiments,
taken from the simulator itself (the LCP of its first step).

A cube resting on a plane tilted by ``theta``, seen in the plane's frame:
the ground is level and gravity ``g·(sin θ, 0, −cos θ)`` points down the
slope along x; four contacts at the bottom corners, ``k`` friction
directions ``d_j = cos(2πj/k) x + sin(2πj/k) y`` (so the slope is aligned
with direction 0). Unknowns are impulses (N·s) ordered
``z = [fn (nc); fd (nc·k); λ (nc)]`` (see :class:`lcpsim.ContactLayout`)
and the LCP is

    M = [[A00, A01, 0], [A10, A11, s·E], [s·μ·I, −s·Eᵀ, 0]],  q = [J_n v*; J_d v*; 0]

with ``A = J M_b⁻¹ Jᵀ``, ``v* = v0 + h g`` and the friction-cone scale ``s``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .contact import ContactLcpMixin
from .world import World

__all__ = ["ContactLcp", "cube_on_slope_lcp"]

G = 9.81


@dataclass(frozen=True)
class ContactLcp(ContactLcpMixin):
    """A contact LCP and what it was built from (``layout``, ``split``: :class:`~lcpsim.contact.ContactLcpMixin`)."""

    M: NDArray[np.float64]
    q: NDArray[np.float64]
    nc: int
    k: int
    mu: float
    h: float
    s: float
    theta_deg: float
    mass: float


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
    in the plane's frame) on a plane tilted by ``theta_deg``, as the simulator
    assembles it. ``k`` even ≥ 2. Size 4·(k + 2)."""
    th = np.deg2rad(theta_deg)
    gravity = (G * np.sin(th), 0.0, -G * np.cos(th))
    world = World(dt=h, gravity=gravity, friction_dirs=k, cone_scale=s)
    world.add_ground(mu=mu)
    a = side / 2.0
    world.add_box((a, a, a), mass=mass, position=(0.0, 0.0, a), velocity=v0, mu=mu)
    core = world._core
    core.start_capture()
    try:
        core.run(1)
        cap = core.drain_capture()
    finally:
        core.stop_capture()
    n, nc, kk = int(cap["n"][0]), int(cap["contacts"][0]), int(cap["friction_dirs"][0])
    M = np.asarray(cap["M"][: n * n]).reshape(n, n)
    q = np.asarray(cap["q"][:n])
    return ContactLcp(M=M, q=q, nc=nc, k=kk, mu=mu, h=h, s=s, theta_deg=theta_deg, mass=mass)
