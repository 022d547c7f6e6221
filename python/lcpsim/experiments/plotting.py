"""Plots of the experiments' results (matplotlib, Agg backend, PNG).

Each function takes result dicts as the experiments return them (or as read
back from JSON) and writes one figure to ``path``.
"""

from __future__ import annotations

import os
from typing import Any, Mapping, Sequence

import numpy as np

__all__ = [
    "plot_failure_rate",
    "plot_slope",
    "plot_critical_scale",
    "plot_invariance",
    "plot_patterns",
    "plot_push",
    "plot_push_sweep",
    "plot_result",
]

OUTCOME_COLORS = {"slide": "tab:green", "rest": "tab:blue", "tip": "tab:red"}


def _plt() -> Any:
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def _save(fig: Any, path: str | os.PathLike[str]) -> str:
    p = os.fspath(path)
    os.makedirs(os.path.dirname(os.path.abspath(p)), exist_ok=True)
    fig.tight_layout()
    fig.savefig(p, dpi=110)
    _plt().close(fig)
    return p


def _solver_label(r: Mapping[str, Any]) -> str:
    s = r.get("solver") or {}
    return str(s.get("name", "?")) if isinstance(s, Mapping) else str(s)


def plot_failure_rate(results: Sequence[Mapping[str, Any]], path: str | os.PathLike[str]) -> str:
    """Failure rate per scale, one group of bars per solver: status failures
    (solid) and all failures incl. physical-unit residual (hatched); the seed's
    rates as black diamonds."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    scales = [row["scale"] for row in results[0]["rows"]]
    x = np.arange(len(scales))
    width = 0.8 / max(len(results), 1)
    for i, r in enumerate(results):
        rows = {row["scale"]: row for row in r["rows"]}
        st = [100 * rows[s]["status_rate"] if s in rows else np.nan for s in scales]
        al = [100 * rows[s]["rate"] if s in rows else np.nan for s in scales]
        off = (i - (len(results) - 1) / 2) * width
        c = f"C{i}"
        ax.bar(x + off, al, width * 0.95, color=c, alpha=0.35, hatch="//", label=f"{_solver_label(r)}: any failure")
        ax.bar(x + off, st, width * 0.95, color=c, label=f"{_solver_label(r)}: status ≠ solved")
    seed = results[0].get("seed_values") or {}
    for j, s in enumerate(scales):
        key = f"{float(s):g}" if s not in ("none", "dt") else s
        if key in seed:
            ax.plot([j], [100 * seed[key]], "kD", ms=7, label="seed note" if j == 0 or "seed note" not in
                    [t.get_label() for t in ax.lines] else None)
    ax.set_xticks(x, [f"s = {s}" for s in scales])
    ax.set_ylabel("LCPs failed (%)")
    n = results[0]["rows"][0]["lcps"]
    ax.set_title(f"Failure rate over the seed corpus ({n} LCPs, {results[0].get('mode', 'resolve')})")
    ax.legend(fontsize=8)
    ax.grid(axis="y", alpha=0.3)
    return _save(fig, path)


def plot_slope(results: Sequence[Mapping[str, Any]], path: str | os.PathLike[str]) -> str:
    """Down-slope distance (symlog) and tilt against time for slope runs with a trace."""
    plt = _plt()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4.2))
    plotted_expected: set[tuple[float, float]] = set()
    for i, r in enumerate(results):
        tr = r.get("trace")
        if not tr:
            continue
        cfg = r["config"]
        lab = f"{_solver_label(r)}, s = {r['scale']}, {cfg['angle_deg']}° → {r['outcome']}"
        ax1.plot(tr["time"], tr["slide_m"], color=f"C{i % 10}", label=lab)
        key = (float(cfg["angle_deg"]), float(cfg["mu"]))
        if key not in plotted_expected:
            plotted_expected.add(key)
            ax1.plot(tr["time"], tr["expected_m"], "k--", lw=1, label=f"analytic slide, {key[0]}°")
        ax2.plot(tr["time"], np.maximum(tr["tilt_deg"], 1e-6), color=f"C{i % 10}", ls="-" if i % 2 else "--", label=lab)
    from matplotlib.ticker import SymmetricalLogLocator

    ax1.set_yscale("symlog", linthresh=1e-6)
    ax1.set_ylim(-10.0, 10.0)
    ax1.yaxis.set_major_locator(SymmetricalLogLocator(base=100, linthresh=1e-6))
    ax1.set_xlabel("time (s)")
    ax1.set_ylabel("down-slope displacement (m, clipped at ±10)")
    ax1.set_title("Slope test: displacement")
    ax1.grid(alpha=0.3)
    ax1.legend(fontsize=7)
    ax2.set_yscale("log")
    ax2.set_ylim(5e-7, 400)
    ax2.axhline(5.0, color="k", lw=0.8, ls=":", label="tip threshold 5°")
    ax2.set_xlabel("time (s)")
    ax2.set_ylabel("rotation (deg, floor 1e-6)")
    ax2.set_title("Slope test: rotation")
    ax2.grid(alpha=0.3)
    return _save(fig, path)


def plot_critical_scale(results: Sequence[Mapping[str, Any]], path: str | os.PathLike[str]) -> str:
    """Outcome of every slope run against the scale, one row per search; the
    critical scale as a vertical line, the seed's 4e-3 dotted."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(8, 1.2 + 0.9 * len(results)))
    for i, r in enumerate(results):
        for o in r["outcomes"]:
            mk = "o" if o.get("stage") == "grid" else "|"
            ax.plot([o["scale"]], [i], mk, color=OUTCOME_COLORS.get(o["outcome"], "k"), ms=9)
        c = r.get("critical_scale")
        if c:
            ax.plot([c, c], [i - 0.35, i + 0.35], "k-", lw=2)
            ax.annotate(f"{c:.3g}", (c, i + 0.38), ha="center", fontsize=8)
    ax.axvline(4e-3, color="grey", ls=":", label="seed note: 4e-3")
    for name, col in OUTCOME_COLORS.items():
        ax.plot([], [], "o", color=col, label=name)
    ax.set_xscale("log")
    ax.set_yticks(range(len(results)), [f"{r['config']['angle_deg']}°, {_solver_label(r)}" for r in results])
    ax.set_ylim(-0.7, len(results) - 0.2)
    ax.set_xlabel("friction-cone scale s (1 = unscaled)")
    ax.set_title("Critical scale: below it the cube is held (rest/tip) instead of sliding")
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5))
    ax.grid(axis="x", alpha=0.3)
    return _save(fig, path)


def plot_invariance(results: Sequence[Mapping[str, Any]], path: str | os.PathLike[str]) -> str:
    """Histogram of per-LCP relative changes of (fn, fd) by scaling."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7, 4))
    for i, r in enumerate(results):
        h = r["rel_error_hist"]
        edges = np.asarray(h["log10_edges"])
        counts = np.asarray(h["counts"], dtype=float)
        centers = 0.5 * (edges[:-1] + edges[1:])
        lab = f"{_solver_label(r)}, s = {r['scale']} ({h['zeros']} exactly 0)"
        ax.bar(centers + (i - (len(results) - 1) / 2) * 0.8 / len(results), counts, 0.8 / len(results),
               color=f"C{i}", label=lab)
    ax.axvline(-12, color="k", ls=":", lw=1, label="1e-12")
    ax.axvline(-16, color="grey", ls="--", lw=1, label="seed: ~1e-16")
    ax.set_yscale("log")
    ax.set_xlabel("log10 relative change of (fn, fd) by scaling (same Lemke basis)")
    ax.set_ylabel("LCPs")
    ax.set_title("Scaling invariance over the seed corpus")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return _save(fig, path)


def plot_patterns(result: Mapping[str, Any], path: str | os.PathLike[str]) -> str:
    """Pattern counts unscaled and scaled, and the cross table."""
    plt = _plt()
    pats = list(result["patterns"])
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.4))
    x = np.arange(len(pats))
    u = [result["counts_unscaled"][p] for p in pats]
    s = [result["counts_scaled"][p] for p in pats]
    ax1.bar(x - 0.2, u, 0.4, label="unscaled")
    ax1.bar(x + 0.2, s, 0.4, label=f"s = {result['scale']}")
    labels = [f"({','.join(p)})" + (" ✗" if p in ("0+0", "0++", "+0+") else "") for p in pats]
    ax1.set_xticks(x, labels, rotation=45, fontsize=8)
    ax1.set_yscale("symlog", linthresh=1)
    ax1.set_ylabel("contacts")
    ax1.set_title(f"Patterns (fn, Σfd, λ), {_solver_label(result)} (✗ impossible)")
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
    return _save(fig, path)


def plot_push(results: Sequence[Mapping[str, Any]], path: str | os.PathLike[str]) -> str:
    """Displacement and friction force against time for push runs with a trace."""
    plt = _plt()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    for i, r in enumerate(results):
        tr = r.get("trace")
        if not tr:
            continue
        lab = f"F = {r['config']['force']} N, {_solver_label(r)}, s = {r['scale']} → {r['outcome']}"
        ax1.plot(tr["time"], tr["displacement_m"], color=f"C{i}", label=lab)
        ax2.plot(tr["time"], tr["friction_N"], color=f"C{i}", label=lab)
    ax1.set_yscale("symlog", linthresh=1e-9)
    ax1.set_xlabel("time (s)")
    ax1.set_ylabel("displacement along the push (m)")
    ax1.grid(alpha=0.3)
    ax1.legend(fontsize=7)
    ax2.set_xlabel("time (s)")
    ax2.set_ylabel("friction force (N)")
    ax2.grid(alpha=0.3)
    return _save(fig, path)


def plot_push_sweep(results: Sequence[Mapping[str, Any]], path: str | os.PathLike[str]) -> str:
    """Friction force and displacement against the applied force (one run per force and solver)."""
    plt = _plt()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    by: dict[str, list[Mapping[str, Any]]] = {}
    for r in results:
        by.setdefault(f"{_solver_label(r)}, s = {r['scale']}", []).append(r)
    for i, (lab, rs) in enumerate(sorted(by.items())):
        rs = sorted(rs, key=lambda r: r["config"]["force"])
        F = [r["config"]["force"] for r in rs]
        ax1.plot(F, [r["friction_force_N"] for r in rs], "o-", color=f"C{i}", label=lab)
        ax2.plot(F, [max(r["displacement_m"], 1e-12) for r in rs], "o-", color=f"C{i}", label=lab)
    if results:
        F = sorted({r["config"]["force"] for r in results})
        ax1.plot(F, [min(f, 9.81) for f in F], "k--", lw=1, label="exact: min(F, μmg)")
    ax1.axvline(9.81, color="grey", ls=":", lw=1)
    ax2.axvline(9.81, color="grey", ls=":", lw=1)
    ax1.set_xlabel("push F (N)")
    ax1.set_ylabel("friction force, last step (N)")
    ax1.legend(fontsize=7)
    ax1.grid(alpha=0.3)
    ax2.set_yscale("log")
    ax2.set_xlabel("push F (N)")
    ax2.set_ylabel("displacement after the run (m)")
    ax2.grid(alpha=0.3)
    fig.suptitle("Pushed 1 kg cube, μ = 1 (μmg = 9.81 N)")
    return _save(fig, path)


def plot_result(result: Mapping[str, Any], path: str | os.PathLike[str]) -> str:
    """The natural plot of one result, by its ``experiment``."""
    kind = result.get("experiment")
    if kind == "failure-rate":
        return plot_failure_rate([result], path)
    if kind == "slope":
        return plot_slope([result], path)
    if kind == "critical-scale":
        return plot_critical_scale([result], path)
    if kind == "invariance":
        return plot_invariance([result], path)
    if kind == "patterns":
        return plot_patterns(result, path)
    if kind == "push":
        return plot_push([result], path)
    raise ValueError(f"no plot for experiment {kind!r}")
