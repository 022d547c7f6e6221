"""The slope test's outcome decided by how the motion starts, not
by what a fixed window happens to show.

A μ = 1 cube sliding on a slope steeper than 45° carries its whole load on
the downhill edge; that state is unstable (a tilt φ grows like e^{γt},
γ ≈ 6.4/s for the unit cube), so watched long enough *every* such run ends
on its side — the exact solver's from round-off after ~5 s, the source note's held
cube within a second or two. A window-based verdict therefore reports the
window. Here the per-step records are read from the first step on and the
outcome is the first of these to hold for ``confirm_s`` of consecutive
solved steps (the onset is the first step of that streak):

``tip``
    the cube pivots about its downhill edge: tilt beyond round-off
    (> ``tilt_tol_rad``) and growing, the normal impulse all on the downhill
    contact points (uphill share ≤ ``load_rtol``, or no uphill point), and
    the angular velocity about that edge's axis n × d (positive, the rest
    of ω smaller);
``slide``
    the tilt stays at round-off while the down-slope displacement follows
    ½·g·(sin θ − μ cos θ)·t² within ``slide_rtol`` (and that distance is
    resolvable: ≥ ``pos_tol_m``);
``rest``
    no tilt, no displacement (≤ ``pos_tol_m``), and the uphill contact
    points carry load — the cube stands on its face and cannot pivot; where
    a slide is expected it must exceed 10·``pos_tol_m`` first, so that
    "not moved" is not merely "not moved yet".

Failed LCP steps never count towards a streak. When nothing is confirmed
within the horizon the outcome is ``undecided``. Also measured: the first
excess-friction step, where the friction along the downhill line exceeds
what the exact cone allows, ``|Σ friction·d| > μ·Σfn`` beyond round-off
(``excess_rtol``·μΣfn): the source note's cone slack in use.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._common import G

__all__ = ["OnsetOptions", "Onset", "observe", "cone_excess", "precise_tilt", "OUTCOMES"]

#: Every outcome of the onset classification.
OUTCOMES = ("tip", "slide", "rest", "undecided")


@dataclass(frozen=True)
class OnsetOptions:
    """Thresholds of the onset classification (see the module docs)."""

    #: Tilt (rad) beyond round-off: the exact solver's sliding cube stays below 1e-12 rad for its first
    #: second (round-off grown by the μ = 1 instability), the source note's held cube passes 1e-8 rad within 0.05 s.
    tilt_tol_rad: float = 1e-10
    #: Relative agreement with ½·a·t² that counts as following it (semi-implicit Euler is 1/n ahead).
    slide_rtol: float = 0.05
    #: Smallest displacement (m) that is resolved (float64 positions near 1 m: 1e4 ulps).
    pos_tol_m: float = 1e-12
    #: Uphill share of Σfn below which the contact is the downhill edge alone.
    load_rtol: float = 1e-9
    #: Friction beyond μ·Σfn, relative to μ·Σfn, that is more than round-off.
    excess_rtol: float = 1e-9
    #: How long (s) a state must hold on consecutive solved steps to be unambiguous.
    confirm_s: float = 0.02
    #: Longest the onset is looked for (s) when the run's own window is shorter.
    horizon_s: float = 4.0


@dataclass(frozen=True)
class Onset:
    """The outcome, when it was confirmed, when tipping began and the first excess-friction step
    (times in s after the start, None where it did not happen within ``probed_s``)."""

    outcome: str
    decided_at_s: float | None
    tip_onset_s: float | None
    first_excess_s: float | None
    probed_s: float


def cone_excess(friction_downhill: NDArray[np.float64], fn: NDArray[np.float64], mu: float,
                rtol: float) -> NDArray[np.bool_]:
    """Steps whose friction along the downhill line exceeds μ·Σfn beyond round-off."""
    return np.asarray(np.abs(friction_downhill) - mu * fn > rtol * mu * np.maximum(fn, 1e-300))


def precise_tilt(q: NDArray[np.float64], q0: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotation angle (rad) of unit quaternions ``q`` (…, 4) from ``q0``: 2·atan2(|v|, |w|) of q0* q,
    exact to round-off near 0 (arccos of the dot product resolves only ~1e-8 rad)."""
    w0, x0, y0, z0 = q0
    w, x, y, z = np.moveaxis(np.asarray(q, dtype=float), -1, 0)
    rw = w0 * w + x0 * x + y0 * y + z0 * z
    rx = w0 * x - x0 * w - y0 * z + z0 * y
    ry = w0 * y + x0 * z - y0 * w - z0 * x
    rz = w0 * z - x0 * y + y0 * x - z0 * w
    return np.asarray(2.0 * np.arctan2(np.sqrt(rx * rx + ry * ry + rz * rz), np.abs(rw)))


def _first_streak(p: NDArray[np.bool_], length: int) -> tuple[int, int] | None:
    """(start, end) of the first run of ``length`` consecutive Trues, or None."""
    n = p.size
    idx = np.arange(n)
    last_false = np.maximum.accumulate(np.where(p, -1, idx))
    hits = np.nonzero(idx - last_false >= length)[0]
    if not hits.size:
        return None
    end = int(hits[0])
    return end - length + 1, end


class _Probe:
    """Steps a world one step at a time and keeps, per step, what the classification reads."""

    def __init__(self, world: Any, body: int, downhill: NDArray[np.float64], normal: NDArray[np.float64]) -> None:
        self.world, self.body, self.d = world, body, downhill
        self.axis = np.cross(normal, downhill)  # ω along n × d tips the top downhill
        b0 = world.body(body)
        self.x0, self.q0 = np.array(b0.position, dtype=float), np.array(b0.orientation, dtype=float)
        self.rows: list[tuple[float, ...]] = []

    def step(self) -> None:
        rec = self.world.step()
        b = self.world.body(self.body)
        pos, om = b.position, np.asarray(b.velocity[3:], dtype=float)
        mine = (rec.body_a == self.body) | (rec.body_b == self.body)
        fn = rec.fn[mine]
        uphill = (rec.points[mine] - pos) @ self.d <= 0.0
        om_tip = float(om @ self.axis)
        self.rows.append((
            rec.time + rec.dt,
            float((pos - self.x0) @ self.d),
            float(precise_tilt(b.orientation, self.q0)),
            om_tip,
            float(np.linalg.norm(om - om_tip * self.axis)),
            float(fn[~uphill].sum()),
            float(fn[uphill].sum()),
            float((rec.friction[mine] @ self.d).sum()),
            1.0 if rec.status == "solved" else 0.0,
        ))

    def arrays(self) -> dict[str, NDArray[np.float64]]:
        a = np.array(self.rows, dtype=float).reshape(-1, 9)
        keys = ("t", "x", "tilt", "om_tip", "om_off", "fn_down", "fn_up", "friction_d", "solved")
        return {k: a[:, i] for i, k in enumerate(keys)}


def _decide(f: dict[str, NDArray[np.float64]], angle_deg: float, mu: float, h: float,
            o: OnsetOptions) -> tuple[str, int, int] | None:
    """(outcome, onset index, decision index) of the first confirmed state, or None."""
    th = math.radians(angle_deg)
    acc = max(G * (math.sin(th) - mu * math.cos(th)), 0.0)
    X = 0.5 * acc * f["t"] ** 2
    solved = f["solved"] > 0
    fn = f["fn_down"] + f["fn_up"]
    flat = f["tilt"] <= o.tilt_tol_rad
    growing = np.diff(f["tilt"], prepend=0.0) > 0
    edge = (f["fn_down"] > 0) & (f["fn_up"] <= o.load_rtol * fn)
    tip = solved & edge & ~flat & growing & (f["om_tip"] > 0) & (f["om_off"] < f["om_tip"])
    slide = solved & flat & (X >= o.pos_tol_m) & (np.abs(f["x"] - X) <= o.slide_rtol * X)
    still = np.abs(f["x"]) <= o.pos_tol_m
    rest = solved & flat & still & ~edge & (fn > 0) & ((X == 0) | (X > 10 * o.pos_tol_m))
    length = max(1, int(math.ceil(o.confirm_s / h - 1e-9)))
    found = [(s[1], s[0], name) for name, p in (("tip", tip), ("slide", slide), ("rest", rest))
             if (s := _first_streak(p, length)) is not None]
    if not found:
        return None
    end, start, name = min(found)
    return name, start, end


def observe(world: Any, body: int, downhill: NDArray[np.float64], normal: NDArray[np.float64],
            angle_deg: float, mu: float, steps: int, options: OnsetOptions | None = None) -> Onset:
    """Classifies the cube ``body`` of ``world`` (stepped ``world.copy()``: the caller's world is left
    as it is) by its onset, looking up to ``steps`` steps ahead (at least ``horizon_s``)."""
    o = options or OnsetOptions()
    h = float(world.dt)
    horizon = max(int(steps), int(round(o.horizon_s / h)))
    probe = _Probe(world.copy(), body, np.asarray(downhill, dtype=float), np.asarray(normal, dtype=float))
    decided: tuple[str, int, int] | None = None
    chunk = max(8, int(round(o.confirm_s / h)))
    while decided is None and len(probe.rows) < horizon:
        for _ in range(min(chunk, horizon - len(probe.rows))):
            probe.step()
        f = probe.arrays()
        decided = _decide(f, angle_deg, mu, h, o)
    f = probe.arrays()
    excess = np.nonzero(cone_excess(f["friction_d"], f["fn_down"] + f["fn_up"], mu, o.excess_rtol)
                        & (f["solved"] > 0))[0]
    first_excess = float(f["t"][excess[0]]) if excess.size else None
    if decided is None:
        return Onset("undecided", None, None, first_excess, float(f["t"][-1]) if f["t"].size else 0.0)
    name, start, end = decided
    return Onset(name, float(f["t"][end]), float(f["t"][start]) if name == "tip" else None, first_excess,
                 float(f["t"][-1]))
