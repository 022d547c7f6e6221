"""The source note's experiments, as plain functions of a
JSON-ready config with an explicit seed::

    from lcpsim.experiments import run_experiment
    r = run_experiment("slope", {"angle_deg": 45.2, "scale": 1e-3, "solver": "classic"})
    r["outcome"], r["slide_distance_m"], r["config"], r["lcpsim_version"]

=================  =========================================================
``failure-rate``   failures of a solver over the cube corpus per scale
``slope``          the 45°+ slope test: rest, slide or tip
``critical-scale`` the scale below which the slope cube is held
``invariance``     fn, fd unchanged and λ·s by scaling
``patterns``       sign patterns (fn, Σfd, λ) per contact, scaled × unscaled
``push``           the pushed cube at 9.79 N
=================  =========================================================

Each returns a dict carrying ``config``, ``seed`` and ``lcpsim_version``;
:mod:`.sweep` maps them over a Dask cluster, :mod:`.report` runs them all.
Each module defines one :class:`~.experiment.Experiment` (run, defaults,
command-line options, text summary, figure, report section), listed in
:mod:`.registry`; the command line and the report are built from it.
"""

from __future__ import annotations

from typing import Any, Callable, Mapping

from .experiment import Experiment
from .presets import PRESETS, Solver, parse_solver
from .registry import REGISTRY, experiment

__all__ = ["REGISTRY", "Experiment", "experiment", "EXPERIMENTS", "DEFAULTS", "run_experiment", "experiment_name",
           "PRESETS", "Solver", "parse_solver"]

#: Experiment name → run function.
EXPERIMENTS: dict[str, Callable[[Mapping[str, Any] | None], dict[str, Any]]] = {n: e.run for n, e in REGISTRY.items()}

#: Experiment name → its config defaults.
DEFAULTS: dict[str, dict[str, Any]] = {n: dict(e.defaults) for n, e in REGISTRY.items()}


def experiment_name(name: str) -> str:
    """The canonical name (``failure_rate`` and ``failure-rate`` both work)."""
    return experiment(name).name


def run_experiment(name: str, config: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Runs experiment ``name`` with ``config`` (missing keys take the defaults)."""
    return experiment(name).run(config)
