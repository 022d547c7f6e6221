"""The source note's experiments on the command line::

    lcpsim failure-rate --scales none,1e-3,1e-4,1e-6 --solver classic
    lcpsim failure-rate --solvers classic,robust,pgs,newton_fb --corpus cubes,hard --scales none,1e-2,1e-3,1e-4,1e-6,1e-8
    lcpsim slope --angle-deg 45.0001 --mu 1 --scale 1e-3 --solver classic --seconds 1
    lcpsim critical-scale --angle-deg 45.2 --mu 1 --solver classic
    lcpsim invariance --digits 20
    lcpsim patterns --scale 1e-3
    lcpsim push --force 9.79 --mu 1
    lcpsim report --out report
    lcpsim sweep sweep.yaml

Every experiment command takes ``--json`` (print the result), ``--plot FILE``
(write a PNG), ``--solver`` (a preset — ``classic``, ``robust`` (default),
``pgs``, ``newton_fb`` — or ``method:key=value,…``) and ``--seed``. A scale is
a number, ``none`` (unscaled) or ``dt`` (the time step). Exit codes: 0 done,
1 a sweep case failed (or is missing), 2 invalid input (a sweep's whole config
is checked before any case runs).
"""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

from ..experiments.experiment import Experiment
from ..experiments.registry import REGISTRY
from .command import EXIT_NOT_SOLVED, EXIT_OK, Command, register_command

__all__: list[str] = []


def _emit(args: argparse.Namespace, result: dict[str, Any], exp: Experiment) -> int:
    from .._json import jsonable

    if getattr(args, "plot", None):
        exp.plot([result], args.plot)
    data = jsonable(result)
    if getattr(args, "out", None):
        with open(args.out, "w") as fh:
            json.dump(data, fh, indent=1)
    if args.json:
        print(json.dumps(data))
    else:
        print(exp.summary(result, args))
        if getattr(args, "plot", None):
            print(f"plot:      {args.plot}")
    return EXIT_OK


def _command(exp: Experiment) -> Command:
    """The subcommand ``lcpsim NAME`` of an experiment."""

    def run(args: argparse.Namespace) -> int:
        return _emit(args, exp.run(exp.config(args)), exp)

    return Command(exp.name, exp.help, exp.arguments, run)


# ---------------------------------------------------------------- report


def _cfg_report(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", default="report", metavar="DIR", help="output directory (default: report)")
    p.add_argument("--quick", action="store_true", help="small sizes (a smoke test, seconds instead of minutes)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")


def _run_report(args: argparse.Namespace) -> int:
    from ..experiments.report import make_report

    summary = make_report(args.out, seed=args.seed, quick=args.quick, log=sys.stderr)
    if args.json:
        print(json.dumps(summary))
    else:
        print(f"report: {summary['index_html']}")
        print(f"        {summary['report_md']}")
        print(f"wall time {summary['wall_time_s']:.1f} s")
    return EXIT_OK


# ---------------------------------------------------------------- sweep


def _cfg_sweep(p: argparse.ArgumentParser) -> None:
    p.add_argument("config", help="sweep config (YAML or JSON): experiment, base, grid, output")
    p.add_argument("--output", "-o", default=None, metavar="FILE", help="results file (.h5 or .parquet); overrides the config's")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS", help="an existing Dask scheduler (default: a local cluster)")
    p.add_argument("--workers", type=int, default=None, help="local cluster workers (default: cores)")
    p.add_argument("--no-progress", action="store_true", help="no progress line")
    p.add_argument("--json", action="store_true", help="print every result as JSON lines at the end")


def _run_sweep(args: argparse.Namespace) -> int:
    from ..experiments import sweep

    cfg = sweep.load_config(args.config)
    out = sweep.run_sweep(
        cfg, output=args.output, scheduler=args.scheduler, workers=args.workers,
        progress=None if args.no_progress else sys.stderr,
    )
    if args.json:
        for rec in sweep.load_results(out["output"]):
            print(json.dumps(rec))
    else:
        print(sweep.summary_text(out))
    # A case that raised, or one still missing, is a failure of the sweep.
    return EXIT_OK if out["failed"] == 0 and out["complete"] else EXIT_NOT_SOLVED


for _exp in REGISTRY.values():
    register_command(_command(_exp))
register_command(Command("report", "run every experiment and write an HTML + Markdown report", _cfg_report, _run_report))
register_command(Command("sweep", "run a grid of experiment cases on Dask, resumable", _cfg_sweep, _run_sweep))
