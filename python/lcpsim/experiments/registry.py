"""Every experiment, in the order the command line lists them and the report
runs them. Adding an experiment: its module (with an ``EXPERIMENT``) and one
line here."""

from __future__ import annotations

from . import critical_scale, failure_rate, invariance, patterns, push, slope
from .experiment import Experiment

#: Experiment name → its definition.
REGISTRY: dict[str, Experiment] = {
    e.name: e
    for e in (
        failure_rate.EXPERIMENT,
        slope.EXPERIMENT,
        critical_scale.EXPERIMENT,
        invariance.EXPERIMENT,
        patterns.EXPERIMENT,
        push.EXPERIMENT,
    )
}


def experiment(name: str) -> Experiment:
    """The experiment called ``name`` (``failure_rate`` and ``failure-rate`` both work)."""
    key = str(name).strip().replace("_", "-")
    if key not in REGISTRY:
        raise ValueError(f"unknown experiment {name!r} (valid: {', '.join(REGISTRY)})")
    return REGISTRY[key]
