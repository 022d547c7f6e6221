"""``lcpsim report``: every experiment at its default size, one page.

Writes to the output directory ``index.html`` and ``report.md`` (the same
content), the figures as PNG, and ``results.json`` with every result (each
carrying its config, seed and lcpsim version). For each claim of the seed
note (DESIGN §2) the page puts the seed's number beside ours — with the
``seed`` preset (the seed's solver setting) and with ``robust`` (lcpsim's
default) — and says why they differ.
"""

from __future__ import annotations

import functools
import html
import json
import math
import os
import sys
import time
from typing import IO, Any, Callable, Sequence

from . import critical_scale, failure_rate, invariance, patterns, push, slope
from ._common import jsonable
from .plotting import (
    plot_critical_scale,
    plot_failure_rate,
    plot_invariance,
    plot_patterns,
    plot_push,
    plot_push_sweep,
    plot_slope,
)
from .seed_corpus import DEFAULTS as CORPUS_DEFAULTS
from .seed_corpus import generate, simulations

__all__ = ["make_report"]

SCALES = ["none", 1e-3, 1e-4, 1e-6, 1e-8]
SLOPE_SCALES = ["none", 1e-3, 1e-6]
PUSH_FORCES = [9.70, 9.75, 9.79, 9.80, 9.81, 9.82, 9.83, 9.90]
#: The solver comparison of issue 5 (classic = the seed preset).
COMPARE_SOLVERS = ["seed", "robust", "pgs", "newton_fb"]
COMPARE_SCALES = ["none", 1e-2, 1e-3, 1e-4, 1e-6, 1e-8]

UNITS_NOTE = (
    "The seed note does not state its units, mass, cube size or time step (DESIGN §2); every figure here is for "
    "a 1 kg, 1 m cube at h = 1e-3 s with impulses in N·s and k = 8 friction directions, so an absolute "
    "tolerance such as the seed's user zero of 1e-6 bites at different problems and different scales than in "
    "the seed's runs. Where a number differs, the phenomenon — not the number — is what is compared."
)


# ---------------------------------------------------------------- document model


class Doc:
    """Blocks rendered to both Markdown and HTML."""

    def __init__(self) -> None:
        self.blocks: list[tuple[str, Any]] = []

    def h(self, level: int, text: str) -> None:
        self.blocks.append(("h", (level, text)))

    def p(self, text: str) -> None:
        self.blocks.append(("p", text))

    def table(self, header: Sequence[str], rows: Sequence[Sequence[Any]]) -> None:
        self.blocks.append(("table", (list(header), [[_cell(c) for c in r] for r in rows])))

    def img(self, path: str, alt: str) -> None:
        self.blocks.append(("img", (path, alt)))

    def pre(self, text: str) -> None:
        self.blocks.append(("pre", text))

    def markdown(self) -> str:
        out: list[str] = []
        for kind, v in self.blocks:
            if kind == "h":
                out.append("#" * v[0] + " " + v[1])
            elif kind == "p":
                out.append(v)
            elif kind == "table":
                head, rows = v
                out.append("| " + " | ".join(h.replace("|", "\\|") for h in head) + " |")
                out.append("|" + "|".join("---" for _ in head) + "|")
                out += ["| " + " | ".join(str(c).replace("|", "\\|") for c in r) + " |" for r in rows]
            elif kind == "img":
                out.append(f"![{v[1]}]({v[0]})")
            elif kind == "pre":
                out.append("```text\n" + v + "\n```")
            out.append("")
        return "\n".join(out)

    def html(self, title: str) -> str:
        e = html.escape
        out = [
            "<!DOCTYPE html>",
            '<html lang="en"><head><meta charset="utf-8">',
            f"<title>{e(title)}</title>",
            "<style>body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;"
            "line-height:1.45;color:#222}table{border-collapse:collapse;margin:1em 0;font-size:0.9em}"
            "td,th{border:1px solid #bbb;padding:3px 7px;text-align:left;vertical-align:top}"
            "th{background:#eee}img{max-width:100%;border:1px solid #ddd;margin:0.5em 0}"
            "pre{background:#f6f6f6;padding:0.6em;overflow-x:auto;font-size:0.8em}code{background:#f3f3f3}</style>",
            "</head><body>",
        ]
        for kind, v in self.blocks:
            if kind == "h":
                out.append(f"<h{v[0]}>{_inline(v[1])}</h{v[0]}>")
            elif kind == "p":
                out.append(f"<p>{_inline(v)}</p>")
            elif kind == "table":
                head, rows = v
                out.append("<table><tr>" + "".join(f"<th>{_inline(h)}</th>" for h in head) + "</tr>")
                out += ["<tr>" + "".join(f"<td>{_inline(str(c))}</td>" for c in r) + "</tr>" for r in rows]
                out.append("</table>")
            elif kind == "img":
                out.append(f'<p><img src="{e(v[0])}" alt="{e(v[1])}"></p>')
            elif kind == "pre":
                out.append(f"<pre>{e(v)}</pre>")
        out.append("</body></html>")
        return "\n".join(out)


def _inline(text: str) -> str:
    """Escapes, then renders `code` and **bold**."""
    import re

    t = html.escape(text)
    t = re.sub(r"`([^`]+)`", r"<code>\1</code>", t)
    t = re.sub(r"\*\*([^*]+)\*\*", r"<b>\1</b>", t)
    return t


def _cell(x: Any) -> str:
    if x is None:
        return "—"
    if isinstance(x, float):
        if math.isnan(x):
            return "—"
        if x == 0:
            return "0"
        a = abs(x)
        return f"{x:.3g}" if 1e-3 <= a < 1e5 else f"{x:.2e}"
    return str(x)


def _pct(x: float) -> str:
    return f"{100 * x:.2f} %"


# ---------------------------------------------------------------- report


def make_report(
    out_dir: str | os.PathLike[str],
    *,
    seed: int = 0,
    quick: bool = False,
    log: IO[str] | None = sys.stderr,
) -> dict[str, Any]:
    """Runs everything and writes the report; returns ``{"index_html", "report_md", "results_json", …}``."""
    t0 = time.perf_counter()
    out = os.fspath(out_dir)
    os.makedirs(out, exist_ok=True)
    corpus = {"n_random": 2, "steps": 200} if quick else {}
    # 2 s as in DESIGN §2 (0.097 m at 45.2°): a cube held by the looser cone needs that long to tip.
    seconds = 0.5 if quick else 2.0
    results: dict[str, Any] = {}

    def step(name: str, fn: Callable[[], Any]) -> Any:
        t = time.perf_counter()
        if log is not None:
            log.write(f"report: {name} …")
            log.flush()
        r = fn()
        if log is not None:
            log.write(f" {time.perf_counter() - t:.1f} s\n")
            log.flush()
        return r

    base = {"seed": seed, "corpus": corpus}
    cc = {**CORPUS_DEFAULTS, **corpus, "seed": seed}
    corp = step("seed corpus", lambda: generate(cc))
    results["corpus"] = {"config": cc, **corp.summary(), "simulations_spec": [s.to_dict() for s in simulations(cc)]}

    fr: dict[str, dict[str, Any]] = {}
    for name in ("seed", "robust"):
        cfg = {**base, "solver": name, "scales": SCALES}
        fr[name] = step(f"failure rate ({name})", functools.partial(failure_rate.run, cfg))
    fr_sim = step(
        "failure rate (seed, simulated)",
        lambda: failure_rate.run({**base, "solver": "seed", "scales": SCALES, "mode": "simulate"}),
    )
    results["failure_rate"] = {"seed": fr["seed"], "robust": fr["robust"], "seed_simulate": fr_sim}
    # PGS is slow on these LCPs (10,000 sweeps when it fails): a seeded subset of the seed corpus.
    cmp_cfg = {
        **base,
        "solvers": COMPARE_SOLVERS,
        "corpora": ["seed", "hard"],
        "scales": ["none", 1e-8] if quick else COMPARE_SCALES,
        "max_lcps": 100 if quick else 1000,
        "hard": {"count": 7 if quick else 70},
    }
    results["comparison"] = step("solver comparison", functools.partial(failure_rate.run, cmp_cfg))

    def slope_runs() -> list[dict[str, Any]]:
        return [
            slope.run({"seed": seed, "solver": solver, "angle_deg": angle, "scale": sc, "seconds": seconds, "trace": True})
            for solver in ("seed", "robust")
            for angle in (45.0001, 45.2)
            for sc in SLOPE_SCALES
        ]

    slopes = results["slope"] = step("slope tests", slope_runs)

    def crit_runs() -> list[dict[str, Any]]:
        return [
            critical_scale.run({"seed": seed, "solver": solver, "angle_deg": angle, "seconds": seconds})
            for solver in ("seed", "robust")
            for angle in (45.0001, 45.2)
        ]

    crit = results["critical_scale"] = step("critical scales", crit_runs)

    def inv_runs() -> list[dict[str, Any]]:
        return [
            invariance.run({**base, "solver": solver, "scale": sc}) for solver in ("robust", "seed") for sc in (1e-3, 1e-6)
        ]

    inv = results["invariance"] = step("invariance", inv_runs)

    def pat_runs() -> list[dict[str, Any]]:
        return [
            patterns.run({**base, "solver": solver, "scale": sc}) for solver in ("robust", "seed") for sc in (1e-3, 1e-6)
        ]

    pats = results["patterns"] = step("patterns", pat_runs)

    def push_runs() -> list[dict[str, Any]]:
        return [
            push.run({"seed": seed, "solver": solver, "scale": sc, "force": F, "seconds": seconds,
                      "trace": F in (9.79, 9.83)})
            for solver in ("robust", "seed")
            for sc in ("none", "dt")
            for F in PUSH_FORCES
        ]

    pushes = results["push"] = step("pushed cube", push_runs)

    # Figures.
    if log is not None:
        log.write("report: figures …\n")
    figs = {}
    figs["failure_rate"] = plot_failure_rate([fr["seed"], fr["robust"]], os.path.join(out, "failure_rate.png"))
    figs["failure_rate_sim"] = plot_failure_rate([fr_sim], os.path.join(out, "failure_rate_simulate.png"))
    for angle in (45.0001, 45.2):
        tag = str(angle).replace(".", "_")
        figs[f"slope_{tag}"] = plot_slope(
            [r for r in slopes if r["config"]["angle_deg"] == angle], os.path.join(out, f"slope_{tag}.png")
        )
    figs["critical_scale"] = plot_critical_scale(crit, os.path.join(out, "critical_scale.png"))
    figs["invariance"] = plot_invariance(inv, os.path.join(out, "invariance.png"))
    for r in pats:
        tag = f"{r['solver']['name']}_{r['scale']}".replace(".", "_").replace("-", "m")
        figs[f"patterns_{tag}"] = plot_patterns(r, os.path.join(out, f"patterns_{tag}.png"))
    figs["push_sweep"] = plot_push_sweep(pushes, os.path.join(out, "push_sweep.png"))
    figs["push_trace"] = plot_push(
        [r for r in pushes if r.get("trace") and r["scale"] == "none"], os.path.join(out, "push_trace.png")
    )

    doc = _document(results, figs, out, seed, quick, time.perf_counter() - t0)
    from .. import __version__

    results_path = os.path.join(out, "results.json")
    with open(results_path, "w") as fh:
        json.dump(jsonable({"lcpsim_version": __version__, "seed": seed, "quick": quick, "results": results}), fh)
    md_path = os.path.join(out, "report.md")
    html_path = os.path.join(out, "index.html")
    with open(md_path, "w") as fh:
        fh.write(doc.markdown())
    with open(html_path, "w") as fh:
        fh.write(doc.html("lcpsim: the seed note's experiments"))
    return {
        "index_html": html_path,
        "report_md": md_path,
        "results_json": results_path,
        "figures": {k: os.path.relpath(v, out) for k, v in figs.items()},
        "wall_time_s": time.perf_counter() - t0,
    }


def _row(fr: dict[str, Any], scale: str) -> dict[str, Any] | None:
    for r in fr["rows"]:
        if r["scale"] == scale:
            row: dict[str, Any] = r
            return row
    return None


def _document(res: dict[str, Any], figs: dict[str, str], out: str, seed: int, quick: bool, wall: float) -> Doc:
    from .. import __version__

    def rel(k: str) -> str:
        return os.path.relpath(figs[k], out)

    d = Doc()
    d.h(1, "lcpsim: the seed note's experiments")
    d.p(
        f"lcpsim {__version__}, seed {seed}{' (quick sizes)' if quick else ''}; generated in {wall:.0f} s. "
        "Every number below is recomputed by `lcpsim report` (each experiment also has its own command, "
        "shown with its section); `results.json` holds every result with its config, seed and version."
    )
    d.p(UNITS_NOTE)
    d.p(
        "Solvers: **seed** = Lemke with the classic pivoting rule, piv_tol 1e-12, zero_tol 1e-6, applied to the LCP "
        "as assembled (scaled by s) — the seed's setting; **robust** = lcpsim's default Lemke (lexicographic, "
        "equilibrated, accepted by its residual). Every answer is judged in physical units: λ mapped back "
        "(λ = s·λ_scaled), residual ‖min(z, w)‖∞ on the unscaled LCP."
    )

    # ---- summary table
    frs, frr, frsim = res["failure_rate"]["seed"], res["failure_rate"]["robust"], res["failure_rate"]["seed_simulate"]
    crit = {(r["solver"]["name"], r["config"]["angle_deg"]): r for r in res["critical_scale"]}
    inv = {(r["solver"]["name"], r["scale"]): r for r in res["invariance"]}
    pat = {(r["solver"]["name"], r["scale"]): r for r in res["patterns"]}
    push_r = {(r["solver"]["name"], r["scale"], r["config"]["force"]): r for r in res["push"]}

    def crit_txt(r: dict[str, Any]) -> str:
        if r["critical_scale"] is not None:
            return f"{r['critical_scale']:.3g}" + ("" if r["monotone"] else " (outcomes not monotone in s)")
        return {"held_at_hi": "held already unscaled", "slides_everywhere": "none: slides at every s ≥ 1e-8"}.get(
            r["note"], "—")

    rows = []
    for sc, seedval in (("0.001", "3.9 % (97 of 2499)"), ("0.0001", "≈ 2.1 %"), ("1e-06", "0")):
        s_row, r_row = _row(frs, sc), _row(frr, sc)
        rows.append([
            f"Lemke failure rate, s = {sc}", seedval,
            f"{_pct(s_row['status_rate'])} status; {_pct(s_row['rate'])} incl. residual > 1e-6" if s_row else "—",
            f"{_pct(r_row['rate'])}" if r_row else "—",
        ])
    for angle, seedval in ((45.0001, "≈ 4e-3"), (45.2, "— (DESIGN §2, independent implementation: tips for s ≤ 0.1)")):
        rows.append([f"critical scale, {angle}°, μ = 1", seedval, crit_txt(crit[("seed", angle)]),
                     crit_txt(crit[("robust", angle)])])
    si, ri = inv[("seed", "0.001")], inv[("robust", "0.001")]
    rows.append([
        "scaling invariance of fn, fd (s = 1e-3, relative)", "~1e-16",
        f"{max(si['max_rel_dfn'], si['max_rel_dfd']):.2e} (same basis; {si['different_basis']} LCPs changed basis, "
        f"{si['status_changed']} changed status)",
        f"{max(ri['max_rel_dfn'], ri['max_rel_dfd']):.2e} (same basis; {ri['different_basis']} changed basis)",
    ])
    sp, rp = push_r[("seed", "none", 9.79)], push_r[("robust", "none", 9.79)]
    rows.append(["pushed cube 9.79 N: outcome, λ", "stays, λ ≈ 1e-19", f"{sp['outcome']}, λ max {sp['lambda_max']:.2e}",
                 f"{rp['outcome']}, λ max {rp['lambda_max']:.2e}"])
    rows.append([
        "pushed cube: normal impulses (N·s)", "0, 1e-5, 0.004895, 0.004905",
        ", ".join(f"{x:.6g}" for x in sorted(sp["normal_impulses"])),
        ", ".join(f"{x:.6g}" for x in sorted(rp["normal_impulses"])),
    ])
    ps, pr = pat[("seed", "0.001")], pat[("robust", "0.001")]
    rows.append([
        "impossible patterns; scaling changes patterns (s = 1e-3)", "none; scaling does not matter",
        f"{ps['impossible']['unscaled'] + ps['impossible']['scaled']} LCPs in solved answers "
        f"(+{ps['impossible']['unscaled_failed'] + ps['impossible']['scaled_failed']} in failed); "
        f"{ps['changed']} of {ps['contacts']} contacts change",
        f"{pr['impossible']['unscaled'] + pr['impossible']['scaled']} LCPs; {pr['changed']} of {pr['contacts']} change",
    ])
    d.h(2, "The seed's claims beside ours")
    d.table(["claim", "seed note", "ours: seed preset", "ours: robust"], rows)
    for para in _differences_text(res):
        d.p(para)

    # ---- corpus
    c = res["corpus"]
    d.h(2, "The seed corpus")
    d.p(
        f"{c['lcps']} LCPs from {len(c['simulations'])} simulations of a 1 kg unit cube (h = 1e-3 s, k = 8), "
        "stepped unscaled with the robust solver: drops flat, on an edge and on a corner, sliding to rest, "
        "pushed at 9.79 N and 12 N, slopes at 20°, 30°, 45.0001°, 45.2°, and seeded random tumbles onto slopes "
        "(see `lcpsim.experiments.seed_corpus`). By size: "
        + ", ".join(f"n = {n}: {k}" for n, k in c["by_size"].items()) + "."
    )
    d.table(["simulation", "slope (°)", "μ", "LCPs"],
            [[s["name"], f"{s['angle_deg']:g}", f"{s['mu']:g}", s["lcps"]] for s in c["simulations"]])

    # ---- failure rate
    d.h(2, "Failure rate per scale")
    d.p(
        "`lcpsim failure-rate --scales none,1e-3,1e-4,1e-6,1e-8 --solver seed` (and `--solver robust`). The same "
        "corpus LCPs are scaled by each s and re-solved. A failure is a status other than solved, or a "
        "physical-unit residual above 1e-6 (`accepted wrong`: the solver said solved, the unscaled residual "
        "disagrees — the tolerance artifact)."
    )
    hdr = ["solver", "s", "LCPs", "status failures", "residual failures", "accepted wrong", "any failure", "statuses"]
    trows = []
    for name, fr in (("seed", frs), ("robust", frr), ("seed (simulate)", frsim)):
        for r in fr["rows"]:
            trows.append([name, r["scale"], r["lcps"], f"{r['status_failures']} ({_pct(r['status_rate'])})",
                          f"{r['residual_failures']} ({_pct(r['residual_rate'])})", r["accepted_wrong"],
                          _pct(r["rate"]), ", ".join(f"{k} {v}" for k, v in r["by_status"].items() if k != "solved") or "—"])
    d.table(hdr, trows)
    d.img(rel("failure_rate"), "failure rate per scale")
    d.p(
        "The seed counted failures over one simulation run at each scale; `--mode simulate` does that (each "
        "corpus simulation re-run with the seed preset in the loop; a failed step's last iterate is applied, so "
        "trajectories, and the LCP counts, differ per scale):"
    )
    d.img(rel("failure_rate_sim"), "failure rate per scale, simulated")

    # ---- solver comparison (issue 5)
    _comparison_section(d, res["comparison"])

    # ---- slope
    d.h(2, "Slope test")
    d.p(
        "`lcpsim slope --angle-deg A --mu 1 --scale S --solver P --seconds T`. A μ = 1 cube on a slope just "
        "steeper than 45° must slide with ½·g·(sin θ − μ cos θ)·T² and not tip. Outcome: tip if rotated > 5°, "
        "else slide if it moved ≥ half the analytic distance, else rest. `cone excess` counts solved steps whose "
        "friction exceeds μ·Σfn (impossible for an exact solution): the seed's artifact at work."
    )
    srows = []
    for r in res["slope"]:
        srows.append([
            r["solver"]["name"], f"{r['config']['angle_deg']:g}", r["scale"], r["outcome"], r["slide_distance_m"],
            r["expected_slide_m"], r["tilt_deg"], r["lcp_failures"],
            "—" if r["first_failure_s"] is None else f"{r['first_failure_s']:.3f}",
            r["cone_excess_steps"], r["energy_gain_J"],
        ])
    d.table(["solver", "angle (°)", "s", "outcome", "slide (m)", "analytic (m)", "max rotation (°)", "LCP failures",
             "first failure (s)", "cone-excess steps", "energy gain (J)"], srows)
    d.img(rel("slope_45_0001"), "slope test at 45.0001°")
    d.img(rel("slope_45_2"), "slope test at 45.2°")

    # ---- critical scale
    d.h(2, "Critical scale")
    d.p(
        "`lcpsim critical-scale --angle-deg A --mu 1 --solver seed`: one slope test per decade from s = 1 down to "
        "1e-8, then bisection in log s between the largest held scale and the slide above it."
    )
    crows = []
    for r in res["critical_scale"]:
        crows.append([r["solver"]["name"], f"{r['config']['angle_deg']:g}", crit_txt(r),
                      "—" if r["bracket"] is None else f"[{r['bracket'][0]:.3g}, {r['bracket'][1]:.3g}]",
                      ", ".join(f"{o['scale']:.2g}:{o['outcome']}" for o in r["outcomes"] if o["stage"] == "grid")])
    d.table(["solver", "angle (°)", "critical scale", "bracket", "grid outcomes (s:outcome)"], crows)
    d.img(rel("critical_scale"), "critical scale")

    # ---- invariance
    d.h(2, "Scaling invariance")
    d.p(
        "`lcpsim invariance --scale S --solver P [--digits 20]`: every corpus LCP solved unscaled and scaled; "
        "fn, fd compared directly, λ_scaled·s against λ. Headline figures over LCPs whose Lemke basis is the "
        "same both times (then only round-off can differ); an LCP with several solutions may end in another "
        "basis — counted apart, with how many of those are two valid solutions."
    )
    irows = []
    for r in res["invariance"]:
        irows.append([r["solver"]["name"], r["scale"], r["lcps"], r["compared"], r["max_abs_dfn"], r["max_abs_dfd"],
                      r["max_rel_dfn"], r["max_rel_dfd"], r["max_rel_lambda_err"], r["different_basis"],
                      r["different_basis_both_valid"], r["status_changed"]])
    d.table(["solver", "s", "LCPs", "solved both", "max |Δfn|", "max |Δfd|", "rel Δfn", "rel Δfd", "rel λ err",
             "other basis", "both valid", "status changed"], irows)
    d.img(rel("invariance"), "invariance histogram")
    ex = next((r for r in res["invariance"] if r["solver"]["name"] == "robust" and r.get("examples")), None)
    if ex:
        lines = []
        for e in ex["examples"]:
            lines += [f"Size = {e['n']}, {e['contacts']} contact points ({e['simulation']}, step {e['step']}), s = {ex['scale']}",
                      "Before", " ".join(f"{x:.20g}" for x in e["before"]),
                      "After", " ".join(f"{x:.20g}" for x in e["after"]), ""]
        d.p("As the seed printed them (robust, 20 significant digits; After = the scaled LCP's z, λ = λ/s):")
        d.pre("\n".join(lines).strip())

    # ---- patterns
    d.h(2, "Contact patterns")
    d.p(
        "`lcpsim patterns --scale S --solver P`: sign of (fn, Σfd, λ) per contact, unscaled and scaled; "
        "(0,+,0), (0,+,+) and (+,0,+) are impossible for an exact solution with μ > 0."
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
            d.img(rel(k), k)

    # ---- push
    d.h(2, "Pushed cube")
    d.p(
        "`lcpsim push --force F --mu 1 --solver P`: a 1 kg cube, μ = 1, pushed at its centre of mass; it must "
        "stay iff F ≤ μmg = 9.81 N with friction exactly F, and slide above."
    )
    prows = []
    for r in res["push"]:
        prows.append([r["solver"]["name"], r["scale"], r["config"]["force"], r["outcome"], r["expected_outcome"],
                      f"{r['friction_force_N']:.10g}", r["lambda_max"], r["displacement_m"], r["lcp_failures"]])
    d.table(["solver", "s", "F (N)", "outcome", "exact", "friction (N)", "λ max", "moved (m)", "LCP failures"], prows)
    d.p(
        f"Normal impulses at 9.79 N (robust, unscaled), by position along the push: "
        + ", ".join(f"{x:.6g} N·s at {o:+.2f} m" for x, o in zip(rp["normal_impulses"], rp["contact_offsets_m"]))
        + " — the load sits on the leading edge, as the seed's 0, 1e-5, 0.004895, 0.004905 show."
    )
    d.img(rel("push_sweep"), "push sweep")
    d.img(rel("push_trace"), "push traces")
    return d


def _comparison_section(d: Doc, cmp: dict[str, Any]) -> None:
    cfg = cmp["config"]
    scales = ",".join("none" if x in (None, "none") else f"{float(x):g}" for x in cfg["scales"])
    seed_c, hard_c = cmp["corpora"]["seed"], cmp["corpora"]["hard"]
    d.h(2, "Solver comparison: classic, robust, PGS, Newton–FB")
    d.p(
        f"`lcpsim failure-rate --solvers {','.join(s['name'] for s in cmp['solvers'])} --corpus seed,hard "
        f"--scales {scales} --max-lcps {cfg['max_lcps']} --hard-count {hard_c['lcps']}` "
        f"(drop `--max-lcps` for the whole seed corpus). Corpora: {seed_c['lcps']} LCPs of the seed corpus "
        f"(a seeded subset), and {hard_c['lcps']} LCPs of the hard generator (`lcpsim.generate.hard_corpus`, seed "
        f"{hard_c['seed']}: " + ", ".join(f"{k} {v}" for k, v in hard_c["by_kind"].items())
        + f"; n up to {hard_c['max_n']}), generated at each scale s and judged on the same scenes at s = 1. "
        "Solvers: **seed** = classic Lemke (piv_tol 1e-12, zero_tol 1e-6, on the LCP as scaled); **robust** = "
        "lcpsim's default; **pgs**, **newton_fb** with their defaults. Counts: status ≠ solved; physical residual "
        f"> {cmp['tol']:g} and > {cmp['rel_tol']:g}·(1 + ‖q‖∞) (issue 5's criterion); accepted wrong = said "
        "solved, physical residual > 1e-6."
    )
    d.p(
        f"Certified (robust, LCPs with n ≤ {cmp['certify_max_n']}): the final basis re-solved in exact rational "
        "arithmetic from the floats as given (`solve_lcp(..., certify=True)`). *exact*: z ≥ 0, w ≥ 0, zᵀw = 0 "
        "hold exactly. On these rank-deficient contact LCPs entries that are exactly 0 in real arithmetic are "
        "±1e-17 after rounding, so a right basis often fails the exact check; *η ≤ 1e-14*: the answer is the exact "
        "solution of an LCP within 1e-14 (relative, entrywise) of the one given (Oettli–Prager backward error); "
        "*η or residual*: that, or the exact basis solution's natural residual ≤ 1e-14·(1 + ‖q‖∞) (resting "
        "contacts whose tangential q is ±1e-17, where a componentwise η is meaningless)."
    )

    def share(k: str, row: dict[str, Any]) -> str:
        if row.get(k) is None or not row.get("cert_lcps"):
            return "—"
        return f"{row[k]}/{row['cert_lcps']} ({100 * row[k] / row['cert_lcps']:.1f} %)"

    trows = []
    for r in cmp["comparison"]:
        trows.append([
            r["solver"], r["corpus"], r["scale"], r["lcps"], r["status_failures"], r["residual_failures"],
            "—" if r.get("rel_residual_failures") is None else r["rel_residual_failures"], r["accepted_wrong"],
            share("certified", r), share("certified_eta", r), share("certified_either", r),
        ])
    d.table(["solver", "corpus", "s", "LCPs", "status failures", "residual > 1e-6", "residual > 1e-9·(1+‖q‖)",
             "accepted wrong", "certified exact", "η ≤ 1e-14", "η or residual"], trows)


def _g(x: Any, fmt: str = ".3g") -> str:
    return "—" if x is None else format(x, fmt)


def _differences_text(res: dict[str, Any]) -> list[str]:
    """Paragraphs saying where and why our figures differ from the seed's."""
    frs = res["failure_rate"]["seed"]
    crit = {(r["solver"]["name"], r["config"]["angle_deg"]): r for r in res["critical_scale"]}
    sl = {(r["solver"]["name"], r["config"]["angle_deg"], r["scale"]): r for r in res["slope"]}
    sp = next(r for r in res["push"] if r["solver"]["name"] == "seed" and r["scale"] == "none" and r["config"]["force"] == 9.79)
    parts = []
    s3, s6 = _row(frs, "0.001"), _row(frs, "1e-06")
    if s3 and s6:
        parts.append(
            f"**Failure rates.** With the seed's setting our status failures fall from {_pct(s3['status_rate'])} at "
            f"s = 1e-3 to {_pct(s6['status_rate'])} at s = 1e-6 — the seed's trend (3.9 % → 0) — at other levels: "
            "the seed's one simulation, units and Lemke are not ours, and our corpus mixes many scenes. Judged in "
            "physical units the improvement is an artifact: the answers accepted at s = 1e-6 fail the unscaled "
            f"residual in {_pct(s6['residual_rate'])} of the LCPs (friction without normal force, friction beyond "
            "the cone) — the looser cone of DESIGN §2. The robust solver fails on none at any scale."
        )
    a, b = sl.get(("seed", 45.2, "none")), sl.get(("seed", 45.2, "0.001"))
    c0, c2 = crit[("seed", 45.0001)], crit[("seed", 45.2)]
    if a and b:
        txt = (
            "**Slope test and critical scale.** With the seed preset the 45.2° cube "
            f"{'slides' if a['outcome'] == 'slide' else a['outcome'] + 's'} unscaled ({_g(a['slide_distance_m'])} m in "
            f"{a['seconds']:g} s; analytic {_g(a['expected_slide_m'])} m; {a['lcp_failures']} failed LCPs) and at "
            f"s = 1e-3 ends as '{b['outcome']}' with {b['held_steps_before_failure']} solved steps carrying friction "
            "beyond μ·Σfn before any failure — the cube held by the looser cone, the seed's phenomenon."
        )
        if b["lcp_failures"]:
            st = ", ".join(f"{k} {v}" for k, v in b["lcp_statuses"].items() if k != "solved")
            txt += (
                f" There our classic Lemke then fails (first at t = {_g(b['first_failure_s'])} s; {st}); the "
                "simulator applies a failed solve's last iterate"
                + (f", which launches the cube (energy gain {_g(b['energy_gain_J'], '.2g')} J), so this 'tip' ends "
                   "as a blow-up." if b["energy_gain_J"] > 1e-6 else ".")
            )
        txt += (
            f" The switch lies at s ≈ {_g(c2['critical_scale'])}; DESIGN §2's independent classic implementation "
            "tipped for s ≤ 0.1."
        )
        parts.append(txt)
    z = sl.get(("seed", 45.0001, "none"))
    lo = sl.get(("seed", 45.0001, "1e-06"))
    if z and lo:
        txt = (
            " At 45.0001° the stick solution of our 1 kg, 1 m cube violates the cone by only ~2.4e-8 N·s — below "
            "the user zero even unscaled — so a classic Lemke should hold it at every s ≤ 1, and the seed's 4e-3 "
            f"(its own units) has no counterpart here. Ours, unscaled: '{z['outcome']}', "
            f"{_g(z['slide_distance_m'])} m (analytic {_g(z['expected_slide_m'])} m)"
        )
        if z["lcp_failures"]:
            st = ", ".join(f"{k} {v}" for k, v in z["lcp_statuses"].items() if k != "solved")
            txt += (
                f", with failed LCPs from t = {_g(z['first_failure_s'])} s ({st}; a failed step applies no impulse, "
                "so the cube drops for that step)"
            )
        txt += (
            f"; at s = 1e-6: '{lo['outcome']}', {_g(lo['slide_distance_m'])} m with {lo['cone_excess_steps']} steps "
            f"of excess friction and {_g(lo['tilt_deg'])}° rotation (a held cube tipping slowly moves its centre "
            "down-slope too, and can pass the half-distance test). "
            + ("Outcomes are not monotone in s there; " if not c0["monotone"] else "")
            + f"the search reports {_g(c0['critical_scale']) if c0['critical_scale'] is not None else c0['note']}."
        )
        parts[-1] += txt
    rob = [r for r in res["slope"] if r["solver"]["name"] == "robust"]
    if rob:
        worst = max(abs(r["slide_rel_error"]) for r in rob if r["slide_rel_error"] is not None)
        parts[-1] += (
            f" The robust solver slides at every scale, within {100 * worst:.2f} % of the analytic distance, with no "
            "LCP failure."
        )
    parts.append(
        f"**Pushed cube.** The seed's λ ≈ 1e-19 is round-off in its solver; ours is {_g(sp['lambda_max'], '.2g')} with "
        f"the seed preset (unscaled; {sp['lcp_failures']} failed LCPs) and exactly 0 with robust. The normal "
        "impulses match the seed's to the digits shown."
    )
    return parts
