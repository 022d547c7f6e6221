#!/usr/bin/env python3
"""Many-body scenes: lcpsim beside MuJoCo, PyBullet and Rapier.

Scenes (``many_scenes.py``): a 10-box stack; 3×3×3 and 10×10×10 towers
(lcpsim's ``box_pile``: towers on a grid 1.5 m apart); heaps of 200 and 1,000
unit cubes dropped with random orientations into 4 static walls. 1 kg unit
cubes, μ = 0.5, g = 9.81, dt = 1e-3, on a ground plane; every engine starts
from the same state: lcpsim and MuJoCo read the scene's MJCF file
(``benchmarks/scenes/<scene>.xml``; ``--write-scenes`` writes them from
``lcpsim.scenes``), PyBullet and Rapier are built from the state exported from
lcpsim's world read from it.

Each engine × scene runs in its own process (``many_engines.py``; Rapier:
``benchmarks/rapier_bench``), under an address-space cap (``--mem-cap-gb``)
and a wall-clock budget (``--budget`` seconds per engine × scene, for all its
repetitions; a process still stepping ``--grace`` seconds after it is killed).
Reported: steps/s (stepping calls only, median over repetitions), contacts,
lcpsim's LCP count, failures and largest LCP, the top boxes' drift, the
deepest penetration over the sampled states (the same separating-axis code for
every engine), the worker's peak RSS (``wait4``), and the ratio to MuJoCo.

    bash benchmarks/peers/setup.sh      # venv with mujoco, pybullet, lcpsim; builds rapier-bench
    benchmarks/peers/.venv/bin/python benchmarks/peers/many_bodies.py [--scenes stack10,towers3] [--engines ...]

Writes ``benchmarks/peers/many_bodies.json.gz`` (with every sampled state) and
prints the markdown section for ``benchmarks/RESULTS.md``.

Pours (``--benchmark pours``): ``lcpsim.scenes.cube_pour`` of 45, 90, 200 and
1,000 cubes (3 s = 3,000 steps), contact that changes every step, beside the
heap of 200 cubes (``pour45,pour90,pour200,heap200`` by default). Its own data
file ``benchmarks/peers/pours.json.gz`` (``--merge`` adds scenes run later) and
its own subsection of RESULTS.md; per engine × scene also steps/s over each
window of 250 steps, and lcpsim's failed LCPs, pivots per step and the share
of islands that reached the dense Lemke (``Trajectory.lcp_stats().stages``,
where lcpsim reports it). Per-engine budgets: ``--engine-budget lcpsim=600``::

    benchmarks/peers/.venv/bin/python benchmarks/peers/many_bodies.py --benchmark pours \
        --scenes pour45,pour90 --budget 300 --engine-budget lcpsim=600 --write-results
"""

from __future__ import annotations

import argparse
import gzip
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path.insert(0, str(HERE))

sys.path.insert(0, str(HERE.parent))

import many_bodies_report  # noqa: E402
from many_scenes import (SCENE_BY_KEY, SCENES, describe, drift, load, mjcf_path, penetration,  # noqa: E402
                         scene_mjcf)

ENGINES = ["lcpsim", "mujoco", "pybullet", "rapier"]
RAPIER_BIN = ROOT / "benchmarks" / "rapier_bench" / "target" / "release" / "rapier-bench"
SAMPLES = 10  # pose samples per run (plus the start)


def worker_command(engine: str, scene: str, desc_path: str, steps: int, budget: float, reps: int,
                   every: int = 0) -> list[str]:
    every = every or max(1, steps // SAMPLES)
    if engine == "rapier":
        return [str(RAPIER_BIN), "scene", desc_path, "--steps", str(steps), "--budget", str(budget),
                "--sample-every", str(every), "--reps", str(reps)]
    return [sys.executable, str(HERE / "many_engines.py"), engine, scene, desc_path, str(steps), str(budget),
            str(every), str(reps)]


def run_worker(cmd: list[str], deadline: float, mem_cap: int) -> dict[str, Any]:
    """Runs one worker; returns its events, exit status, peak RSS and whether it was killed."""

    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (mem_cap, mem_cap))

    err = tempfile.TemporaryFile()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=err, preexec_fn=limit, text=True,
                            env={**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [
                                str(HERE), os.environ.get("PYTHONPATH", "")]))})
    events: list[dict[str, Any]] = []

    def read() -> None:
        assert proc.stdout is not None
        for line in proc.stdout:
            try:
                events.append(json.loads(line))
            except json.JSONDecodeError:
                pass

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    t0 = time.perf_counter()
    killed = False
    # Reaped by wait4 (not Popen.poll) for the child's peak RSS (ru_maxrss, KiB on Linux).
    while True:
        pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
        if pid:
            break
        if time.perf_counter() - t0 > deadline:
            proc.kill()
            killed = True
            _, status, usage = os.wait4(proc.pid, 0)
            break
        time.sleep(0.1)
    proc.returncode = os.waitstatus_to_exitcode(status)
    peak = usage.ru_maxrss / 1024
    reader.join(timeout=5)
    err.seek(0)
    stderr = err.read().decode(errors="replace")[-2000:]
    return {"events": events, "returncode": proc.returncode, "killed": killed, "peak_rss_mb": peak,
            "stderr": stderr, "wall_s": time.perf_counter() - t0}


def crash_reason(stderr: str, returncode: int) -> str:
    """The telling line of a crashed worker's stderr (Rust's allocation failure, a panic, an exception)."""
    lines = [ln for ln in stderr.splitlines() if ln.strip() and not ln.startswith((" ", "\t", "note:", "stack backtrace"))]
    for ln in lines:
        if "memory allocation of" in ln or "panicked" in ln:
            return ln.strip()
    return lines[-1].strip() if lines else f"exit status {returncode}"


def summarize(desc: dict[str, Any], run: dict[str, Any], steps: int) -> dict[str, Any]:
    """One engine × scene: rates, counts, drift and penetration from the worker's events."""
    ev = run["events"]
    reps = [e for e in ev if e["event"] == "rep"]
    samples = [e for e in ev if e["event"] == "sample"]
    progress = [e for e in ev if e["event"] == "progress" and e.get("rep", 0) == 0]
    ready = next((e for e in ev if e["event"] == "ready"), {})
    out: dict[str, Any] = {"steps_planned": steps, "peak_rss_mb": run["peak_rss_mb"],
                           "rss_after_build_mb": ready.get("rss_mb"), "wall_s": run["wall_s"],
                           "returncode": run["returncode"]}
    done = reps[0]["steps"] if reps else (progress[-1]["steps"] if progress else 0)
    secs = reps[0]["seconds"] if reps else (progress[-1]["seconds"] if progress else 0.0)
    out["steps"] = done
    out["progress"] = [[e["steps"], e["seconds"]] for e in progress]
    out["windows"] = window_rates(out["progress"], desc.get("window") or 0)
    out["rates"] = [r["steps"] / r["seconds"] for r in reps if r["seconds"] > 0]
    if not out["rates"] and secs > 0:
        out["rates"] = [done / secs]
    out["steps_per_second"] = float(np.median(out["rates"])) if out["rates"] else None
    if reps:
        out["stats"] = reps[0].get("stats", {})
    else:  # killed in a stepping call: lcpsim's counts at its last sample
        partial = [e for e in ev if e["event"] == "stats" and e.get("rep", 0) == 0]
        if partial:
            out["stats"] = partial[-1]["stats"]
            out["stats_at_step"] = partial[-1]["steps"]
    if "step_pivots" in out.get("stats", {}):
        out["lcp"] = lcp_summary(out["stats"], desc.get("window") or 0)
    if run["killed"]:
        out["outcome"] = "killed"
    elif not reps:
        out["outcome"] = "crashed"
    elif reps[0]["timed_out"]:
        out["outcome"] = "timed_out"
    else:
        out["outcome"] = "ok"
    if out["outcome"] == "crashed":
        out["error"] = crash_reason(run["stderr"], run["returncode"])
    if samples and done > 0:
        pos = [np.array(s["pos"], dtype=float) for s in samples]
        quat = [np.array(s["quat"], dtype=float) for s in samples]
        finite = all(np.isfinite(p).all() and np.isfinite(q).all() for p, q in zip(pos, quat))
        out["finite"] = finite
        out["sampled_steps"] = [s["step"] for s in samples]
        out["contacts_sampled"] = [s["contacts"] for s in samples]
        if finite:
            depths = [penetration(desc, p, q) for p, q in zip(pos, quat)]
            out["max_penetration_m"], out["final_penetration_m"] = max(depths), depths[-1]
            out["drift"] = drift(desc, pos[0], pos[-1])
        out["final_state"] = {"step": samples[-1]["step"], "pos": samples[-1]["pos"], "quat": samples[-1]["quat"]}
    return out


def window_rates(progress: list[list[float]], window: int) -> list[dict[str, Any]]:
    """Steps/s over each ``window`` steps (the last window as far as the run got),
    from the progress points; exact where the points fall on the windows' ends,
    which the workers' stepping calls make sure of when ``window`` is the sample interval."""
    if not window or not progress:
        return []
    steps, secs = [0] + [p[0] for p in progress], [0.0] + [p[1] for p in progress]
    out = []
    for a in range(0, int(steps[-1]), window):
        b = min(a + window, int(steps[-1]))
        t = float(np.interp(b, steps, secs) - np.interp(a, steps, secs))
        out.append({"from": a, "to": b, "seconds": t, "steps_per_second": (b - a) / t if t > 0 else None,
                    "exact": a in steps and b in steps})
    return out


STAGES = ("previous_basis", "guessed_basis", "structured_lemke", "dense_lemke")


def lcp_summary(st: dict[str, Any], window: int) -> dict[str, Any]:
    """lcpsim's per-step counts summed up: failed LCPs, pivots per LCP step
    (median, mean), the solve chain's stages and backstop fraction (None where
    lcpsim does not report them), and the same per ``window`` steps."""
    piv = np.asarray(st["step_pivots"], dtype=float)
    con = np.asarray(st["step_contacts"], dtype=int)
    fail = np.asarray(st["step_failed"], dtype=int)
    has = con > 0
    calls = np.asarray(st.get("stage_calls") or [], dtype=float).reshape(-1, 3 + len(STAGES))

    def part(a: int, b: int) -> dict[str, Any]:
        p, h = piv[a:b], has[a:b]
        d: dict[str, Any] = {"from": a, "to": b, "lcp_steps": int(h.sum()), "failed": int(fail[a:b].sum()),
                             "pivots_median": float(np.median(p[h])) if h.any() else None,
                             "pivots_mean": float(p[h].mean()) if h.any() else None,
                             "pivots_max": int(p.max(initial=0)), "contacts_max": int(con[a:b].max(initial=0))}
        if st.get("stages_recorded"):
            sel = calls[(calls[:, 0] >= a) & (calls[:, 0] < b)] if len(calls) else calls
            counts = sel[:, 2:].sum(axis=0) if len(sel) else np.zeros(len(STAGES) + 1)
            d["stages"] = {name: int(c) for name, c in zip(STAGES, counts)}
            if counts[-1]:
                d["stages"]["other"] = int(counts[-1])
            total = int(counts.sum())
            dense = counts[STAGES.index("dense_lemke")]
            d["backstop_fraction"] = float(dense / total) if total else None
        return d

    out = part(0, len(piv))
    if not st.get("stages_recorded") and st.get("backstop_recorded"):
        n = st.get("stage_islands", 0)
        out["backstop_fraction"] = st["backstop_islands"] / n if n else None
    out["stages_recorded"] = bool(st.get("stages_recorded"))
    out["backstop_recorded"] = bool(st.get("backstop_recorded") or st.get("stages_recorded"))
    if st.get("other_stages"):
        out["other_stages"] = st["other_stages"]
    if window:
        out["windows"] = [part(a, min(a + window, len(piv))) for a in range(0, len(piv), window)]
    return out


def merge_rounds(rs: list[dict[str, Any]]) -> dict[str, Any]:
    """One engine × scene over its rounds: the first round's summary (the
    trajectory is the same in every round), with the rates of every round and
    their median; the outcome and peak RSS of the worst round."""
    out = dict(rs[0])
    if len(rs) == 1:
        return out
    out["rates"] = [x for r in rs for x in r.get("rates", [])]
    out["round_rates"] = [r.get("steps_per_second") for r in rs]
    out["steps_per_second"] = float(np.median(out["rates"])) if out["rates"] else None
    out["peak_rss_mb"] = max(r["peak_rss_mb"] for r in rs)
    bad = next((r for r in rs if r["outcome"] != "ok"), None)
    if bad is not None:
        out["outcome"], out["steps"] = bad["outcome"], bad["steps"]
        if "error" in bad:
            out["error"] = bad["error"]
    return out


def locked_version(crate: str) -> str:
    """The version of ``crate`` in benchmarks/rapier_bench/Cargo.lock."""
    lock = ROOT / "benchmarks" / "rapier_bench" / "Cargo.lock"
    blocks = lock.read_text().split("[[package]]") if lock.exists() else []
    for b in blocks:
        if f'name = "{crate}"' in b:
            return b.split('version = "', 1)[1].split('"', 1)[0]
    return "?"


def versions() -> dict[str, str]:
    from importlib.metadata import PackageNotFoundError, version

    v: dict[str, str] = {"python": platform.python_version()}
    for dist in ("lcpsim", "mujoco", "pybullet", "numpy"):
        try:
            v[dist] = version(dist)
        except PackageNotFoundError:
            v[dist] = "not installed"
    rev = HERE / ".venv" / "lcpsim-revision.txt"
    if rev.exists():
        v["lcpsim_revision"] = rev.read_text().strip()
    try:
        v["lcpsim_file"] = __import__("lcpsim").__file__
    except ImportError:
        pass
    v["rapier3d-f64"] = locked_version("rapier3d-f64")
    v["parry3d-f64"] = locked_version("parry3d-f64")
    return v


def bench_revision() -> str:
    """The checkout's commit, "+changes" when benchmarks/peers has uncommitted edits (the scripts that ran)."""
    git = ["git", "-C", str(ROOT)]
    try:
        rev = subprocess.run([*git, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run([*git, "status", "--porcelain", "--untracked-files=no", "--", "benchmarks/peers"],
                               capture_output=True, text=True).stdout.strip()
    except OSError:
        return "?"
    return rev + ("+changes" if dirty else "")


def machine() -> str:
    from machine import machine as peers_machine

    m = peers_machine()
    return f"{m['cpu']}, {m['cores']} cores, {m['memory']}, {m['os']}"


def run_all(scene_keys: list[str], engines: list[str], budget: float, grace: float, mem_cap_gb: float,
            progress: Any = print, engine_budgets: dict[str, float] | None = None,
            command: str = "") -> dict[str, Any]:
    """Every engine on every scene (see the module's docstring); ``engine_budgets``
    overrides ``budget`` for the engines it names."""
    engine_budgets = engine_budgets or {}
    res: dict[str, Any] = {"config": {"dt": 1e-3, "mu": 0.5, "g": 9.81, "budget_s": budget, "grace_s": grace,
                                      "mem_cap_gb": mem_cap_gb, "samples": SAMPLES},
                           "machine": machine(), "versions": versions(), "scenes": {},
                           "load_average_before": os.getloadavg(), "bench_revision": bench_revision(),
                           "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}
    with tempfile.TemporaryDirectory() as tmp:
        for key in scene_keys:
            spec = SCENE_BY_KEY[key]
            world, how = load(key)
            desc = describe(world, how)
            desc["mjcf"] = str(mjcf_path(key))
            desc["window"] = spec.sample_every  # 0: none (windows of a tenth of the run are not reported)
            path = os.path.join(tmp, f"{key}.json")
            with open(path, "w") as f:
                json.dump(desc, f)
            steps = int(round(spec.seconds / desc["dt"]))
            n_dyn = sum(not b["static"] for b in desc["boxes"])
            entry: dict[str, Any] = {"title": spec.title, "built_by": how, "bodies": n_dyn,
                                     "static_boxes": len(desc["boxes"]) - n_dyn, "seconds": spec.seconds,
                                     "steps": steps, "reps": spec.reps, "initial_state": desc, "engines": {}}
            entry["rounds"] = spec.rounds
            entry["budget_s"] = {eng: engine_budgets.get(eng, budget) for eng in engines}
            entry["window"] = spec.sample_every
            entry["command"] = command
            entry["benchmark"] = spec.benchmark
            # Rounds run engine after engine, so that a change of the shared
            # machine's speed during the run falls on every engine alike.
            runs: dict[str, list[dict[str, Any]]] = {eng: [] for eng in engines}
            for r in range(spec.rounds):
                for eng in engines:
                    if eng == "rapier" and not RAPIER_BIN.exists():
                        entry["engines"][eng] = {"outcome": "not_run", "error": f"{RAPIER_BIN} not built"}
                        continue
                    b = engine_budgets.get(eng, budget)
                    cmd = worker_command(eng, key, path, steps, b, spec.reps, spec.sample_every)
                    run = run_worker(cmd, b + grace, int(mem_cap_gb * (1 << 30)))
                    s = summarize(desc, run, steps)
                    runs[eng].append(s)
                    tag = f" (round {r + 1} of {spec.rounds})" if spec.rounds > 1 else ""
                    progress(f"  {key} {eng}{tag}: {describe_outcome(s)}")
            for eng, rs in runs.items():
                if rs:
                    entry["engines"][eng] = merge_rounds(rs)
            res["scenes"][key] = entry
    res["load_average_after"] = os.getloadavg()
    return res


def describe_outcome(s: dict[str, Any]) -> str:
    sps = s.get("steps_per_second")
    rate = f"{sps:,.1f} steps/s" if sps else "—"
    if s["outcome"] == "ok":
        return f"{s['steps']} steps at {rate}"
    if s["outcome"] in ("timed_out", "killed"):
        extra = " (a stepping call still running was killed)" if s["outcome"] == "killed" else ""
        return f"timed out after {s['steps']} of {s['steps_planned']} steps at {rate}{extra}"
    return f"{s['outcome']}: {s.get('error', '')}"


RESULTS_MD = ROOT / "benchmarks" / "RESULTS.md"
POURS_OUT = HERE / "pours.json.gz"
POUR_DEFAULT = ["pour45", "pour90", "pour200", "heap200"]
SCALING_JSON = ROOT / "benchmarks" / "lcp_scaling.json"
BROADPHASE_JSON = ROOT / "benchmarks" / "broadphase.json"


def section(res: dict[str, Any]) -> list[str]:
    """The whole "Many bodies" section: the peers' table, then lcp_scaling.py's and the
    broad-phase comparison's tables when their JSON files exist. For a run of the
    pours (``--benchmark pours``) only its subsection (the rest of the section is kept
    by :func:`many_bodies_report.splice`)."""
    import lcp_scaling

    if res.get("benchmark") == "pours":
        return many_bodies_report.render_pours(res)
    lines = many_bodies_report.render(res)
    if SCALING_JSON.exists():
        lines += lcp_scaling.render(json.loads(SCALING_JSON.read_text()))
    if BROADPHASE_JSON.exists():
        lines += many_bodies_report.render_broadphase(json.loads(BROADPHASE_JSON.read_text()))
    return lines


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--benchmark", choices=["many_bodies", "pours"], default="many_bodies",
                    help="which table: the many-body scenes (default) or the pours (its own data file "
                         f"{POURS_OUT.relative_to(ROOT)} and its own subsection of RESULTS.md)")
    ap.add_argument("--scenes", default=None,
                    help="comma-separated; default: every scene of the --benchmark (pours: "
                         f"{','.join(POUR_DEFAULT)})")
    ap.add_argument("--engines", default=",".join(ENGINES))
    ap.add_argument("--budget", type=float, default=60.0, help="wall-clock seconds per engine × scene")
    ap.add_argument("--engine-budget", action="append", default=[], metavar="ENGINE=SECONDS",
                    help="another budget for one engine (repeatable), e.g. lcpsim=600")
    ap.add_argument("--grace", type=float, default=30.0, help="seconds past the budget before a kill")
    ap.add_argument("--mem-cap-gb", type=float, default=4.0, help="address-space cap of each worker")
    ap.add_argument("--out", default=None, help="data file (default: many_bodies.json.gz, or pours.json.gz)")
    ap.add_argument("--render", action="store_true", help="don't run: render the saved --out file")
    ap.add_argument("--windows", default=None,
                    help="with --render: each engine's seconds between these steps (comma-separated)")
    ap.add_argument("--merge", action="store_true", help="replace only the scenes run in the saved --out file")
    ap.add_argument("--write-scenes", action="store_true",
                    help="don't run: write every scene's MJCF file from lcpsim.scenes into benchmarks/scenes/")
    ap.add_argument("--write-results", action="store_true",
                    help=f"rewrite the section '{many_bodies_report.MARKER}' of {RESULTS_MD.relative_to(ROOT)} "
                         "(the subsections this run does not write are kept)")
    args = ap.parse_args()
    pours = args.benchmark == "pours"
    if args.out is None:
        args.out = str(POURS_OUT if pours else HERE / "many_bodies.json.gz")
    if args.scenes is None:
        args.scenes = ",".join(POUR_DEFAULT if pours else [s.key for s in SCENES if s.benchmark == "many_bodies"])
    engine_budgets = {k: float(v) for k, v in (x.split("=", 1) for x in args.engine_budget)}
    if args.write_scenes:
        for spec in SCENES:
            path = mjcf_path(spec.key)
            path.write_text(scene_mjcf(describe(*spec.build()), spec.key))
            print(f"wrote {path.relative_to(ROOT)}")
        return 0
    if args.render:
        with gzip.open(args.out, "rt") as f:
            res = json.load(f)
    else:
        command = " ".join(["benchmarks/peers/.venv/bin/python", "benchmarks/peers/many_bodies.py", *sys.argv[1:]])
        res = run_all(args.scenes.split(","), args.engines.split(","), args.budget, args.grace, args.mem_cap_gb,
                      engine_budgets=engine_budgets, command=command)
        res["command"] = command
        res["benchmark"] = args.benchmark
        res["engine_budgets"] = engine_budgets
        if args.merge and os.path.exists(args.out):
            with gzip.open(args.out, "rt") as f:
                old = json.load(f)
            old["scenes"].update(res["scenes"])
            old["reruns"] = old.get("reruns", []) + [{k: res[k] for k in res if k != "scenes"}
                                                      | {"scenes": list(res["scenes"])}]
            res = old
        with open(args.out, "wb") as raw, gzip.GzipFile(fileobj=raw, mode="wb", mtime=0) as gz:
            gz.write(json.dumps(res).encode())
    if args.windows:
        print("\n".join(many_bodies_report.windows(res, [int(x) for x in args.windows.split(",")])))
        return 0
    lines = section(res)
    print("\n".join(lines))
    if args.write_results:
        RESULTS_MD.write_text(many_bodies_report.splice(RESULTS_MD.read_text(), lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
