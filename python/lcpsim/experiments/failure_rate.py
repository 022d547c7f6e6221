"""Failure rate of a solver over the seed corpus at several friction-cone scales.

The seed note counted Lemke failures over the LCPs of one simulation at
s = 1e-3, 1e-4 and 1e-6 (DESIGN §2: 3.9 %, ≈ 2.1 %, 0). Here, by default
(``mode = "resolve"``), the *same* LCPs — the seed corpus, assembled unscaled
along physical trajectories — are scaled by each s (``D M D``, ``D q``) and
solved with the chosen solver, so that the rates at different scales compare
one solver on one set of problems. ``mode = "simulate"`` instead re-runs every
corpus simulation with the solver and the scale in the loop, as the seed did
(its trajectories, and so its LCPs, then differ from scale to scale, and a
failed step feeds the next one).

A failure is either (report both counts):

* a **status failure**: the solver returned a status other than ``solved``;
* a **residual failure**: the answer mapped back to physical units (fn, fd
  unchanged, ``λ = s·λ_scaled``) has a natural residual ``‖min(z, w)‖∞``
  above ``tol`` on the *unscaled* LCP — whatever the solver said. An answer
  the solver called ``solved`` that fails here is counted in
  ``accepted_wrong``: the tolerance artifact of DESIGN §2.

``failures`` is the union, ``rate = failures / lcps``.
"""

from __future__ import annotations

import time
from typing import Any, Mapping

import numpy as np

from ._common import envelope, merge_config, parse_scale, scale_label, scale_value
from .presets import parse_solver
from .seed_corpus import DEFAULTS as CORPUS_DEFAULTS
from .seed_corpus import build_world, generate, simulations, solve_scaled

__all__ = ["DEFAULTS", "run", "SEED_VALUES"]

DEFAULTS: dict[str, Any] = {
    "seed": 0,
    "scales": ["none", 1e-3, 1e-4, 1e-6],
    "solver": "robust",
    "tol": 1e-6,
    "mode": "resolve",
    "corpus": {},
    "max_lcps": None,
    "threads": 0,
}

#: The seed note's rates (fraction of LCPs) by scale.
SEED_VALUES: dict[str, float] = {"0.001": 97 / 2499, "0.0001": 0.0208, "1e-06": 0.0}


def _corpus_config(cfg: Mapping[str, Any]) -> dict[str, Any]:
    c = {**dict(cfg.get("corpus") or {})}
    c.setdefault("seed", cfg["seed"])
    unknown = set(c) - set(CORPUS_DEFAULTS)
    if unknown:
        raise ValueError(f"corpus: unknown key(s) {sorted(unknown)} (valid: {', '.join(sorted(CORPUS_DEFAULTS))})")
    return c


def run(config: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Runs the experiment; returns ``{"rows": [{"scale", "lcps", "failures", "rate", …}], …}``."""
    t0 = time.perf_counter()
    cfg = merge_config("failure-rate", DEFAULTS, config)
    scales = [parse_scale(s) for s in (cfg["scales"] if not isinstance(cfg["scales"], str) else cfg["scales"].split(","))]
    solver = parse_solver(cfg["solver"])
    tol = float(cfg["tol"])
    mode = str(cfg["mode"])
    if mode not in ("resolve", "simulate"):
        raise ValueError(f"failure-rate: mode must be 'resolve' or 'simulate', got {mode!r}")
    ccfg = _corpus_config(cfg)
    dt = float(ccfg.get("dt", CORPUS_DEFAULTS["dt"]))
    rows = []
    corpus_summary: dict[str, Any]
    if mode == "resolve":
        corpus = generate(ccfg).subsample(cfg["max_lcps"], int(cfg["seed"]))
        corpus_summary = corpus.summary()
        for scale in scales:
            s = scale_value(scale, dt)
            acc = _Acc()
            for g in corpus.groups:
                r = solve_scaled(g, solver, s, threads=int(cfg["threads"]))
                acc.add(r.status, r.residual, r.pivots, tol, size=g.n)
            rows.append({"scale": scale_label(scale), "s": s, **acc.row()})
    else:
        sims = simulations(ccfg)
        corpus_summary = {"simulations": [sp.name for sp in sims]}
        for scale in scales:
            s = scale_value(scale, dt)
            acc = _Acc()
            for spec in sims:
                world, _ = build_world(
                    spec, dt=dt, friction_dirs=int(ccfg.get("friction_dirs", 8)), scale=scale, solver=solver
                )
                traj = world.run(spec.steps)
                has = traj.status != "no_contact"
                acc.add(tuple(traj.status[has]), traj.residual[has], traj.pivots[has], tol, size=traj.lcp_size[has])
            rows.append({"scale": scale_label(scale), "s": s, **acc.row()})
    out = envelope("failure-rate", cfg, t0)
    out.update(
        {
            "solver": solver.to_dict(),
            "mode": mode,
            "tol": tol,
            "corpus": corpus_summary,
            "rows": rows,
            "seed_values": SEED_VALUES,
        }
    )
    out["wall_time_s"] = time.perf_counter() - t0
    return out


class _Acc:
    """Counts over batches of answers."""

    def __init__(self) -> None:
        self.lcps = 0
        self.status_fail = 0
        self.resid_fail = 0
        self.union = 0
        self.accepted_wrong = 0
        self.by_status: dict[str, int] = {}
        self.max_res_solved = 0.0
        self.pivots: list[np.ndarray] = []
        self.by_size: dict[int, list[int]] = {}

    def add(self, status: tuple[str, ...], residual: np.ndarray, pivots: np.ndarray, tol: float, size: Any) -> None:
        st = np.asarray(status)
        ok = st == "solved"
        bad_r = ~(np.asarray(residual) <= tol)  # NaN counts as a failure
        fail = ~ok | bad_r
        self.lcps += len(st)
        self.status_fail += int((~ok).sum())
        self.resid_fail += int(bad_r.sum())
        self.union += int(fail.sum())
        self.accepted_wrong += int((ok & bad_r).sum())
        for s in np.unique(st):
            self.by_status[str(s)] = self.by_status.get(str(s), 0) + int((st == s).sum())
        if ok.any():
            self.max_res_solved = max(self.max_res_solved, float(np.nanmax(np.asarray(residual)[ok])))
        self.pivots.append(np.asarray(pivots))
        sizes = np.broadcast_to(np.asarray(size), st.shape)
        for n in np.unique(sizes):
            m = sizes == n
            e = self.by_size.setdefault(int(n), [0, 0])
            e[0] += int(m.sum())
            e[1] += int(fail[m].sum())

    def row(self) -> dict[str, Any]:
        n = max(self.lcps, 1)
        piv = np.concatenate(self.pivots) if self.pivots else np.zeros(0)
        return {
            "lcps": self.lcps,
            "failures": self.union,
            "rate": self.union / n,
            "status_failures": self.status_fail,
            "status_rate": self.status_fail / n,
            "residual_failures": self.resid_fail,
            "residual_rate": self.resid_fail / n,
            "accepted_wrong": self.accepted_wrong,
            "by_status": dict(sorted(self.by_status.items())),
            "max_residual_solved": self.max_res_solved,
            "pivots_median": float(np.median(piv)) if piv.size else 0.0,
            "pivots_max": int(piv.max(initial=0)),
            "by_size": {str(k): {"lcps": v[0], "failures": v[1]} for k, v in sorted(self.by_size.items())},
        }
