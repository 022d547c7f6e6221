"""The friction-cone scale s (the cone rows of the contact LCP scaled by s,
λ_scaled = λ / s) as users write it: ``None`` /
``"none"`` (unscaled, s = 1), ``"dt"`` (s = the time step, the source note's choice)
or a number > 0. The one parser of the command line and the experiments;
:class:`lcpsim.World` hands its ``cone_scale`` to the compiled module, which
reads the same spellings."""

from __future__ import annotations

import argparse
import math
from typing import Any, Iterable

import numpy as np

__all__ = ["parse_cone_scale", "parse_cone_scales", "cone_scale_argument", "scale_value", "scale_label"]

_UNSCALED = ("none", "unscaled", "")
_TIME_STEP = ("dt", "h", "timestep", "time_step")


def parse_cone_scale(x: Any, name: str = "scale") -> float | str | None:
    """``None`` (unscaled; also ``"none"``, ``"unscaled"``, ``""`` and the number 1),
    ``"dt"`` (also ``"h"``, ``"timestep"``, ``"time_step"``) or a finite number > 0
    (a number or a numeric string). Anything else is a ValueError naming ``name``
    and the value."""
    if x is None:
        return None
    bad = f"{name} must be none, dt or a number > 0, got {x!r}"
    if isinstance(x, str):
        t = x.strip().lower()
        if t in _UNSCALED:
            return None
        if t in _TIME_STEP:
            return "dt"
        try:
            v = float(t)
        except ValueError:
            raise ValueError(bad) from None
    elif isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, float, np.integer, np.floating)):
        raise ValueError(bad)
    else:
        v = float(x)
    if not (math.isfinite(v) and v > 0):
        raise ValueError(bad)
    return None if v == 1.0 else v


def parse_cone_scales(text: str | Iterable[Any]) -> list[float | str | None]:
    """A comma-separated list (or an iterable) of scales."""
    items = [t for t in text.split(",") if t.strip()] if isinstance(text, str) else list(text)
    if not items:
        raise ValueError("give at least one scale")
    return [parse_cone_scale(t) for t in items]


def cone_scale_argument(text: str) -> float | str:
    """The argparse type of a ``--scale`` option: ``"none"`` (unscaled), ``"dt"`` or the number."""
    try:
        s = parse_cone_scale(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None
    return "none" if s is None else s


def scale_value(scale: float | str | None, dt: float) -> float:
    """The numeric s of a parsed scale."""
    if scale is None:
        return 1.0
    if scale == "dt":
        return float(dt)
    return float(scale)


def scale_label(scale: float | str | None) -> str:
    """``none``, ``dt`` or the number (``%g``)."""
    if scale is None:
        return "none"
    if scale == "dt":
        return "dt"
    return f"{float(scale):g}"
