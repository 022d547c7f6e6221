"""Penetration stabilization of the contact LCP's ``b0`` (the normal rows' constant): the
:class:`Stabilization` a :class:`lcpsim.World` takes, and the forms it may be
given in."""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any, Mapping

from . import _core

__all__ = ["Stabilization", "as_stabilization"]


@dataclass(frozen=True)
class Stabilization:
    """Penetration stabilization of ``b0``.

    A contact with gap φ > 0 inside the margin adds ``φ/h`` when ``speculative``
    (it may close within the step, not overshoot); a penetrating one adds
    ``erp·min(0, φ + slop)/h``. A body resting at φ = 0 gets no term, and
    gaps with ``|φ| ≤ gap_floor`` count as φ = 0: they are the round-off of the
    contact geometry (about 1e-14–1e-13 m), which divided by h would move a
    resting stack's LCP every step.
    """

    # The defaults are sim::Stabilization's (``_core.WORLD_DEFAULTS``); the
    # compiled World checks the values.

    #: Fraction of the penetration removed per step, in [0, 1] (default 0.2).
    erp: float = _core.WORLD_DEFAULTS["erp"]
    #: Penetration left uncorrected (m), ≥ 0 (default 0).
    slop: float = _core.WORLD_DEFAULTS["slop"]
    #: Use the positive gap of contacts inside the margin (default True).
    speculative: bool = _core.WORLD_DEFAULTS["speculative"]
    #: Gaps within ±gap_floor (m) get no term; 0 turns the floor off (default 1e-12).
    gap_floor: float = _core.WORLD_DEFAULTS["gap_floor"]

    @classmethod
    def none(cls) -> "Stabilization":
        """No correction at all: ``b0 = J_n v*``."""
        return cls(erp=0.0, slop=0.0, speculative=False, gap_floor=0.0)


#: The fields of :class:`Stabilization`, which ``World`` also takes as keywords.
FIELDS = tuple(f.name for f in fields(Stabilization))


def as_stabilization(s: Stabilization | Mapping[str, Any] | str | None) -> Stabilization:
    """None (the default), ``"none"``, ``"default"``, a :class:`Stabilization` or a
    mapping of its fields."""
    if s is None:
        return Stabilization()
    if isinstance(s, Stabilization):
        return s
    if isinstance(s, str):
        if s == "none":
            return Stabilization.none()
        if s == "default":
            return Stabilization()
        raise ValueError(f"stabilization must be None, 'none', 'default', a Stabilization or a mapping, got {s!r}")
    if isinstance(s, Mapping):
        unknown = set(s) - set(FIELDS)
        if unknown:
            raise ValueError(f"unknown stabilization field(s) {sorted(unknown)} (valid: {', '.join(FIELDS)})")
        return Stabilization(**s)
    raise ValueError(f"stabilization must be None, 'none', a Stabilization or a mapping, got {s!r}")
