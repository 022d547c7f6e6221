#!/usr/bin/env python3
"""lcpsim beside Siconos and Drake on the same LCPs, in one run.

Run it in the peers' venv (``bash benchmarks/peers/setup.sh`` makes it)::

    benchmarks/peers/.venv/bin/python benchmarks/peers/run.py

Solvers, each called once per problem from Python, one call per timed solve:

- lcpsim robust (``solve_lcp(M, q)``: lexicographic Lemke, the default) and
  lcpsim classic (``pivoting="classic"``: the source note's absolute tolerances);
- Siconos 4.4 (Debian ``python3-siconos``) through ``siconos.numerics``:
  ``lcp_lexicolemke``, ``lcp_pivot``, ``lcp_newton_FB``, default options
  (tolerance 1e-6 on the problem as given);
- Drake (PyPI ``drake``): ``MobyLcpSolver`` and ``UnrevisedLemkeSolver``
  through a ``MathematicalProgram`` with ``AddLinearComplementarityConstraint``
  (Moby's ``Solve`` runs ``SolveLcpLemkeRegularized``; Drake binds no other
  Moby entry point in Python).

What is inside the timer: lcpsim's call takes numpy ``M, q`` and returns its
result object (conversion included). For the peers the problem object is built
outside the timer (``sn.LCP(M, q)``, ``SolverOptions``, output arrays; Drake's
``MathematicalProgram`` with its constraint) and only the solve call — plus
Drake's ``GetSolution`` — is timed, which favours the peers. Every solver is
handed fresh copies of ``M`` and ``q`` made just before (so the input is in
cache, as after a simulator's assembly, for lcpsim as much as for a peer whose
problem object was just built).

Timing modes, both from ``time.perf_counter`` around each call:

- *interleaved* (the headline): ``--passes`` passes over a problem set; in a
  pass every problem is solved once by every solver in turn (order rotated),
  so each call finds caches and branch predictors warmed by other code, as a
  simulator's solve would, and load changes hit all solvers alike. Per
  problem the median over passes.
- *back-to-back*: ``--repeats`` consecutive calls of one solver on one problem
  (warm caches), median per problem. Skipped for slow sets.

The ratio of a peer to lcpsim robust is the median over problems of the
per-problem time ratio (paired), so problems of different sizes weigh alike.

Failures: by the solver's own word (Siconos ``info != 0``, Drake
``is_success()`` false, lcpsim ``status != "solved"``) and by an independent
check of the returned ``z``: the natural residual ``‖min(z, Mz + q)‖∞`` above
``--tol`` (1e-6), computed both in the units the solver was given and in
physical units — for a cone-scaled contact LCP ``z_phys = D z`` (λ multiplied
by s) on the unscaled problem ``(M₁, q₁)``, impulses in N·s, velocities in m/s.
A solve counts as failed if the solver says so or its physical residual is
above the tolerance; "said solved, wrong" counts those the solver called solved.

Writes ``benchmarks/RESULTS.md`` (with the simulation throughput of
``sim_peers.py`` unless ``--no-sim``) and ``benchmarks/peers/results.json.gz`` (raw per-problem results: labels,
sizes, statuses, residuals, median times; gzip-compressed JSON).

The run is split by concept: ``problems.py`` (the problem sets),
``solvers.py`` (lcpsim and the peers behind one call), ``measure.py``
(timing and summaries), ``report.py`` (RESULTS.md), ``machine.py`` (machine
and versions), ``common.py`` (paths and console); this file is the command
line (``--help``; ``--quick`` for a smoke run, ``--render`` to rewrite
RESULTS.md from the last results).
"""

from __future__ import annotations

import argparse
import datetime as _dt
import gzip
import json
import os
import shlex
import sys
import time
from typing import Any

# One BLAS thread (set before numpy loads OpenBLAS): the peers' LAPACK calls must
# not spin extra threads on a shared 2-core machine.
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

from common import HERE, RESULTS_JSON, RESULTS_MD, ROOT, peers_chatter_to, say  # noqa: E402
from machine import loadavg, machine, versions  # noqa: E402
from measure import measure, summarize  # noqa: E402
from problems import ProblemSet, contact_sets, hard_sets, cube_corpus_sets, spd_sets  # noqa: E402
from report import headline, table, write_report  # noqa: E402
from solvers import Solver, drake_solvers, lcpsim_solvers, siconos_solvers  # noqa: E402


def render_only() -> int:
    """RESULTS.md from the last run's results.json.gz (e.g. after a change of wording)."""
    with gzip.open(RESULTS_JSON, "rt") as f:
        results = json.load(f)
    solvers = [Solver(k, v["name"], v["family"], lambda M, q: None, v["call"])  # type: ignore[arg-type,return-value]
               for k, v in results["solvers"].items()]
    sim_md = None
    if results.get("simulation"):
        sys.path.insert(0, str(HERE))
        import sim_peers

        sim_md = sim_peers.render(results["simulation"])
    write_report(results, solvers, sim_md)
    say(f"rewrote {RESULTS_MD.relative_to(ROOT)} from {RESULTS_JSON.relative_to(ROOT)}")
    return 0


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--contact-per-size", type=int, default=300, help="contact LCPs per size and scale")
    ap.add_argument("--contact-scales", default="1,1e-2,1e-3,1e-4,1e-6,1e-8")
    ap.add_argument("--cubes-per-size", type=int, default=100, help="cube-corpus LCPs per size and scale")
    ap.add_argument("--cubes-scales", default="1,1e-2,1e-3,1e-4,1e-6,1e-8")
    ap.add_argument("--hard-count", type=int, default=70, help="hard contact LCPs per scale")
    ap.add_argument("--hard-scales", default="1,1e-3,1e-6")
    ap.add_argument("--spd", default="40:30,200:10,1000:3", help="size:count,… of random SPD LCPs")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--passes", type=int, default=3, help="interleaved passes")
    ap.add_argument("--repeats", type=int, default=5, help="back-to-back repeats per solver and problem")
    ap.add_argument("--slow", type=float, default=1.0, help="a call slower than this (s) is not repeated")
    ap.add_argument("--tol", type=float, default=1e-6)
    ap.add_argument("--only", default="", help="comma-separated set prefixes to run (contact,cubes,hard,spd)")
    ap.add_argument("--skip-solvers", default="", help="comma-separated solver keys to leave out")
    ap.add_argument("--no-sim", action="store_true", help="leave out the simulation throughput (sim_peers.py)")
    ap.add_argument("--quick", action="store_true", help="smoke run: few problems, one pass")
    ap.add_argument("--no-write", action="store_true", help="print only; do not write RESULTS.md / results.json.gz")
    ap.add_argument("--render", action="store_true", help="rewrite RESULTS.md from results.json.gz without running")
    return ap.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    if args.render:
        return render_only()
    if args.quick:
        args.contact_per_size, args.cubes_per_size, args.hard_count = 5, 5, 7
        args.spd, args.passes, args.repeats = "40:2,200:1", 1, 2
    floats = lambda s: [float(x) for x in s.split(",") if x]  # noqa: E731
    only = [x for x in args.only.split(",") if x]
    want = lambda name: not only or name in only  # noqa: E731

    started = time.perf_counter()
    load_before = loadavg()
    say(f"lcpsim peers benchmark — load {load_before}")
    solvers = lcpsim_solvers()
    notes = []
    for make in (siconos_solvers, drake_solvers):
        got, msg = make()
        solvers += got
        if not got:
            notes.append(msg)
            say(msg)
    skip = set(x for x in args.skip_solvers.split(",") if x)
    solvers = [s for s in solvers if s.key not in skip]

    sets: list[ProblemSet] = []
    if want("contact"):
        sets += contact_sets(floats(args.contact_scales), args.contact_per_size, args.seed)
    if want("cubes"):
        got, msg = cube_corpus_sets(floats(args.cubes_scales), args.cubes_per_size, args.seed)
        sets += got
        notes.append(msg)
        say(msg)
    if want("hard"):
        sets += hard_sets(floats(args.hard_scales), args.hard_count, args.seed)
    if want("spd"):
        sets += spd_sets([(int(a), int(b)) for a, b in (x.split(":") for x in args.spd.split(",") if x)], args.seed)

    def med(ts: list[float]) -> float | None:
        return float(f"{np.median(ts):.4g}") if ts else None

    results: dict[str, Any] = {"sets": {}}
    with peers_chatter_to(HERE / "peers_output.log"):
        for ps in sets:
            say(f"{ps.key}: {len(ps.problems)} problems × {len(solvers)} solvers")
            recs = measure(ps, solvers, args.passes, args.repeats, args.slow)
            summary = summarize(ps, recs, args.tol, "lcpsim_robust")
            results["sets"][ps.key] = {
                "title": ps.title,
                "description": ps.description,
                "back_to_back": ps.back_to_back and args.repeats > 0,
                "summary": summary,
                "raw": {
                    "labels": [p.label for p in ps.problems],
                    "n": [p.n for p in ps.problems],
                    "solvers": {
                        k: {
                            "ok": [r.ok for r in rr],
                            "status": [r.status for r in rr],
                            "residual_given": [float(f"{r.res_given:.3g}") for r in rr],
                            "residual_physical": [float(f"{r.res_phys:.3g}") for r in rr],
                            "t_interleaved_median": [med(r.t_inter) for r in rr],
                            "t_interleaved_samples": [len(r.t_inter) for r in rr],
                            "t_back_to_back_median": [med(r.t_b2b) for r in rr],
                            "t_back_to_back_samples": [len(r.t_b2b) for r in rr],
                        }
                        for k, rr in recs.items()
                    },
                },
            }
            for line in table(summary, solvers, ps.back_to_back and args.repeats > 0):
                say(line)

    sim_md = None
    sim_results = None
    if not args.no_sim:
        sys.path.insert(0, str(HERE))
        import sim_peers

        say("simulation throughput (sim_peers.py)")
        with peers_chatter_to(HERE / "sim_output.log"):
            sim_results = sim_peers.run_all(progress=say)
        sim_md = sim_peers.render(sim_results)
        for line in sim_md:
            say(line)

    results.update(
        {
            "command": "benchmarks/peers/run.py" + ("" if argv is None and len(sys.argv) <= 1 else " " + shlex.join(
                argv if argv is not None else sys.argv[1:])),
            "date": _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "duration_s": time.perf_counter() - started,
            "load_before": load_before,
            "load_after": loadavg(),
            "machine": machine(),
            "versions": versions(),
            "notes": notes,
            "config": {
                **{k: v for k, v in vars(args).items()},
                "threads_env": "/".join(os.environ.get(k, "unset") for k in
                                        ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")),
            },
            "solvers": {s.key: {"name": s.name, "family": s.family, "call": s.note} for s in solvers},
            "simulation": sim_results,
        }
    )
    _, results["targets"] = headline(results, solvers, args.tol)
    if not args.no_write:
        with open(RESULTS_JSON, "wb") as raw, gzip.GzipFile(fileobj=raw, mode="wb", mtime=0) as gz:
            gz.write(json.dumps(results, separators=(",", ":"), default=str).encode())
        write_report(results, solvers, sim_md)
        say(f"wrote {RESULTS_MD.relative_to(ROOT)} and {RESULTS_JSON.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
