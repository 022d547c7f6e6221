"""The markdown section of ``many_bodies.py``'s results (for ``benchmarks/RESULTS.md``)."""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np

TITLES = {
    "lcpsim": "lcpsim (`World.run`)",
    "mujoco": "MuJoCo (`mj_step`, nstep)",
    "pybullet": "PyBullet (DIRECT)",
    "rapier": "Rapier (rapier3d-f64, Rust)",
}

NOTES = [
    "**lcpsim**: hard contact, a Stewart–Trinkle LCP per step over the contacts (per contact island where "
    "lcpsim splits them; the friction directions the file's cone gives, named under 'Scenes built by': MuJoCo's "
    "default pyramid is 4, so n = 6 per contact point, since d4697cf, 8 before it) solved by Lemke; LCPs counts the "
    "steps with contacts; the stepping loop in Rust (`World.run`). A steps/s of a run that "
    "timed out is over the steps it did.",
    "**MuJoCo**: soft contacts (defaults: pyramidal cone, Newton solver, `solref` 0.02 s), so boxes rest a little "
    "inside each other and stacks sink; `mj_step(m, d, nstep)` from Python.",
    "**PyBullet**: sequential impulses, 50 iterations, box friction per direction; lateral friction √0.5 on every "
    "body since Bullet multiplies the pair's values; `stepSimulation` per step from Python.",
    "**Rapier**: soft-constraint impulse solver (4 iterations, defaults); stepping in Rust in the "
    "`rapier-bench` process, no Python in the loop.",
    "Penetration: the deepest box–box (separating-axis depth) or box–ground overlap over the sampled states "
    "(the start and every tenth of the run; in brackets, in the last one), the same code for every engine. Drift: the largest distance a "
    "tower's top box moved over the run (the lowest vertical change in brackets). Contacts: the most contact "
    "points an engine reported at a sample (lcpsim: the most in any step). Peak RSS: the worker process's "
    "maximum resident set (`wait4`), the interpreter and the engine's libraries included.",
]


def fmt(x: float | None, spec: str = ".3g") -> str:
    return "—" if x is None else format(x, spec)


def ran(s: dict[str, Any], e: dict[str, Any]) -> str:
    reps = len(s.get("rates", []))
    if s["outcome"] == "ok":
        rounds = len(s.get("round_rates", [])) or 1
        within = f" in {rounds} rounds" if rounds > 1 else ""
        return f"{s['steps']} steps × {reps} rep{'s' if reps != 1 else ''}{within}"
    if s["outcome"] in ("timed_out", "killed"):
        how = ", killed mid-call" if s["outcome"] == "killed" else ""
        return f"**timed out** after {s['steps']} of {e['steps']} steps{how}"
    err = s.get("error", "")
    m = re.search(r"memory allocation of (\d+) bytes failed", err)
    if m:
        b = int(m.group(1))
        return (f"**not run**: an allocation of {b / 1e9:.3g} GB (a dense n × n M, n = {math.sqrt(b / 8):,.0f}) "
                f"failed under the cap, after {s['steps']} steps")
    return f"**{s['outcome']}**: {err}"


def lcp_cell(s: dict[str, Any]) -> str:
    st = s.get("stats") or {}
    if "lcps" not in st:
        return ""
    if "max_island_lcp" in st:  # one LCP per contact island
        return (f"{st['lcps']} / {st['failures']} / {st['max_island_lcp']} (up to {st['max_islands']} islands, "
                f"all contacts n = {st['max_lcp_size']})")
    return f"{st['lcps']} / {st['failures']} / {st['max_lcp_size']}"


def same_steps_ratio(s: dict[str, Any], mj: dict[str, Any]) -> float | None:
    """MuJoCo's time for the first steps a run did, over that run's: a heap's first
    steps (in free fall) are cheaper than its last, so a run cut short is compared
    on the same steps too."""
    done, prog, mprog = s.get("steps", 0), s.get("progress") or [], mj.get("progress") or []
    if not done or not prog or not mprog or mprog[-1][0] < done or s is mj:
        return None
    t_mj = float(np.interp(done, [0] + [p[0] for p in mprog], [0.0] + [p[1] for p in mprog]))
    return t_mj / prog[-1][1] if prog[-1][1] > 0 else None


def windows(res: dict[str, Any], bounds: list[int]) -> list[str]:
    """Each engine's stepping seconds between successive ``bounds`` (steps), read
    from its progress points (interpolated inside a stepping call, which the
    line marks): where in a heap's course the time goes."""
    lines = []
    for key, sc in res["scenes"].items():
        for eng, s in sc["engines"].items():
            prog = s.get("progress") or []
            if not prog:
                continue
            steps, secs = [0] + [p[0] for p in prog], [0.0] + [p[1] for p in prog]
            for a, b in zip(bounds, bounds[1:]):
                if b > steps[-1]:
                    break
                t = float(np.interp(b, steps, secs) - np.interp(a, steps, secs))
                exact = a in steps and b in steps
                lines.append(f"{key} {eng} steps {a}-{b}: {t:.1f} s, {t / (b - a):.3f} s/step"
                             + ("" if exact else " (interpolated)"))
    return lines


def render(res: dict[str, Any]) -> list[str]:
    cfg = res["config"]
    v = res["versions"]
    lines = [
        "## Many bodies: lcpsim beside MuJoCo, PyBullet and Rapier",
        "",
        f"Machine: {res['machine']}. Versions: lcpsim {v.get('lcpsim')} "
        f"({v.get('lcpsim_revision', 'revision unknown')}), MuJoCo {v.get('mujoco')}, PyBullet {v.get('pybullet')}, "
        f"rapier3d-f64 {v.get('rapier3d-f64')}, Python {v.get('python')}, numpy {v.get('numpy')}.",
        "",
        f"1 kg unit cubes, μ = {cfg['mu']} for every pair, g = {cfg['g']}, dt = {cfg['dt']:g} s, on a ground plane; "
        "every engine starts from the state exported from the lcpsim world. Each engine × scene runs in its own "
        f"process under a {cfg['mem_cap_gb']:g} GiB address-space cap and a {cfg['budget_s']:g} s wall-clock budget "
        f"(killed {cfg['grace_s']:g} s past it if a stepping call is still running). steps/s counts the stepping "
        "calls only (median over the repetitions that fit in the budget; for the scenes with several rounds, "
        "over every repetition of rounds run engine after engine, so a change of the machine's speed falls on "
        "every engine alike). "
        f"Command: `{res.get('command', 'benchmarks/peers/.venv/bin/python benchmarks/peers/many_bodies.py')}`. "
        "The machine is shared "
        f"(1-minute load average {res['load_average_before'][0]:.1f} before the run, "
        f"{res['load_average_after'][0]:.1f} after): rates move by tens of per cent between runs.",
        "",
        "| scene | engine | ran | steps/s | × MuJoCo | contacts (max) | LCPs / failures / largest n | top drift (m) "
        "| max penetration (m) (at the end) | peak RSS (MB) |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for key, e in res["scenes"].items():
        mj = e["engines"].get("mujoco", {}).get("steps_per_second")
        first = True
        for eng, s in e["engines"].items():
            walls = f" + {e['static_boxes']} static boxes" if e.get("static_boxes") else ""
            scene = (f"{e['title']} ({e['bodies']} bodies{walls}, {e['seconds']:g} s = {e['steps']} steps)"
                     if first else "")
            first = False
            if s["outcome"] == "not_run":
                lines.append(f"| {scene} | {TITLES.get(eng, eng)} | not run: {s['error']} | | | | | | | |")
                continue
            sps = s.get("steps_per_second")
            ratio = f"{sps / mj:.3g}×" if sps and mj else "—"
            same = same_steps_ratio(s, e["engines"].get("mujoco", {}))
            if s["outcome"] != "ok" and same:
                ratio += f" ({same:.3g}× over the same first {s['steps']} steps)"
            contacts = s.get("stats", {}).get("max_contacts")
            if contacts is None or eng != "lcpsim":
                sampled = s.get("contacts_sampled") or []
                contacts = max(sampled) if sampled else None
            d = s.get("drift")
            drift = f"{d['max_m']:.2g} ({d['min_dz_m']:+.2g})" if d else "—"
            if s.get("finite") is False:
                drift = "**NaN state**"
            lines.append(
                f"| {scene} | {TITLES.get(eng, eng)} | {ran(s, e)} | {fmt(sps, ',.1f')} | {ratio} | "
                f"{fmt(contacts, 'd')} | {lcp_cell(s)} | {drift} | {fmt(s.get('max_penetration_m'), '.2g')} "
                f"({fmt(s.get('final_penetration_m'), '.2g')}) | "
                f"{fmt(s.get('peak_rss_mb'), ',.0f')} |"
            )
    lines += ["", "How to read it:", ""] + [f"- {n}" for n in NOTES] + [""]
    built = {e["built_by"] for e in res["scenes"].values()}
    lines += ["Scenes built by: " + "; ".join(sorted(built)) + ".", ""]
    return lines


# --------------------------------------------------------------------------- the pours

POURS_HEADING = "### Pours: contact that changes every step"


def _runs(res: dict[str, Any]) -> list[dict[str, Any]]:
    """The runs that wrote the data file (the first, then each ``--merge``), each with the scenes it holds now."""
    runs = [{k: v for k, v in res.items() if k != "scenes"}] + list(res.get("reruns", []))
    held = {key: e.get("command") for key, e in res["scenes"].items()}
    # A scene is held by the last run of its command (a rerun replaces an earlier run's figures).
    last = {r.get("command"): i for i, r in enumerate(runs)}
    for i, r in enumerate(runs):
        r["held"] = [key for key, cmd in held.items() if cmd == r.get("command") and last[cmd] == i]
    return [r for r in runs if r["held"]]


def _backstop(lcp: dict[str, Any] | None) -> str:
    if not lcp:
        return ""
    if not lcp.get("backstop_recorded"):
        return "not recorded"
    f = lcp.get("backstop_fraction")
    if f is None:
        return "—"
    st = lcp.get("stages")
    return f"{f:.3g}" + (f" ({st['dense_lemke']:,} of {sum(st.values()):,} islands)" if st else "")


def _stages(lcp: dict[str, Any] | None) -> str:
    if not lcp or not lcp.get("stages_recorded"):
        return "not recorded" if lcp else ""
    st = lcp["stages"]
    out = " / ".join(f"{st[k]:,}" for k in ("previous_basis", "guessed_basis", "structured_lemke", "dense_lemke"))
    return out + (f" (other stages: {st['other']:,})" if st.get("other") else "")


def _ran(s: dict[str, Any], e: dict[str, Any], budget: float | None) -> str:
    b = f" in {budget:g} s" if budget else ""
    if s["outcome"] == "ok":
        reps = len(s.get("rates", []))
        return f"all {s['steps']:,}" + (f" × {reps} reps" if reps > 1 else "")
    if s["outcome"] in ("timed_out", "killed"):
        how = " (killed mid-step)" if s["outcome"] == "killed" else ""
        return f"**{s['steps']:,} of {e['steps']:,}**{b}{how}"
    if s.get("steps"):
        return f"**{s['steps']:,} of {e['steps']:,}**, then {ran(s, e)}"
    return ran(s, e)


def render_pours(res: dict[str, Any]) -> list[str]:
    """The pours' subsection: one table of every engine × scene, then steps/s
    per window of steps (and lcpsim's pivots per window), from ``--benchmark pours``'s data file."""
    # The pours by size, then the heaps.
    order = sorted(res["scenes"], key=lambda k: (not k.startswith("pour"), int("".join(filter(str.isdigit, k)) or 0)))
    scenes = {k: res["scenes"][k] for k in order}
    lines = [
        POURS_HEADING,
        "",
        "Written by `many_bodies.py --benchmark pours --write-results` from `benchmarks/peers/pours.json.gz` "
        "(do not edit by hand; rerun). A pour: n unit cubes (1 kg, μ = 0.5) with uniformly random orientations "
        "released at rest from a loose column (g × g cells per layer, g = max(2, ⌈√(n/10)⌉), cells 1.8 m apart) "
        "inside four static walls, tumbling into one heap, 3 simulated seconds (3,000 steps of 1 ms): contacts "
        "appear, vanish and change every step. The heap of 200 cubes (`cube_heap`, a stepped pyramid started "
        "just above its resting places, with walls) is run beside them. Every engine starts from the state "
        "exported from the lcpsim world (walls included); each engine × scene in its own process, under its "
        "wall-clock budget (below); steps/s counts the stepping calls only; a run cut by its budget reports "
        "the steps it did and its rate over them (× MuJoCo in brackets: MuJoCo's time over the same first "
        "steps, since the early, free-falling steps are the cheap ones).",
        "",
    ]
    for i, r in enumerate(_runs(res), 1):
        v = r.get("versions", {})
        la = r.get("load_average_before", [float("nan")])[0], r.get("load_average_after", [float("nan")])[0]
        lines.append(
            f"- Run {i} ({', '.join(r['held'])}): lcpsim {v.get('lcpsim')} built from commit "
            f"{v.get('lcpsim_revision', '?')} (benchmark scripts at {r.get('bench_revision', '?')}); "
            f"{r.get('machine')}; MuJoCo {v.get('mujoco')}, PyBullet {v.get('pybullet')}, rapier3d-f64 "
            f"{v.get('rapier3d-f64')}, Python {v.get('python')}, numpy {v.get('numpy')}; "
            f"{r.get('date', 'date not recorded')}; 1-minute load average {la[0]:.1f} before, {la[1]:.1f} after. "
            f"Command: `{r.get('command')}`")
    built = sorted({e["built_by"] for e in scenes.values()})
    lines += ["", "Scenes built by: " + "; ".join(built) + "."]
    if any("built here" in b for b in built):
        lines.append("**Some scenes were built here, not by lcpsim's `cube_pour`: their figures are not those of "
                     "lcpsim's scene.**")
    lines += [
        "",
        "| scene | engine | budget (s) | steps done | steps/s | × MuJoCo | failed LCPs | backstop fraction "
        "| pivots per LCP step (median / mean) | contacts (max) | max penetration (m) (at the end) "
        "| peak RSS (MB) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for key, e in scenes.items():
        mj = e["engines"].get("mujoco", {})
        mjs = mj.get("steps_per_second")
        first = True
        for eng, s in e["engines"].items():
            walls = f" + {e['static_boxes']} walls" if e.get("static_boxes") else ""
            scene = f"{key}: {e['title']} ({e['bodies']} cubes{walls})" if first else ""
            first = False
            budget = (e.get("budget_s") or {}).get(eng)
            if s["outcome"] == "not_run":
                lines.append(f"| {scene} | {TITLES.get(eng, eng)} | {fmt(budget, 'g')} | not run: {s['error']} "
                             "| | | | | | | | |")
                continue
            sps = s.get("steps_per_second")
            ratio = f"{sps / mjs:.3g}×" if sps and mjs else "—"
            same = same_steps_ratio(s, mj)
            if s["outcome"] != "ok" and same:
                ratio += f" ({same:.3g}×)"
            lcp = s.get("lcp")
            if lcp:
                failed = f"{lcp['failed']:,} of {lcp['lcp_steps']:,}"
                piv = f"{fmt(lcp['pivots_median'], ',.4g')} / {fmt(lcp['pivots_mean'], ',.4g')}"
                if s.get("stats_at_step"):
                    failed += f" (to step {s['stats_at_step']:,})"
            else:
                failed = piv = ""
            contacts = (s.get("stats") or {}).get("max_contacts") if eng == "lcpsim" else None
            if contacts is None:
                sampled = s.get("contacts_sampled") or []
                contacts = max(sampled) if sampled else None
            lines.append(
                f"| {scene} | {TITLES.get(eng, eng)} | {fmt(budget, 'g')} | {_ran(s, e, None)} | "
                f"{fmt(sps, ',.1f')} | {ratio} | {failed} | {_backstop(lcp)} | {piv} | {fmt(contacts, ',d')} | "
                f"{fmt(s.get('max_penetration_m'), '.2g')} ({fmt(s.get('final_penetration_m'), '.2g')}) | "
                f"{fmt(s.get('peak_rss_mb'), ',.0f')} |")
    staged = [(key, e["engines"]["lcpsim"]["lcp"]) for key, e in scenes.items()
              if (e["engines"].get("lcpsim", {}).get("lcp") or {}).get("stages_recorded")]
    by_stage = ("" if not staged else " lcpsim's contact islands by the stage of the solve chain that answered "
                "them (previous basis / guessed basis / structured Lemke / dense Lemke): "
                + "; ".join(f"{key} {_stages(lcp)}" for key, lcp in staged) + ".")
    lines += [
        "",
        "- **failed LCPs**: lcpsim's steps whose contact LCP was not solved (of the steps with contacts). "
        "**backstop fraction**: the share of contact islands that reached the last stage of lcpsim's island "
        "solve chain, the dense Lemke (whose ladder ends in cold and exact runs), from "
        "`Trajectory.lcp_stats().stages` (\"not recorded\": the lcpsim built does not report the stages); "
        "lcpsim built before dd08433 answered every single-body island (one cube on the floor or against a "
        "wall) by that stage, later builds only those without a previous basis, so the fraction counts those "
        "too, not only coupled islands that every earlier stage missed. "
        "**pivots per LCP step**: every island's pivots (every attempt's) in one step, over the steps with contacts."
        + by_stage,
        "- Contacts: lcpsim the most in any step, the peers the most at a sample (every 250 steps). Penetration: "
        "the deepest box–box, box–wall or box–ground overlap over the samples (the same separating-axis code for "
        "every engine; at the last sample in brackets). Engines as in the table above (MuJoCo soft contacts with "
        "its defaults; PyBullet and Rapier without sleeping).",
        "",
    ]
    lines += pour_windows(res)
    return lines


def _rate(x: float) -> str:
    return f"{x:,.0f}" if x >= 100 else f"{x:.3g}"


def pour_windows(res: dict[str, Any]) -> list[str]:
    """Steps/s over each window of steps, per engine × scene; lcpsim's mean pivots
    per LCP step and most contacts per window below its rate."""
    rows = []
    width = 0
    order = sorted(res["scenes"], key=lambda k: (not k.startswith("pour"), int("".join(filter(str.isdigit, k)) or 0)))
    for key in order:
        e = res["scenes"][key]
        w = e.get("window") or 0
        if not w:
            continue
        # lcpsim's and MuJoCo's rows (the other engines' windows are in the data file: --windows).
        for eng, s in e["engines"].items():
            wins = s.get("windows") or []
            if not wins or eng not in ("lcpsim", "mujoco"):
                continue
            width = max(width, -(-e["steps"] // w))
            cells = [("—" if x["steps_per_second"] is None else _rate(x["steps_per_second"]))
                     + ("" if x["to"] - x["from"] == w else f" ({x['to'] - x['from']} steps)") for x in wins]
            rows.append((key, w, TITLES.get(eng, eng) + " steps/s", cells))
            lcp = s.get("lcp")
            if lcp and lcp.get("windows"):
                if lcp.get("stages_recorded"):
                    rows.append((key, w, "lcpsim pivots per LCP step (mean) · backstop fraction",
                                 [f"{fmt(x['pivots_mean'], ',.0f')} · {fmt(x.get('backstop_fraction'), '.2g')}"
                                  for x in lcp["windows"]]))
                else:
                    rows.append((key, w, "lcpsim pivots per LCP step (mean)",
                                 [fmt(x["pivots_mean"], ",.0f") for x in lcp["windows"]]))
    if not rows:
        return []
    ws = {r[1] for r in rows}
    w = ws.pop() if len(ws) == 1 else None
    head = [f"{i * w}–{(i + 1) * w}" for i in range(width)] if w else [f"window {i + 1}" for i in range(width)]
    lines = [
        "Where the time goes: lcpsim's and MuJoCo's steps/s over each window of 250 steps (exact: the workers' "
        "stepping calls end on the windows' bounds; a run cut short ends with a shorter window), lcpsim's pivots "
        "per LCP step and backstop fraction per window (every engine's windows: `many_bodies.py --benchmark pours "
        "--render --windows 0,250,500,…`).",
        "",
        "| scene | | " + " | ".join(head) + " |",
        "|---|---|" + "---|" * width,
    ]
    last = None
    for key, _, what, cells in rows:
        lines.append(f"| {key if key != last else ''} | {what} | " + " | ".join(cells + [""] * (width - len(cells)))
                     + " |")
        last = key
    return lines + [""]


# --------------------------------------------------------------------------- the other two benchmarks

#: RESULTS.md's "Many bodies" section runs from this heading to the next "## " heading or the end.
MARKER = "## Many bodies"


def render_broadphase(bp: dict[str, Any]) -> list[str]:
    """The table of ``rapier-bench broadphase --json``."""
    names = {"sap": "sweep-and-prune (reference)", "bvh_rebuild": "parry BVH, rebuilt",
             "bvh_refit": "parry BVH, updated + refitted", "sim_sap": "lcpsim's broad phase"}
    methods = [m for m in names if any(m in s["methods"] for s in bp["sizes"])]
    lines = [
        "### Broad phase: parry's BVH against sweep-and-prune",
        "",
        f"Random boxes (half extents 0.25–0.75 m, about one per 8 m³, each moving at up to 1 m/s, "
        f"steps of {bp['dt']:.4g} s), parry3d-f64 {bp['parry3d_f64']}; every method finds the same pairs "
        "(checked every step, and against brute force up to 3,000 boxes). Median milliseconds per update "
        f"(new bounds in, every overlapping pair out) over {bp['sizes'][0]['steps']} steps. Command: "
        "`benchmarks/rapier_bench/target/release/rapier-bench broadphase --json > benchmarks/broadphase.json` "
        "(without `--json`: this table). The plain sweep along x tests every pair overlapping in x, about "
        "n²·(2 × mean width / side) of them, so it falls behind the tree as boxes fill a cube (sweeping the axis of widest spread "
        "helps only where the boxes spread unevenly).",
        "",
        "| boxes | pairs per step | " + " | ".join(f"{names[m]} (ms)" for m in methods) + " |",
        "|---|---|" + "---|" * len(methods),
    ]
    for s in bp["sizes"]:
        pairs = s["methods"]["sap"]["pairs"]
        cells = " | ".join(f"{s['methods'][m]['ms_median']:.3f}" if m in s["methods"] else "—" for m in methods)
        lines.append(f"| {s['n']:,} | {min(pairs):,}–{max(pairs):,} | {cells} |")
    if bp.get("measured_at"):
        lines += ["", f"Measured at {bp['measured_at']}; data in `benchmarks/broadphase.json`."]
    return lines + [""]


def _subsections(text: str) -> tuple[str, list[tuple[str, str]]]:
    """``text`` as what precedes its first "### " heading and its (heading, block) pairs."""
    parts = ("\n" + text).split("\n### ")
    blocks = [("### " + p).rstrip("\n") for p in parts[1:]]
    return parts[0].strip("\n"), [(b.split("\n", 1)[0], b) for b in blocks]


def splice(md: str, section: list[str]) -> str:
    """``md`` with its "Many bodies" section (from :data:`MARKER` to the next top-level
    heading, such as fclib_siconos.py's, or the end) rewritten from ``section``: its
    text before the first subsection (unless ``section`` has none) and every subsection it has are replaced (a
    subsection by the one of the same heading, in place; new ones after the rest),
    and the subsections it does not have — earlier runs, written by hand — are kept."""
    head, _, rest = md.partition("\n" + MARKER)
    later = rest.split("\n## ", 1)
    keep = "\n## " + later[1].rstrip("\n") + "\n" if len(later) == 2 else ""
    old_top, old = _subsections(MARKER + later[0]) if rest else ("", [])
    top, new = _subsections("\n".join(section))
    fresh, had = dict(new), {h for h, _ in old}
    # A section of subsections only (the pours') keeps the text before them.
    blocks = [top or old_top] + [fresh.get(h, b) for h, b in old] + [b for h, b in new if h not in had]
    return head.rstrip("\n") + "\n\n" + "\n\n".join(blocks) + "\n" + keep


def tail(md: str) -> str:
    """The "Many bodies" section of ``md`` ("" if none), for writers of the rest of the file to keep."""
    parts = md.split("\n" + MARKER, 1)
    return "\n" + MARKER + parts[1] if len(parts) == 2 else ""
