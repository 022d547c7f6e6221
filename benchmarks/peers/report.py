"""``benchmarks/RESULTS.md`` from a peers' run: the speed goals checked on the
run, one table per family of problem sets, and how it was measured (the
per-problem figures stay in ``results.json.gz``)."""

from __future__ import annotations

import re
import sys
from typing import Any

import numpy as np

from common import HERE, RESULTS_MD
from solvers import Solver


def fmt_time(t: float | None) -> str:
    if t is None:
        return "—"
    if t < 1e-3:
        return f"{t * 1e6:.1f} µs"
    if t < 1.0:
        return f"{t * 1e3:.2f} ms"
    return f"{t:.2f} s"


def fmt_ratio(r: float | None) -> str:
    return "—" if r is None else f"{r:.2f}×"


def fmt_count(k: int, n: int) -> str:
    if k == 0:
        return "0"
    pct = 100.0 * k / n
    return f"{k} ({pct:.1f} %)" if pct < 1 else f"{k} ({pct:.0f} %)"


def table(summary: dict[str, Any], solvers: list[Solver], b2b: bool) -> list[str]:
    head = ["group", "solver", "failed", "own word", "resid. > tol (given)", "resid. > tol (phys.)",
            "said solved, wrong", "median (interleaved)", "× robust"]
    if b2b:
        head += ["median (back-to-back)", "× robust"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for g, gs in summary.items():
        if g == "all" and len(summary) == 2:
            continue  # one group: "all" repeats it
        label = f"{g}" if g != "all" else f"all (n = {gs['sizes'][0]}–{gs['sizes'][2]})"
        for s in solvers:
            r = gs["solvers"][s.key]
            n = r["problems"]
            cells = [label, s.name, fmt_count(r["failed"], n), fmt_count(r["own_word"], n),
                     fmt_count(r["residual_given"], n), fmt_count(r["residual_physical"], n),
                     fmt_count(r["said_solved_wrong"], n),
                     fmt_time(r["median_s_interleaved"]), fmt_ratio(r["ratio_interleaved"])]
            if b2b:
                cells += [fmt_time(r["median_s_back_to_back"]), fmt_ratio(r["ratio_back_to_back"])]
            lines.append("| " + " | ".join(cells) + " |")
            label = ""
    return lines


#: Set-key prefixes and the family each names.
FAMILIES = [
    (("contact/",), "Contact LCPs of the one-cube generator"),
    (("cubes/",), "Cube corpus (LCPs of seeded one-cube simulations)"),
    (("hard/",), "Hard contact LCPs"),
    (("spd/",), "Random SPD LCPs"),
]


def family_table(sets: list[tuple[str, dict[str, Any]]], solvers: list[Solver]) -> list[str]:
    """One table for a family of sets (one set per scale or size): per solver and set,
    failed of the set's problems and the interleaved time ÷ lcpsim robust's (median
    over the set's problems, back-to-back in brackets where measured)."""
    cols = [s["title"].split(", ")[-1] for _, s in sets]
    lines = ["| solver | " + " | ".join(cols) + " |", "|---|" + "---|" * len(cols)]
    for sv in solvers:
        cells = []
        for _, s in sets:
            r = s["summary"]["all"]["solvers"][sv.key]
            ratio = fmt_ratio(r["ratio_interleaved"])
            if r.get("ratio_back_to_back") is not None:
                ratio += f" ({fmt_ratio(r['ratio_back_to_back'])})"
            cells.append(f"{fmt_count(r['failed'], r['problems'])} · {ratio}")
        lines.append(f"| {sv.name} | " + " | ".join(cells) + " |")
    return lines


TARGETS = [
    # (set-key prefix, groups, peer, target ratio)
    ("contact/", ("n = 20", "n = 40"), "siconos_lexicolemke", 5.0),
    ("contact/", ("n = 20", "n = 40"), "drake_moby", 10.0),
    ("spd/n=1000", ("n = 1000",), "siconos_lexicolemke", 4.0),
]


def headline(results: dict[str, Any], solvers: list[Solver], tol: float) -> tuple[list[str], dict[str, Any]]:
    """Speed goals checked on this run, plus pooled failure rates on the contact sets."""
    names = {s.key: s.name for s in solvers}
    sets = results["sets"]
    lines = ["| target | measured (interleaved) | back-to-back | interleaved, on the problems the peer got right "
             "| lcpsim robust failures there | met? |",
             "|---|---|---|---|---|---|"]
    data: dict[str, Any] = {}
    for prefix, groups, peer, goal in TARGETS:
        if peer not in names:
            continue
        for g in groups:
            ri, rb, rr, fails, total = [], [], [], 0, 0
            for key, s in sets.items():
                if not key.startswith(prefix) or g not in s["summary"]:
                    continue
                row = s["summary"][g]["solvers"]
                if row[peer]["ratio_interleaved"] is not None:
                    ri.append(row[peer]["ratio_interleaved"])
                if row[peer]["ratio_back_to_back"] is not None:
                    rb.append(row[peer]["ratio_back_to_back"])
                if row[peer]["ratio_interleaved_right"] is not None:
                    rr.append(row[peer]["ratio_interleaved_right"])
                fails += row["lcpsim_robust"]["failed"]
                total += row["lcpsim_robust"]["problems"]
            if not ri:
                continue
            lo, hi = min(ri), max(ri)
            span = f"{np.median(ri):.2f}× (sets: {lo:.2f}–{hi:.2f}×)" if len(ri) > 1 else f"{ri[0]:.2f}×"
            bspan = "—" if not rb else (f"{np.median(rb):.2f}×" + (f" ({min(rb):.2f}–{max(rb):.2f}×)" if len(rb) > 1 else ""))
            rspan = "—" if not rr else (f"{np.median(rr):.2f}×" + (f" ({min(rr):.2f}–{max(rr):.2f}×)" if len(rr) > 1 else ""))
            met = "yes" if np.median(ri) >= goal and fails == 0 else "no"
            lines.append(f"| {g}: lcpsim robust ≥ {goal:g}× faster than {names[peer]} | {span} | {bspan} | {rspan} | "
                         f"{fails} of {total} | {met} |")
            data[f"{prefix}{g}:{peer}"] = {"goal": goal, "ratios_interleaved": ri, "ratios_back_to_back": rb,
                                           "ratios_interleaved_peer_right": rr,
                                           "robust_failures": fails, "problems": total, "met": met == "yes"}
    # Pooled failure rates over every contact scale, sizes 20 and 40, with each
    # solver's time ratio to lcpsim robust (median over the scales, as above).
    pooled = ["", "Failures pooled over all contact-LCP scales (n = 20 and 40; failed = own word or physical "
              f"residual > {tol:g}), and time ÷ lcpsim robust's (median over the scales; interleaved, back-to-back "
              "in brackets):", "", "| solver | failed | own word | said solved, wrong | × robust, n = 20 | "
              "× robust, n = 40 |", "|---|---|---|---|---|---|"]
    for s in solvers:
        f = o = w = t = 0
        ratios: dict[str, tuple[list[float], list[float]]] = {"n = 20": ([], []), "n = 40": ([], [])}
        for key, st in sets.items():
            if not key.startswith("contact/"):
                continue
            for g, (ri, rb) in ratios.items():
                if g in st["summary"]:
                    r = st["summary"][g]["solvers"][s.key]
                    f, o, w, t = f + r["failed"], o + r["own_word"], w + r["said_solved_wrong"], t + r["problems"]
                    for out, k in ((ri, "ratio_interleaved"), (rb, "ratio_back_to_back")):
                        if r[k] is not None:
                            out.append(r[k])
        cells = [f"{fmt_ratio(float(np.median(ri)) if ri else None)} "
                 f"({fmt_ratio(float(np.median(rb)) if rb else None)})" for ri, rb in ratios.values()]
        if t:
            pooled.append(f"| {s.name} | {fmt_count(f, t)} of {t} | {fmt_count(o, t)} | {fmt_count(w, t)} | "
                          f"{cells[0]} | {cells[1]} |")
    return lines + pooled, data


def write_report(results: dict[str, Any], solvers: list[Solver], sim_md: list[str] | None) -> None:
    m, v, cfg = results["machine"], results["versions"], results["config"]
    lines = [
        "# Benchmarks: lcpsim beside Siconos, Drake, MuJoCo and PyBullet",
        "",
        "Written by `benchmarks/peers/run.py` — do not edit by hand; rerun instead:",
        "",
        "```bash",
        "bash benchmarks/peers/setup.sh                      # peers + lcpsim wheel in benchmarks/peers/.venv",
        f"benchmarks/peers/.venv/bin/python {results['command']}",
        "```",
        "",
        "Raw per-problem results (statuses, residuals, median times): `benchmarks/peers/results.json.gz`.",
        "",
        "## Machine and versions",
        "",
        f"- date: {results['date']} (run took {results['duration_s'] / 60:.1f} min)",
        f"- CPU: {m['cpu']}, {m['cores']} cores ({m['cores_usable']} usable), {m['memory']} RAM, "
        f"Linux {m['kernel']}",
        f"- load average (1, 5, 15 min) before / after: {results['load_before']} / {results['load_after']} — "
        "the machine is shared with other jobs, so absolute times are noisy; ratios come from the same run, "
        "interleaved per problem",
        f"- Python {v['python']}, numpy {v['numpy']}; lcpsim {v['lcpsim']} ({v.get('lcpsim_revision', '?')}); "
        f"Siconos {v['siconos']} (Debian python3-siconos); Drake {v['drake']}; MuJoCo {v['mujoco']}; "
        f"PyBullet {v['pybullet']}",
        f"- threads: OMP/OPENBLAS/MKL_NUM_THREADS = {cfg['threads_env']}",
        f"- timing: `time.perf_counter()` around each call; {cfg['passes']} interleaved passes, "
        f"{cfg['repeats']} back-to-back repeats (see below); tolerance {cfg['tol']:g}",
        "",
        "## How it is measured",
        "",
        "Every solver is called once per problem from Python (one call = one solve):",
        "",
    ]
    for s in solvers:
        lines.append(f"- **{s.name}**: {s.note}")
    lines += [
        "",
        "lcpsim's timed call takes numpy `M, q` and returns its result object. For the peers the problem object is "
        "built before the timer starts (Siconos `LCP`, `SolverOptions`, output arrays; Drake's "
        "`MathematicalProgram` with `AddLinearComplementarityConstraint`); only the solve call (and Drake's "
        "`GetSolution`) is timed — this favours the peers. Each solver is handed fresh copies of `M` and `q` made "
        "just before (in cache, as after a simulator's assembly — for lcpsim as for a peer whose problem object "
        "was just built from them).",
        "",
        "- **interleaved** (headline): passes over a set; in each pass every problem is solved once by every "
        "solver in turn (rotating order), median per problem over passes. Each call finds the caches as other "
        "code left them, as in a simulator, and load changes hit all solvers alike.",
        "- **back-to-back**: repeated calls of one solver on one problem (warm caches), median per problem. "
        "Not run for the hard corpus and SPD n = 1000.",
        "- **× robust** is the median over problems of (solver's time / lcpsim robust's time) on the same "
        "problem: above 1 means lcpsim robust is faster. Times of failed solves count too.",
        f"- **failed** = the solver said it failed (**own word**: Siconos `info ≠ 0`, Drake `is_success()` false, "
        f"lcpsim status ≠ `solved`) or its answer has a natural residual ‖min(z, Mz+q)‖∞ > {cfg['tol']:g} in "
        "physical units. **resid. > tol (given)**: the residual in the units of the problem the solver was given; "
        "**(phys.)**: for a cone-scaled contact LCP, z mapped back (z_phys = D z, D = diag(I, I, s·I): λ times s) "
        "and the residual taken on the unscaled problem (N·s, m/s); the same as (given) for unscaled and SPD "
        "problems. **said solved, wrong**: the solver reported success and the physical residual is above the "
        "tolerance.",
        "",
        "## Speed goals checked on this run",
        "",
        "The project's goals for lcpsim robust against the Lemke solvers of Siconos and Drake, judged on the interleaved ratio (median over the contact sets, one per scale; the range over the sets "
        "in brackets) and on lcpsim robust having no failure there. The column on the problems the peer got "
        "right leaves out its failed solves, which often end early on a wrong answer.",
        "",
    ]
    hl, _ = headline(results, solvers, cfg["tol"])
    lines += hl
    lines += ["", "## Problem sets", "",
              "One table per family: each cell is *failed of the set's problems · time ÷ lcpsim robust's* (median "
              "over the set's problems, interleaved; back-to-back in brackets where measured). The per-size tables "
              "(own word, residuals in given and physical units, median times) are in `results.json.gz`; "
              "`report.table` renders them.", ""]
    for note in results.get("notes", []):
        lines.append(f"- {note}")
    if results.get("notes"):
        lines.append("")
    for prefixes, title in FAMILIES:
        fam = [(k, s) for k, s in results["sets"].items() if k.startswith(prefixes)]
        if not fam:
            continue
        first = re.sub(r"(s|n) = [^ ,.]+\.$", r"\1 as in each column.", fam[0][1]["description"])
        lines += [f"### {title}", "", first, ""]
        lines += family_table(fam, solvers)
        lines.append("")
    if sim_md:
        lines += sim_md
    # many_bodies.py owns the section from "## Many bodies" to the end: keep it.
    sys.path.insert(0, str(HERE))
    from many_bodies_report import tail

    kept = tail(RESULTS_MD.read_text()) if RESULTS_MD.exists() else ""
    RESULTS_MD.write_text("\n".join(lines).rstrip("\n") + "\n" + kept)
