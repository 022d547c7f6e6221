"""What makes an experiment: one :class:`Experiment` per experiment module,
listed in :mod:`.registry`. The command line (``lcpsim NAME``), the sweep and
the report (``lcpsim report``) are built from these definitions, so adding an
experiment is one module plus one registry line.

Also here: the command-line options the experiments share (solver, seed,
output, cube-corpus size, simulated time) and the report's run context.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from dataclasses import dataclass, field
from typing import IO, Any, Callable, Mapping, Sequence

from ..scale import cone_scale_argument as scale_argument
from .document import Doc

__all__ = [
    "Experiment",
    "ReportPart",
    "ReportContext",
    "scale_pair_runs",
    "add_common_arguments",
    "add_corpus_arguments",
    "add_simulation_arguments",
    "corpus_config",
    "base_config",
    "header",
    "scale_argument",
]

Result = dict[str, Any]


@dataclass
class ReportContext:
    """Sizes and output of one ``lcpsim report`` run; ``step`` times and logs each stage."""

    out: str
    seed: int = 0
    quick: bool = False
    log: IO[str] | None = None
    started: float = field(default_factory=time.perf_counter)

    @property
    def corpus(self) -> dict[str, Any]:
        """Cube-corpus overrides: smaller with ``quick``."""
        return {"n_random": 2, "steps": 200} if self.quick else {}

    @property
    def seconds(self) -> float:
        """Simulated time of the slope and push runs: 2 s (0.097 m of slide at
        45.2°), long enough for the figures to show a held cube tipping (the
        slope outcome itself is decided at onset, whatever the time)."""
        return 0.5 if self.quick else 2.0

    @property
    def base(self) -> dict[str, Any]:
        """Config keys every cube-corpus experiment of the report shares."""
        return {"seed": self.seed, "corpus": self.corpus}

    def path(self, name: str) -> str:
        return os.path.join(self.out, name)

    def rel(self, path: str) -> str:
        return os.path.relpath(path, self.out)

    def step(self, name: str, fn: Callable[[], Any]) -> Any:
        t = time.perf_counter()
        if self.log is not None:
            self.log.write(f"report: {name} …")
            self.log.flush()
        r = fn()
        if self.log is not None:
            self.log.write(f" {time.perf_counter() - t:.1f} s\n")
            self.log.flush()
        return r


@dataclass(frozen=True)
class ReportPart:
    """An experiment's part of the report: ``run`` returns its entries of
    ``results.json``, ``figures`` writes its PNGs (name → path) from all results,
    ``section`` adds its section to the document."""

    run: Callable[[ReportContext], Result]
    figures: Callable[[Result, ReportContext], dict[str, str]]
    section: Callable[[Doc, Result, dict[str, str], ReportContext], None]


@dataclass(frozen=True)
class Experiment:
    """One experiment: its function of a config and everything that presents it.

    ``arguments`` adds the command-line options, ``config`` turns parsed options
    into a config (a ValueError is a one-line usage error), ``summary`` is the
    text the command prints, ``plot`` draws results into one PNG."""

    name: str
    help: str
    defaults: Mapping[str, Any]
    run: Callable[[Mapping[str, Any] | None], Result]
    arguments: Callable[[argparse.ArgumentParser], None]
    config: Callable[[argparse.Namespace], dict[str, Any]]
    summary: Callable[[Result, argparse.Namespace | None], str]
    plot: Callable[[Sequence[Mapping[str, Any]], str | os.PathLike[str]], str]
    report: ReportPart | None = None

    @classmethod
    def of_module(
        cls, module: str, help: str, *, plot: Callable[[Sequence[Mapping[str, Any]], str | os.PathLike[str]], str]
    ) -> "Experiment":
        """``of_module(__name__, help, plot=...)``: the experiment an experiment
        module defines by these names: ``DEFAULTS``, ``run``, ``cli_arguments``,
        ``cli_config``, ``summary`` and, for the report, ``report_run``,
        ``report_figures``, ``report_section``. Its name is the module's, with
        hyphens (``critical_scale`` → ``critical-scale``). Without
        ``report_figures`` the report has one figure: ``plot`` of the results
        under the module's own name, in ``NAME.png``."""
        m = sys.modules[module]
        key = module.rsplit(".", 1)[-1]
        name = key.replace("_", "-")
        figures = getattr(m, "report_figures", None) or _one_figure(key, plot)
        return cls(
            name=name, help=help, defaults=m.DEFAULTS, run=m.run, arguments=m.cli_arguments, config=m.cli_config,
            summary=m.summary, plot=plot, report=ReportPart(m.report_run, figures, m.report_section),
        )


def _one_figure(
    key: str, plot: Callable[[Sequence[Mapping[str, Any]], str | os.PathLike[str]], str]
) -> Callable[[Result, ReportContext], dict[str, str]]:
    def figures(res: Result, ctx: ReportContext) -> dict[str, str]:
        return {key: plot(res[key], ctx.path(f"{key}.png"))}

    return figures


def scale_pair_runs(ctx: ReportContext, title: str, run: Callable[[Mapping[str, Any]], Result]) -> list[Result]:
    """The report's runs of a cube-corpus comparison, unscaled against s: both
    presets (robust, classic) at s = 1e-3 and 1e-6."""

    def runs() -> list[Result]:
        return [run({**ctx.base, "solver": solver, "scale": sc}) for solver in ("robust", "classic") for sc in (1e-3, 1e-6)]

    return list(ctx.step(title, runs))


# ---------------------------------------------------------------- shared command-line options


def add_common_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--solver", default="robust", metavar="SOLVER",
                   help="solver: classic | robust | lemke | pgs | newton_fb | method:key=value,… (default: robust)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.add_argument("--plot", metavar="FILE", default=None, help="write a plot (PNG)")
    p.add_argument("--out", metavar="FILE", default=None, help="also write the JSON result to FILE")


def add_corpus_arguments(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("cube corpus")
    g.add_argument("--corpus-steps", type=int, default=None, metavar="N", help="steps per simulation (default: 600)")
    g.add_argument("--corpus-random", type=int, default=None, metavar="N", help="random tumbling drops (default: 8)")
    g.add_argument("--max-lcps", type=int, default=None, metavar="N", help="use at most N LCPs (seeded subset)")
    g.add_argument("--threads", type=int, default=0, help="solver threads (default 0: one per core)")


def add_simulation_arguments(p: argparse.ArgumentParser, seconds: float = 1.0) -> None:
    p.add_argument("--seconds", type=float, default=seconds, help=f"simulated time (default: {seconds:g})")
    p.add_argument("--dt", type=float, default=1e-3, help="time step h (default: 1e-3)")
    p.add_argument("--friction-dirs", type=int, default=8, metavar="K", help="friction directions (default: 8)")


def corpus_config(args: argparse.Namespace) -> dict[str, Any]:
    """The cube-corpus keys of a config from :func:`add_corpus_arguments`' options."""
    c: dict[str, Any] = {}
    if args.corpus_steps is not None:
        c["steps"] = args.corpus_steps
    if args.corpus_random is not None:
        c["n_random"] = args.corpus_random
    return {"corpus": c, "max_lcps": args.max_lcps, "threads": args.threads}


def base_config(args: argparse.Namespace) -> dict[str, Any]:
    """``solver`` (checked now: a bad name is a one-line error) and ``seed``."""
    from .presets import parse_solver

    parse_solver(args.solver)
    return {"solver": args.solver, "seed": args.seed}


def header(r: Mapping[str, Any]) -> str:
    """The first line of every experiment's text summary."""
    s = r.get("solver") or {}
    opts = ", ".join(f"{k}={v}" for k, v in (s.get("options") or {}).items())
    return (f"lcpsim {r['lcpsim_version']} {r['experiment']}: solver {s.get('name')} "
            f"({s.get('method')}{', ' + opts if opts else ''}), seed {r['seed']}")
