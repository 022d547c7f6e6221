"""Contact patterns: the sign of (fn, Σfd, λ) per contact, unscaled and scaled.

The seed's table (DESIGN §2), ``+`` meaning positive, ``0`` zero:

========  ============================================================
(0,0,0)   contact breaks
(0,0,+)   tangential motion, no friction
(0,+,0)   impossible: the cone row μ fn − Σfd ≥ 0 forces fd = 0
(0,+,+)   impossible (same reason)
(+,0,0)   static, no friction needed
(+,0,+)   impossible for an exact solution with μ > 0: the cone slack
          μ fn > 0 and λ > 0 violate complementarity
(+,+,0)   static friction
(+,+,+)   sliding
========  ============================================================

Every seed-corpus LCP is solved unscaled and at scale s with the chosen
solver; each answer is mapped back to physical units (λ = s·λ_scaled) and
each contact's pattern counted by :class:`lcpsim.ContactLayout`'s one zero
rule: a value counts as positive when it is strictly greater than
``zero_rel`` times its LCP's scale — for fn and Σfd the largest impulse of
the LCP or, when larger, its impulse scale ‖q‖∞/max|A| (N·s); for λ ‖q‖∞
(m/s) — so that round-off around an exact zero is zero
(``ContactLayout.zero_levels``, ``ContactLayout.patterns``).
The result has the counts for both solves, the unscaled × scaled cross table
(rows unscaled, columns scaled; pattern order as above) and every LCP where
an impossible pattern occurred (``impossible_lcps``, at most ``max_listed``;
``impossible`` counts them all, in solved answers and in failed ones apart).
"""

from __future__ import annotations

import time
from typing import Any, Mapping

import numpy as np
from numpy.typing import NDArray

from .._core import ContactLayout
from ._common import envelope, merge_config, parse_scale, scale_label, scale_value
from .failure_rate import _corpus_config
from .presets import parse_solver
from .seed_corpus import DEFAULTS as CORPUS_DEFAULTS
from .seed_corpus import Group, ScaledSolve, generate, solve_scaled

__all__ = ["DEFAULTS", "PATTERNS", "IMPOSSIBLE", "run", "contact_patterns"]

#: The 8 patterns (fn, Σfd, λ) in table order, as strings.
PATTERNS: tuple[str, ...] = tuple(ContactLayout.PATTERNS)
#: The impossible ones (with μ > 0).
IMPOSSIBLE: tuple[str, ...] = ("0+0", "0++", "+0+")
MEANING: dict[str, str] = {
    "000": "contact breaks",
    "00+": "tangential motion, no friction",
    "0+0": "impossible (cone row forces fd = 0)",
    "0++": "impossible (cone row forces fd = 0)",
    "+00": "static, no friction",
    "+0+": "impossible (cone slack and λ > 0)",
    "++0": "static friction",
    "+++": "sliding",
}

DEFAULTS: dict[str, Any] = {
    "seed": 0,
    "scale": 1e-3,
    "solver": "robust",
    "corpus": {},
    "max_lcps": None,
    "zero_rel": 1e-9,
    "threads": 0,
    "max_listed": 50,
}


def contact_patterns(g: Group, r: ScaledSolve, zero_rel: float) -> NDArray[np.int64]:
    """(b, nc) pattern codes 0…7 (index into :data:`PATTERNS`) of physical answers ``r``."""
    lay = ContactLayout(g.contacts, g.friction_dirs)
    impulse_zero, velocity_zero = lay.zero_levels(g.M, g.q, r.z, zero_rel)
    codes: NDArray[np.int64] = lay.patterns(r.z, impulse_zero, velocity_zero).astype(np.int64)
    return codes


def run(config: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Runs the census; returns ``{"counts_unscaled", "counts_scaled", "cross", "impossible", "impossible_lcps", …}``."""
    t0 = time.perf_counter()
    cfg = merge_config("patterns", DEFAULTS, config)
    solver = parse_solver(cfg["solver"])
    ccfg = _corpus_config(cfg)
    dt = float(ccfg.get("dt", CORPUS_DEFAULTS["dt"]))
    scale = parse_scale(cfg["scale"])
    s = scale_value(scale, dt)
    zero_rel = float(cfg["zero_rel"])
    corpus = generate(ccfg).subsample(cfg["max_lcps"], int(cfg["seed"]))
    cross = np.zeros((8, 8), dtype=np.int64)
    counts = {"unscaled": np.zeros(8, dtype=np.int64), "scaled": np.zeros(8, dtype=np.int64)}
    imp = {"unscaled": 0, "scaled": 0, "unscaled_failed": 0, "scaled_failed": 0}
    listed: list[dict[str, Any]] = []
    impossible_codes = np.array([PATTERNS.index(p) for p in IMPOSSIBLE])
    lcps = contacts = 0
    for g in corpus.groups:
        r0 = solve_scaled(g, solver, 1.0, int(cfg["threads"]))
        r1 = solve_scaled(g, solver, s, int(cfg["threads"]))
        p0 = contact_patterns(g, r0, zero_rel)
        p1 = contact_patterns(g, r1, zero_rel)
        lcps += len(g)
        contacts += p0.size
        np.add.at(cross, (p0.ravel(), p1.ravel()), 1)
        counts["unscaled"] += np.bincount(p0.ravel(), minlength=8)
        counts["scaled"] += np.bincount(p1.ravel(), minlength=8)
        mu = g.mu()
        for name, p, r in (("unscaled", p0, r0), ("scaled", p1, r1)):
            bad = np.isin(p, impossible_codes) & (mu > 0)
            rows = bad.any(axis=1)
            imp[name] += int((rows & r.ok).sum())
            imp[name + "_failed"] += int((rows & ~r.ok).sum())
            for j in np.nonzero(rows)[0]:
                if len(listed) >= int(cfg["max_listed"]):
                    break
                lay = ContactLayout(g.contacts, g.friction_dirs)
                listed.append(
                    {
                        "lcp": int(g.index[j]),
                        "solve": name,
                        "status": r.status[j],
                        "simulation": corpus.sims[int(g.sim[j])].name,
                        "step": int(g.step[j]),
                        "n": g.n,
                        "contacts": [int(c) for c in np.nonzero(bad[j])[0]],
                        "patterns": [PATTERNS[int(c)] for c in p[j][bad[j]]],
                        "fn": r.z[j, lay.fn][bad[j]].tolist(),
                        "sum_fd": r.z[j, lay.fd].reshape(lay.nc, lay.k).sum(axis=1)[bad[j]].tolist(),
                        "lambda": r.z[j, lay.lam][bad[j]].tolist(),
                        "residual": float(r.residual[j]),
                    }
                )
    changed = int(cross.sum() - np.trace(cross))
    out = envelope("patterns", cfg, t0)
    out.update(
        {
            "solver": solver.to_dict(),
            "scale": scale_label(scale),
            "s": s,
            "lcps": lcps,
            "contacts": contacts,
            "patterns": list(PATTERNS),
            "meaning": MEANING,
            "counts_unscaled": {p: int(c) for p, c in zip(PATTERNS, counts["unscaled"])},
            "counts_scaled": {p: int(c) for p, c in zip(PATTERNS, counts["scaled"])},
            "cross": cross.tolist(),
            "changed": changed,
            "impossible": imp,
            "impossible_lcps": listed,
        }
    )
    out["wall_time_s"] = time.perf_counter() - t0
    return out
