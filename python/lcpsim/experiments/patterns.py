"""Contact patterns: the sign of (fn, Σfd, λ) per contact, unscaled and scaled.

The source note's table, ``+`` meaning positive, ``0`` zero:

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

Every cube-corpus LCP is solved unscaled and at scale s with the chosen
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

import argparse
import os
import time
from typing import Any, Mapping

import numpy as np
from numpy.typing import NDArray

from .._core import ContactLayout
from ._common import envelope, merge_config, scale_label
from .cube_corpus import SCALED_CASE_DEFAULTS, Group, ScaledSolve, scaled_case, solve_scaled
from .document import Doc
from .experiment import (
    Experiment, ReportContext, add_common_arguments, add_corpus_arguments, base_config, corpus_config, header,
    scale_argument, scale_pair_runs,
)
from .figure import save, solver_label, two_panels

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

DEFAULTS: dict[str, Any] = {**SCALED_CASE_DEFAULTS, "zero_rel": 1e-9, "max_listed": 50}


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
    solver, scale, s, corpus = scaled_case(cfg)
    zero_rel = float(cfg["zero_rel"])
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
            # By the solver's word: classic's "solved" with an impossible pattern is the artifact
            # (its `ok` is False there, as the acceptance rule rejects such answers).
            said_solved = np.array([st == "solved" for st in r.status], dtype=bool)
            imp[name] += int((rows & said_solved).sum())
            imp[name + "_failed"] += int((rows & ~said_solved).sum())
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


# ---------------------------------------------------------------- command line, figures, report


def cli_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--scale", type=scale_argument, default=1e-3, metavar="dt|S", help="cone scale (default: 1e-3)")
    p.add_argument("--zero-rel", type=float, default=1e-9, help="relative zero for the signs (default: 1e-9)")
    add_common_arguments(p)
    add_corpus_arguments(p)


def cli_config(args: argparse.Namespace) -> dict[str, Any]:
    return {**base_config(args), **corpus_config(args), "scale": args.scale, "zero_rel": args.zero_rel}


def summary(r: dict[str, Any], args: argparse.Namespace | None = None) -> str:
    """The text ``lcpsim patterns`` prints."""
    pats = r["patterns"]
    lines = [header(r), f"{r['lcps']} LCPs, {r['contacts']} contacts; unscaled vs s = {r['scale']}", ""]
    lines.append(f"{'(fn,Σfd,λ)':>11} {'unscaled':>9} {'scaled':>9}  meaning")
    for p in pats:
        lines.append(f"{'(' + ','.join(p) + ')':>11} {r['counts_unscaled'][p]:>9} {r['counts_scaled'][p]:>9}  {r['meaning'][p]}")
    lines += ["", "cross table (rows unscaled, columns scaled):", " " * 9 + "".join(f"{'(' + ','.join(p) + ')':>9}" for p in pats)]
    for p, row in zip(pats, r["cross"]):
        lines.append(f"{'(' + ','.join(p) + ')':>9}" + "".join(f"{v:>9}" for v in row))
    imp = r["impossible"]
    lines += [
        "",
        f"contacts whose pattern changed with scaling: {r['changed']}",
        f"LCPs with an impossible pattern: unscaled {imp['unscaled']} (+{imp['unscaled_failed']} in failed solves), "
        f"scaled {imp['scaled']} (+{imp['scaled_failed']} in failed solves)",
    ]
    for x in r["impossible_lcps"][:10]:
        lines.append(f"  LCP {x['lcp']} ({x['simulation']} step {x['step']}, {x['solve']}, {x['status']}): "
                     f"{', '.join(x['patterns'])} fn {x['fn']} Σfd {x['sum_fd']} λ {x['lambda']}")
    if len(r["impossible_lcps"]) > 10:
        lines.append(f"  … {len(r['impossible_lcps']) - 10} more listed in --json")
    return "\n".join(lines)


def plot_patterns(result: Mapping[str, Any], path: str | os.PathLike[str]) -> str:
    """Pattern counts unscaled and scaled, and the cross table."""
    pats = list(result["patterns"])
    fig, ax1, ax2 = two_panels(11, 4.4)
    x = np.arange(len(pats))
    u = [result["counts_unscaled"][p] for p in pats]
    s = [result["counts_scaled"][p] for p in pats]
    ax1.bar(x - 0.2, u, 0.4, label="unscaled")
    ax1.bar(x + 0.2, s, 0.4, label=f"s = {result['scale']}")
    labels = [f"({','.join(p)})" + (" ✗" if p in ("0+0", "0++", "+0+") else "") for p in pats]
    ax1.set_xticks(x, labels, rotation=45, fontsize=8)
    ax1.set_yscale("symlog", linthresh=1)
    ax1.set_ylabel("contacts")
    ax1.set_title(f"Patterns (fn, Σfd, λ), {solver_label(result)} (✗ impossible)")
    ax1.legend(fontsize=8)
    cross = np.asarray(result["cross"], dtype=float)
    im = ax2.imshow(np.log10(cross + 1), cmap="viridis")
    for i in range(len(pats)):
        for j in range(len(pats)):
            if cross[i, j]:
                ax2.text(j, i, f"{int(cross[i, j])}", ha="center", va="center", fontsize=7,
                         color="w" if i != j else "k")
    ax2.set_xticks(x, labels, rotation=45, fontsize=7)
    ax2.set_yticks(x, labels, fontsize=7)
    ax2.set_xlabel(f"scaled (s = {result['scale']})")
    ax2.set_ylabel("unscaled")
    ax2.set_title(f"unscaled × scaled ({result['changed']} contacts changed)")
    fig.colorbar(im, ax=ax2, label="log10(count + 1)")
    return save(fig, path)


def report_run(ctx: ReportContext) -> dict[str, Any]:
    return {"patterns": scale_pair_runs(ctx, "patterns", run)}


def report_figures(res: dict[str, Any], ctx: ReportContext) -> dict[str, str]:
    figs = {}
    for r in res["patterns"]:
        tag = f"{r['solver']['name']}_{r['scale']}".replace(".", "_").replace("-", "m")
        figs[f"patterns_{tag}"] = plot_patterns(r, ctx.path(f"patterns_{tag}.png"))
    return figs


def report_section(d: Doc, res: dict[str, Any], figs: dict[str, str], ctx: ReportContext) -> None:
    d.section(
        "Contact patterns",
        """`lcpsim patterns --scale S --solver P`: sign of (fn, Σfd, λ) per contact, unscaled and scaled; (0,+,0),
        (0,+,+) and (+,0,+) are impossible for an exact solution with μ > 0.""",
    )
    pats_all = res["patterns"][0]["patterns"]
    prow = []
    for r in res["patterns"]:
        for which in ("unscaled", "scaled"):
            if which == "unscaled" and r["scale"] != "0.001":
                continue
            cnt = r["counts_unscaled" if which == "unscaled" else "counts_scaled"]
            prow.append([r["solver"]["name"], "1" if which == "unscaled" else r["scale"]] + [cnt[p] for p in pats_all] +
                        [r["impossible"][which], r["impossible"][which + "_failed"]])
    d.table(["solver", "s"] + [f"({','.join(p)})" for p in pats_all] + ["LCPs w/ impossible (solved)", "(failed)"], prow)
    for k in sorted(figs):
        if k.startswith("patterns_"):
            d.img(ctx.rel(figs[k]), k)


EXPERIMENT = Experiment.of_module(
    __name__,
    "sign patterns (fn, Σfd, λ) per contact, unscaled × scaled",
    plot=lambda results, path: plot_patterns(results[0], path),
)
