"""Solver presets: how an experiment solves its LCPs.

``classic``
    The source note's setting: Lemke with the ``classic`` pivoting rule (Moby /
    Drake style: absolute tolerances, Harris slack), ``piv_tol = 1e-12``,
    ``zero_tol = 1e-6``, applied to the LCP *as assembled* — the scaled one
    when a cone scale s < 1 is used — so its user zero of 1e-6 on the cone
    row means ``μ fn − Eᵀ fd ≥ −1e-6 / s`` in physical units.
``robust``
    lcpsim's default Lemke (lexicographic pivoting, its own equilibration,
    relative tie tolerance, answer accepted by its residual). The experiments
    judge every answer in physical units (λ mapped back, residual on the
    unscaled LCP), whatever the preset.

Any other solver can be named on the command line (``--solver``)::

    classic | robust | lemke | pgs | newton_fb
    lemke:pivoting=classic,zero_tol=1e-8       method, then options
    method=lemke,pivoting=classic,piv_tol=1e-10 the same as key=value pairs
    classic:zero_tol=1e-8                       a preset with options changed

Option values are parsed as int, float, true/false or left as strings; the
solver validates them (an unknown option is a ValueError naming it).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from ..lcp import METHODS, solve_lcp, solve_lcp_batch
from ..result import LcpBatchResult, LcpResult

__all__ = ["Solver", "PRESETS", "parse_solver", "solver_from_dict"]


@dataclass(frozen=True)
class Solver:
    """A named solver: ``method`` plus its options (as for :func:`lcpsim.solve_lcp`)."""

    name: str
    method: str = "lemke"
    options: Mapping[str, Any] = field(default_factory=dict)
    description: str = ""

    def solve(self, M: Any, q: Any) -> LcpResult:
        return solve_lcp(M, q, method=self.method, **dict(self.options))

    def solve_batch(self, Ms: Any, qs: Any, threads: int = 1) -> LcpBatchResult:
        return solve_lcp_batch(Ms, qs, method=self.method, threads=threads, **dict(self.options))

    def world_kwargs(self) -> dict[str, Any]:
        """Keyword arguments for :class:`lcpsim.World` / the scene builders."""
        return {"method": self.method, **dict(self.options)}

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "method": self.method, "options": dict(self.options)}

    @property
    def spec(self) -> str:
        """A string :func:`parse_solver` turns back into this solver."""
        if self.name in PRESETS and PRESETS[self.name] == self:
            return self.name
        opts = ",".join(f"{k}={v}" for k, v in self.options.items())
        return f"{self.method}:{opts}" if opts else self.method


#: The named presets.
PRESETS: dict[str, Solver] = {
    "classic": Solver(
        "classic",
        "lemke",
        {"pivoting": "classic", "piv_tol": 1e-12, "zero_tol": 1e-6},
        "classic Lemke, piv_tol 1e-12, zero_tol 1e-6, on the LCP as assembled (the source note's setting)",
    ),
    "robust": Solver(
        "robust",
        "lemke",
        {},
        "lcpsim's default Lemke: lexicographic pivoting, equilibration, answer accepted by its residual",
    ),
    "lemke": Solver("lemke", "lemke", {}, "Lemke with its defaults (= robust)"),
    "pgs": Solver("pgs", "pgs", {}, "projected Gauss-Seidel with its defaults"),
    "newton_fb": Solver("newton_fb", "newton_fb", {}, "damped Newton on the Fischer-Burmeister function"),
}


def _value(text: str) -> Any:
    t = text.strip()
    low = t.lower()
    if low in ("true", "false"):
        return low == "true"
    if low == "none":
        return None
    try:
        return int(t)
    except ValueError:
        pass
    try:
        return float(t)
    except ValueError:
        return t


def _pairs(text: str, spec: str) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for item in text.split(","):
        if not item.strip():
            continue
        if "=" not in item:
            raise ValueError(f"solver {spec!r}: expected key=value, got {item.strip()!r}")
        k, v = item.split("=", 1)
        out[k.strip()] = _value(v)
    return out


def _check(solver: Solver) -> Solver:
    if solver.method not in METHODS:
        raise ValueError(f"unknown method {solver.method!r} (valid: {', '.join(METHODS)})")
    # Let the solver itself validate the options on a 1x1 LCP.
    solve_lcp(np.array([[1.0]]), np.array([-1.0]), method=solver.method, **dict(solver.options))
    return solver


def parse_solver(spec: "str | Solver | Mapping[str, Any]") -> Solver:
    """A :class:`Solver` from a preset name, ``method:key=value,…``,
    ``method=…,key=value,…``, ``preset:key=value,…`` or a dict
    ``{"method": …, "options": {…}}`` (as :meth:`Solver.to_dict` writes)."""
    if isinstance(spec, Solver):
        return spec
    if isinstance(spec, Mapping):
        return solver_from_dict(spec)
    if not isinstance(spec, str) or not spec.strip():
        raise ValueError(f"a solver must be a preset ({', '.join(PRESETS)}) or method:key=value,…, got {spec!r}")
    text = spec.strip()
    if text in PRESETS:
        return PRESETS[text]
    head, _, rest = text.partition(":")
    head = head.strip()
    if "=" in head:  # method=lemke,pivoting=classic,…
        pairs = _pairs(text, spec)
        method = pairs.pop("method", "lemke")
        return _check(Solver(text, str(method), pairs))
    if head in PRESETS:
        base = PRESETS[head]
        return _check(Solver(text, base.method, {**dict(base.options), **_pairs(rest, spec)}))
    if head in METHODS:
        return _check(Solver(text, head, _pairs(rest, spec)))
    raise ValueError(
        f"unknown solver {spec!r} (presets: {', '.join(PRESETS)}; or method:key=value,… with method in "
        f"{', '.join(METHODS)})"
    )


def solver_from_dict(d: Mapping[str, Any]) -> Solver:
    """The inverse of :meth:`Solver.to_dict` (``name`` optional)."""
    if "method" not in d and "name" in d:
        return parse_solver(str(d["name"]))
    method = str(d.get("method", "lemke"))
    opts = dict(d.get("options") or {})
    name = str(d.get("name") or (f"{method}:" + ",".join(f"{k}={v}" for k, v in opts.items()) if opts else method))
    if name in PRESETS and PRESETS[name].method == method and dict(PRESETS[name].options) == opts:
        return PRESETS[name]
    return _check(Solver(name, method, opts))
