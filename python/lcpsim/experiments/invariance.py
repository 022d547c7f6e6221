"""Scaling invariance: fn and fd do not change when the friction cone is
scaled; λ grows by 1/s.

The scaled LCP is ``D M D, D q`` with ``D = diag(I, I, s·I)``: its solutions
are exactly ``(fn, fd, λ/s)`` for the solutions ``(fn, fd, λ)`` of the
unscaled one. The source note printed both with 20 significant digits and found
agreement to ~1e-16. Here every cube-corpus LCP is solved unscaled and scaled
with the same solver and the answers compared (λ_scaled·s against λ):

* absolute differences ``max_abs_dfn``, ``max_abs_dfd`` (N·s);
* relative: ``‖Δ(fn, fd)‖∞`` over the LCP's largest impulse (or its impulse
  scale ‖q‖∞/max|A| when larger), ``‖s·λ_s − λ‖∞`` over the largest λ (or
  ‖q‖∞, a velocity, when larger) — so that round-off around an exact 0 does
  not count as a 100 % error.

A contact LCP can have several solutions (four coplanar contacts share a
load in infinitely many ways; friction can be split across directions), and
a solver may return a different one after scaling. The headline figures
therefore compare answers that end in the *same* Lemke basis — the same
vertex, so any difference is round-off — and the LCPs where the basis
changed are counted separately (``different_basis``), with how many of
those are two valid solutions of the same LCP (``different_basis_both_valid``:
both residuals ≤ ``valid_tol`` in physical units). ``all_pairs`` holds the
figures over every LCP solved both times. For solvers without a basis (PGS,
Newton) every pair counts.
"""

from __future__ import annotations

import argparse
import os
import time
from typing import Any, Mapping, Sequence

import numpy as np

from .._core import ContactLayout
from ._common import envelope, merge_config, scale_label
from .cube_corpus import SCALED_CASE_DEFAULTS, scaled_case, solve_scaled
from .document import Doc
from .experiment import (
    Experiment, ReportContext, add_common_arguments, add_corpus_arguments, base_config, corpus_config, header,
    scale_argument, scale_pair_runs,
)
from .figure import label_axes, pyplot, save, solver_label

__all__ = ["DEFAULTS", "run"]

DEFAULTS: dict[str, Any] = {**SCALED_CASE_DEFAULTS, "valid_tol": 1e-10, "examples": True, "max_listed": 20}

#: The source note's figure: agreement of fn, fd to about 1e-16 (printed with 20 digits).
NOTE_VALUE = 1e-16


def _stats(ef: np.ndarray, ed: np.ndarray, rf: np.ndarray, rd: np.ndarray, rl: np.ndarray) -> dict[str, float]:
    def m(a: np.ndarray) -> float:
        return float(a.max(initial=0.0))

    return {
        "max_abs_dfn": m(ef),
        "max_abs_dfd": m(ed),
        "max_rel_dfn": m(rf),
        "max_rel_dfd": m(rd),
        "max_rel_lambda_err": m(rl),
    }


def _hist(rel: np.ndarray) -> dict[str, Any]:
    """Counts of per-LCP relative errors in decades 1e-18 … 1 (exact zeros apart)."""
    edges = np.arange(-18, 1, dtype=float)
    pos = rel[rel > 0]
    lg = np.clip(np.log10(pos), edges[0], edges[-1] - 1e-9) if pos.size else pos
    counts, _ = np.histogram(lg, bins=edges)
    return {"log10_edges": edges.tolist(), "counts": counts.tolist(), "zeros": int((rel == 0).sum())}


def run(config: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Runs the comparison; returns ``{"lcps", "max_abs_dfn", "max_abs_dfd", "max_rel_lambda_err", …}``."""
    t0 = time.perf_counter()
    cfg = merge_config("invariance", DEFAULTS, config)
    solver, scale, s, corpus = scaled_case(cfg)
    valid_tol = float(cfg["valid_tol"])
    threads = int(cfg["threads"])
    keys = ("ef", "ed", "rf", "rd", "rl")
    same: dict[str, list[np.ndarray]] = {k: [] for k in keys}
    allp: dict[str, list[np.ndarray]] = {k: [] for k in keys}
    counts = dict(lcps=0, compared=0, status_changed=0, same_basis=0, different_basis=0, different_basis_both_valid=0)
    listed: list[dict[str, Any]] = []
    examples: list[dict[str, Any]] = []
    per_lcp_rel: list[np.ndarray] = []
    for g in corpus.groups:
        lay = ContactLayout(g.contacts, g.friction_dirs)
        force, fd, lam = lay.force, lay.fd, lay.lam
        r0 = solve_scaled(g, solver, 1.0, threads)
        r1 = solve_scaled(g, solver, s, threads)
        counts["lcps"] += len(g)
        counts["status_changed"] += int((r0.ok != r1.ok).sum())
        both = r0.ok & r1.ok
        counts["compared"] += int(both.sum())
        z0, z1 = r0.z, r1.z  # both in physical units
        qn = np.abs(g.q).max(axis=1)
        an = np.abs(g.M[:, force, force]).max(axis=(1, 2))
        fscale = np.maximum(np.abs(z0[:, force]).max(axis=1), qn / np.where(an > 0, an, 1.0))
        fscale = np.where(fscale > 0, fscale, 1.0)
        lscale = np.maximum(np.abs(z0[:, lam]).max(axis=1), qn)
        lscale = np.where(lscale > 0, lscale, 1.0)
        d = np.abs(z1 - z0)
        ef, ed, el = d[:, lay.fn].max(axis=1), d[:, fd].max(axis=1), d[:, lam].max(axis=1)
        vals = {"ef": ef, "ed": ed, "rf": ef / fscale, "rd": ed / fscale, "rl": el / lscale}
        if r0.basis is not None and r1.basis is not None:
            sb = both & (r0.basis == r1.basis).all(axis=1)
        else:
            sb = both
        db = both & ~sb
        counts["same_basis"] += int(sb.sum())
        counts["different_basis"] += int(db.sum())
        valid = (r0.residual <= valid_tol) & (r1.residual <= valid_tol)
        counts["different_basis_both_valid"] += int((db & valid).sum())
        for key in keys:
            same[key].append(vals[key][sb])
            allp[key].append(vals[key][both])
        per_lcp_rel.append(np.maximum(vals["rf"], vals["rd"])[sb])
        for j in np.nonzero(db)[0]:
            if len(listed) >= int(cfg["max_listed"]):
                break
            listed.append(
                {
                    "lcp": int(g.index[j]),
                    "simulation": corpus.sims[int(g.sim[j])].name,
                    "step": int(g.step[j]),
                    "n": g.n,
                    "rel_dfn": float(vals["rf"][j]),
                    "rel_dfd": float(vals["rd"][j]),
                    "rel_lambda": float(vals["rl"][j]),
                    "residual_unscaled": float(r0.residual[j]),
                    "residual_scaled": float(r1.residual[j]),
                }
            )
        if cfg["examples"] and g.n in (20, 40):
            # The first LCP of this size with friction, as the source note showed (sizes 20 and 40).
            cand = np.nonzero(sb & (np.abs(z0[:, fd]).max(axis=1) > 0))[0]
            if cand.size:
                e = int(cand[0])
                examples.append(
                    {
                        "lcp": int(g.index[e]),
                        "simulation": corpus.sims[int(g.sim[e])].name,
                        "step": int(g.step[e]),
                        "n": g.n,
                        "contacts": lay.nc,
                        "before": z0[e].tolist(),
                        "after": (z1[e] / lay.cone_diagonal(s)).tolist(),
                        "after_mapped": z1[e].tolist(),
                    }
                )
    def cat(parts: list[np.ndarray]) -> np.ndarray:
        return np.concatenate(parts) if parts else np.zeros(0)

    head = _stats(*(cat(same[k]) for k in keys))
    out = envelope("invariance", cfg, t0)
    rel = cat(per_lcp_rel)
    out.update(
        {
            "solver": solver.to_dict(),
            "scale": scale_label(scale),
            "s": s,
            **counts,
            **head,
            "all_pairs": _stats(*(cat(allp[k]) for k in keys)),
            "different_basis_lcps": listed,
            "examples": examples,
            "rel_error_hist": _hist(rel),
            "rel_error_quantiles": {
                q: float(np.quantile(rel, float(q))) if rel.size else 0.0 for q in ("0.5", "0.9", "0.99", "1.0")
            },
            "note_value": NOTE_VALUE,
        }
    )
    out["wall_time_s"] = time.perf_counter() - t0
    return out


# ---------------------------------------------------------------- command line, figures, report


def cli_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--scale", type=scale_argument, default=1e-3, metavar="dt|S", help="cone scale compared with unscaled (default: 1e-3)")
    p.add_argument("--digits", type=int, default=None, metavar="N", help="print example vectors with N significant digits (as the source note: 20)")
    add_common_arguments(p)
    add_corpus_arguments(p)


def cli_config(args: argparse.Namespace) -> dict[str, Any]:
    if args.digits is not None and not 1 <= args.digits <= 40:
        raise ValueError(f"--digits must be in 1…40, got {args.digits}")
    return {**base_config(args), **corpus_config(args), "scale": args.scale}


def summary(r: dict[str, Any], args: argparse.Namespace | None = None) -> str:
    """The text ``lcpsim invariance`` prints (example vectors with ``args.digits`` digits)."""
    digits = getattr(args, "digits", None)
    lines = [
        header(r),
        f"{r['lcps']} LCPs, unscaled vs s = {r['scale']} (λ_scaled·s against λ); solved both times: {r['compared']}",
        f"same Lemke basis: {r['same_basis']}; different basis: {r['different_basis']} "
        f"(both valid solutions: {r['different_basis_both_valid']}); status changed: {r['status_changed']}",
        "",
        "same basis (round-off only):",
        f"  max |Δfn| = {r['max_abs_dfn']:.3e} N·s   relative {r['max_rel_dfn']:.3e}",
        f"  max |Δfd| = {r['max_abs_dfd']:.3e} N·s   relative {r['max_rel_dfd']:.3e}",
        f"  max relative λ error = {r['max_rel_lambda_err']:.3e}",
        "all pairs solved both times:",
        "  " + ", ".join(f"{k} {v:.3e}" for k, v in r["all_pairs"].items()),
        "source note: fn, fd agree to ~1e-16",
    ]
    if digits:
        for ex in r.get("examples", []):
            lines += ["", f"Size = {ex['n']}, {ex['contacts']} contact points (LCP {ex['lcp']}, {ex['simulation']} step {ex['step']})",
                      "Before", " ".join(f"{x:.{digits}g}" for x in ex["before"]),
                      "After", " ".join(f"{x:.{digits}g}" for x in ex["after"])]
    return "\n".join(lines)


def plot_invariance(results: Sequence[Mapping[str, Any]], path: str | os.PathLike[str]) -> str:
    """Histogram of per-LCP relative changes of (fn, fd) by scaling."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4))
    for i, r in enumerate(results):
        h = r["rel_error_hist"]
        edges = np.asarray(h["log10_edges"])
        counts = np.asarray(h["counts"], dtype=float)
        centers = 0.5 * (edges[:-1] + edges[1:])
        lab = f"{solver_label(r)}, s = {r['scale']} ({h['zeros']} exactly 0)"
        ax.bar(centers + (i - (len(results) - 1) / 2) * 0.8 / len(results), counts, 0.8 / len(results),
               color=f"C{i}", label=lab)
    ax.axvline(-12, color="k", ls=":", lw=1, label="1e-12")
    ax.axvline(-16, color="grey", ls="--", lw=1, label="source note: ~1e-16")
    ax.set_yscale("log")
    label_axes(ax, "log10 relative change of (fn, fd) by scaling (same Lemke basis)", "LCPs",
               title="Scaling invariance over the cube corpus", legend=8)
    return save(fig, path)


def report_run(ctx: ReportContext) -> dict[str, Any]:
    return {"invariance": scale_pair_runs(ctx, "invariance", run)}


def report_section(d: Doc, res: dict[str, Any], figs: dict[str, str], ctx: ReportContext) -> None:
    d.section(
        "Scaling invariance",
        """`lcpsim invariance --scale S --solver P [--digits 20]`: every corpus LCP solved unscaled and scaled; fn, fd
        compared directly, λ_scaled·s against λ. Headline figures over LCPs whose Lemke basis is the same both times
        (then only round-off can differ); an LCP with several solutions may end in another basis — counted apart, with
        how many of those are two valid solutions.""",
    )
    irows = []
    for r in res["invariance"]:
        irows.append([r["solver"]["name"], r["scale"], r["lcps"], r["compared"], r["max_abs_dfn"], r["max_abs_dfd"],
                      r["max_rel_dfn"], r["max_rel_dfd"], r["max_rel_lambda_err"], r["different_basis"],
                      r["different_basis_both_valid"], r["status_changed"]])
    d.table(["solver", "s", "LCPs", "solved both", "max |Δfn|", "max |Δfd|", "rel Δfn", "rel Δfd", "rel λ err",
             "other basis", "both valid", "status changed"], irows)
    d.img(ctx.rel(figs["invariance"]), "invariance histogram")
    ex = next((r for r in res["invariance"] if r["solver"]["name"] == "robust" and r.get("examples")), None)
    if ex:
        lines = []
        for e in ex["examples"]:
            lines += [f"Size = {e['n']}, {e['contacts']} contact points ({e['simulation']}, step {e['step']}), s = {ex['scale']}",
                      "Before", " ".join(f"{x:.20g}" for x in e["before"]),
                      "After", " ".join(f"{x:.20g}" for x in e["after"]), ""]
        d.p("As the source note printed them (robust, 20 significant digits; After = the scaled LCP's z, λ = λ/s):")
        d.pre("\n".join(lines).strip())


EXPERIMENT = Experiment.of_module(
    __name__, "fn, fd unchanged and λ·s by cone scaling, over the cube corpus", plot=plot_invariance
)
