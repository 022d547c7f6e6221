"""The cube corpus: a documented, seeded set of simulations whose LCPs the
experiments study. Regenerated on demand — nothing downloaded.

Every simulation is a 1 kg, 1 m cube (inertia of the solid cube) at
``h = 1e-3`` s with ``k = 8`` friction directions (LCP size 10·nc: 10, 20 or
40 for 1, 2 or 4 contacts), stepped *unscaled* (s = 1) with the ``robust``
solver so that every trajectory is physical; each LCP is captured as
assembled. The experiments then re-solve these same LCPs with the solver and
the scale under study (``D M D``, ``D q`` with ``D = diag(I, I, s·I)``), so
that a different answer can only come from the solver and the scale, never
from a trajectory that went elsewhere.

The simulations (:func:`simulations`), all on a plane through the origin:

=================  ===========================================================
``flat_drop``      cube dropped flat from 5 cm with 0.3 m/s sideways (μ 0.5):
                   4 contacts, lands, slides to rest
``edge_drop``      cube turned 25° about x dropped from 10 cm (μ 0.6): lands
                   on an edge (2 contacts) and tips onto a face
``vertex_drop``    cube in a generic (seeded) orientation dropped from 10 cm
                   (μ 0.6): lands on a corner (1 contact), then edge, face
``slide_to_rest``  cube touching the ground at 1.5 m/s (μ 0.3): 4 sliding
                   contacts until it stops (≈ 0.51 s), then rest
``push_static``    9.79 N at the centre of mass, μ 1: static friction
``push_slide``     12 N at the centre of mass, μ 1: sliding
``slope_rest``     20° slope, μ 0.5: sticks
``slope_slide``    30° slope, μ 0.5: slides
``slope_knife``    45.0001° and 45.2° slopes, μ 1: the source note's slope test
                   (slides with the load on the downhill edge)
``tumble_<i>``     ``n_random`` seeded drops: slope 0°–40°, μ in [0.3, 1.2],
                   uniformly random orientation, angular velocity ~ N(0, 2
                   rad/s), sideways velocity ~ N(0, 0.5 m/s), gap 2–30 cm
=================  ===========================================================

``steps`` (default 600 per simulation, 0.6 s) sets the length; the default
corpus holds about 9,000 LCPs and takes about a second to generate.
"""

from __future__ import annotations

import math
import os
import tempfile
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np
from numpy.typing import NDArray

from .._core import ContactLayout, quat_from_axis_angle, quat_from_matrix, quat_mul, quat_to_matrix
from .._json import fields_dict
from ..world import World
from ._common import merge_config
from ..scale import parse_cone_scale, scale_value
from .presets import PRESETS, Solver, parse_solver

__all__ = [
    "DEFAULTS",
    "SimSpec",
    "Group",
    "CubeCorpus",
    "ScaledSolve",
    "simulations",
    "build_world",
    "generate",
    "scaled",
    "solve_scaled",
    "physical_answers",
    "experiment_corpus",
    "scaled_case",
]

#: Corpus config defaults.
DEFAULTS: dict[str, Any] = {
    "seed": 0,
    "n_random": 8,
    "steps": 600,
    "dt": 1e-3,
    "friction_dirs": 8,
}


@dataclass(frozen=True)
class SimSpec:
    """One simulation of the corpus: a cube on a plane."""

    name: str
    angle_deg: float = 0.0
    mu: float = 0.5
    height: float = 0.0  # gap between the lowest corner and the plane (m)
    orientation: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)  # relative to the plane's frame
    velocity: tuple[float, float, float] = (0.0, 0.0, 0.0)  # in the plane's frame (x downhill)
    angular_velocity: tuple[float, float, float] = (0.0, 0.0, 0.0)
    force: float = 0.0  # push along +x at the centre of mass (N)
    steps: int = 1000

    def to_dict(self) -> dict[str, Any]:
        return fields_dict(self)


def simulations(config: Mapping[str, Any] | None = None) -> list[SimSpec]:
    """The corpus's simulations for a config (see the module docs)."""
    cfg = merge_config("cube corpus", DEFAULTS, config)
    steps = int(cfg["steps"])
    rng = np.random.default_rng(int(cfg["seed"]))
    generic = rng.normal(size=4)
    edge = quat_from_axis_angle((1.0, 0.0, 0.0), math.radians(25))
    sims = [
        SimSpec("flat_drop", 0.0, 0.5, 0.05, velocity=(0.3, 0.0, 0.0), steps=steps),
        SimSpec("edge_drop", 0.0, 0.6, 0.10, (edge[0], edge[1], edge[2], edge[3]), steps=steps),
        SimSpec("vertex_drop", 0.0, 0.6, 0.10, tuple(generic / np.linalg.norm(generic)), steps=steps),
        SimSpec("slide_to_rest", 0.0, 0.3, 0.0, velocity=(1.5, 0.0, 0.0), steps=steps),
        SimSpec("push_static", 0.0, 1.0, 0.0, force=9.79, steps=steps),
        SimSpec("push_slide", 0.0, 1.0, 0.0, force=12.0, steps=steps),
        SimSpec("slope_rest", 20.0, 0.5, 0.0, steps=steps),
        SimSpec("slope_slide", 30.0, 0.5, 0.0, steps=steps),
        SimSpec("slope_knife_45.0001", 45.0001, 1.0, 0.0, steps=steps),
        SimSpec("slope_knife_45.2", 45.2, 1.0, 0.0, steps=steps),
    ]
    for i in range(int(cfg["n_random"])):
        angle = float(rng.choice([0.0, 10.0, 20.0, 30.0, 40.0]))
        mu = float(rng.uniform(0.3, 1.2))
        q = rng.normal(size=4)
        wv = rng.normal(0.0, 2.0, size=3)
        v = rng.normal(0.0, 0.5, size=3)
        v[2] = 0.0
        h = float(rng.uniform(0.02, 0.3))
        qn = q / np.linalg.norm(q)
        sims.append(
            SimSpec(
                f"tumble_{i}",
                angle,
                round(mu, 6),
                round(h, 6),
                (float(qn[0]), float(qn[1]), float(qn[2]), float(qn[3])),
                (float(v[0]), float(v[1]), float(v[2])),
                (float(wv[0]), float(wv[1]), float(wv[2])),
                steps=steps,
            )
        )
    return sims


def build_world(
    spec: SimSpec,
    *,
    dt: float = 1e-3,
    friction_dirs: int = 8,
    scale: float | str | None = None,
    solver: Solver = PRESETS["robust"],
) -> tuple[World, int]:
    """The world of one simulation and the cube's index. The cube's
    orientation and velocities are given in the plane's frame (x downhill,
    z along the normal); its lowest corner is ``spec.height`` above the plane."""
    w = World(dt=dt, friction_dirs=friction_dirs, cone_scale=scale, **solver.world_kwargs())
    if spec.angle_deg == 0.0:
        plane = w.add_ground(mu=spec.mu)
    else:
        plane = w.add_slope(spec.angle_deg, mu=spec.mu)
    pb = w.body(plane)
    n = np.asarray(pb.normal, dtype=float)
    down = np.asarray(pb.downhill if pb.downhill is not None else (1.0, 0.0, 0.0), dtype=float)
    down = down - (down @ n) * n
    down /= np.linalg.norm(down)
    side = np.cross(n, down)
    frame = np.stack([down, side, n], axis=1)  # plane frame → world
    # Orientation: plane frame rotation composed with the spec's.
    q_plane = quat_from_matrix(frame)
    q = np.asarray(quat_mul(q_plane, tuple(spec.orientation)))
    q /= np.linalg.norm(q)
    R = quat_to_matrix(q / np.linalg.norm(q))
    a = 0.5
    corners = np.array([[sx, sy, sz] for sx in (-a, a) for sy in (-a, a) for sz in (-a, a)]) @ R.T
    lowest = float((corners @ n).min())
    offset = float(pb.offset or 0.0)
    pos = n * (offset + spec.height - lowest)
    cube = w.add_box(
        size=1.0,
        mass=1.0,
        position=tuple(pos),
        orientation=tuple(q),
        velocity=tuple(frame @ np.asarray(spec.velocity, dtype=float)),
        angular_velocity=tuple(frame @ np.asarray(spec.angular_velocity, dtype=float)),
        mu=spec.mu,
    )
    if spec.force:
        w.apply_force(cube, (spec.force, 0.0, 0.0))
    return w, cube


@dataclass
class Group:
    """The corpus's LCPs of one size ``n = nc·(k + 2)``, stacked: ``M`` (b, n, n),
    ``q`` (b, n) unscaled as assembled, ``z`` (b, n) the ``robust`` solution
    the simulation used, and per LCP ``index`` (its number in the corpus),
    ``sim`` (which simulation) and ``step``."""

    n: int
    contacts: int
    friction_dirs: int
    M: NDArray[np.float64]  # (b, n, n) unscaled
    q: NDArray[np.float64]  # (b, n) unscaled
    z: NDArray[np.float64]  # (b, n) the robust answers
    index: NDArray[np.int64]
    sim: NDArray[np.int64]
    step: NDArray[np.int64]

    def __len__(self) -> int:
        return int(self.q.shape[0])

    def take(self, mask: NDArray[np.bool_] | NDArray[np.int64]) -> "Group":
        return Group(
            self.n, self.contacts, self.friction_dirs, self.M[mask], self.q[mask], self.z[mask],
            self.index[mask], self.sim[mask], self.step[mask],
        )

    def mu(self) -> NDArray[np.float64]:
        """(b, nc) each contact's μ, read off the cone rows (``M[λ_i, fn_i] = μ_i`` unscaled)."""
        lay = ContactLayout(self.contacts, self.friction_dirs)
        i = np.arange(lay.nc)
        return np.asarray(self.M[:, lay.impulses + i, i])


@dataclass
class CubeCorpus:
    """The corpus's LCPs in memory, grouped by size (see :class:`Group`)."""

    config: dict[str, Any]
    sims: list[SimSpec]
    groups: list[Group] = field(default_factory=list)

    def __len__(self) -> int:
        return sum(len(g) for g in self.groups)

    def subsample(self, max_lcps: int | None, seed: int = 0) -> "CubeCorpus":
        """At most ``max_lcps`` LCPs (a seeded random subset, order kept), or self."""
        total = len(self)
        if max_lcps is None or max_lcps >= total:
            return self
        rng = np.random.default_rng(seed)
        keep = np.zeros(total, dtype=bool)
        keep[rng.choice(total, size=int(max_lcps), replace=False)] = True
        groups = []
        for g in self.groups:
            sel = keep[g.index]
            if sel.any():
                groups.append(g.take(sel))
        return CubeCorpus(self.config, self.sims, groups)

    def summary(self) -> dict[str, Any]:
        per_sim = np.zeros(len(self.sims), dtype=np.int64)
        for g in self.groups:
            per_sim += np.bincount(g.sim, minlength=len(self.sims))
        return {
            "lcps": len(self),
            "by_contacts": {str(g.contacts): len(g) for g in self.groups},
            "by_size": {str(g.n): len(g) for g in self.groups},
            "simulations": [
                {"name": s.name, "lcps": int(per_sim[i]), "angle_deg": s.angle_deg, "mu": s.mu}
                for i, s in enumerate(self.sims)
            ],
        }


_CACHE: dict[str, CubeCorpus] = {}


def generate(
    config: Mapping[str, Any] | None = None, *, path: str | os.PathLike[str] | None = None, cache: bool = True
) -> CubeCorpus:
    """Runs the corpus's simulations and returns their LCPs. ``path``: also
    keep the HDF5 capture there (``docs/capture.md`` format), else a
    temporary file is used and removed. The last corpus made in this process
    is kept (``cache``), so experiments run one after another share it."""
    import json

    from ..io.capture import CaptureWriter, open_capture

    cfg = merge_config("cube corpus", DEFAULTS, config)
    key = json.dumps(cfg, sort_keys=True)
    if cache and path is None and key in _CACHE:
        return _CACHE[key]
    sims = simulations(cfg)
    tmpdir = None
    if path is None:
        tmpdir = tempfile.TemporaryDirectory(prefix="lcpsim-corpus-")
        file = os.path.join(tmpdir.name, "cube_corpus.h5")
    else:
        file = os.fspath(path)
    parts: dict[int, dict[str, list[Any]]] = {}
    try:
        meta = {"corpus": "cubes", "config": cfg, "simulations": [s.to_dict() for s in sims]}
        with CaptureWriter(file, metadata=meta) as writer:
            for spec in sims:
                world, _ = build_world(spec, dt=float(cfg["dt"]), friction_dirs=int(cfg["friction_dirs"]))
                world.run(spec.steps, capture=writer)
        with open_capture(file) as c:
            runs = c.run
            for rec in c:
                p = parts.setdefault(rec.n, {k: [] for k in ("M", "q", "z", "index", "sim", "step", "nc", "k")})
                p["M"].append(rec.M)
                p["q"].append(rec.q)
                p["z"].append(rec.z)
                p["index"].append(rec.index)
                p["sim"].append(int(runs[rec.index]))
                p["step"].append(rec.step)
                p["nc"].append(rec.contacts)
                p["k"].append(rec.friction_dirs)
    finally:
        if tmpdir is not None:
            tmpdir.cleanup()
    groups = []
    for n in sorted(parts):
        p = parts.pop(n)
        groups.append(
            Group(
                n=n,
                contacts=int(p["nc"][0]),
                friction_dirs=int(p["k"][0]),
                M=np.stack(p["M"]),
                q=np.stack(p["q"]),
                z=np.stack(p["z"]),
                index=np.asarray(p["index"], dtype=np.int64),
                sim=np.asarray(p["sim"], dtype=np.int64),
                step=np.asarray(p["step"], dtype=np.int64),
            )
        )
    out = CubeCorpus(config=cfg, sims=sims, groups=groups)
    if cache and path is None:
        _CACHE.clear()
        _CACHE[key] = out
    return out


def scaled(M: NDArray[np.float64], q: NDArray[np.float64], nc: int, k: int, s: float) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """``(D M D, D q, d)`` with ``D = diag(I, I, s·I)`` (λ rows and columns scaled by s)."""
    lay = ContactLayout(nc, k)
    Ms, qs = lay.scale_lcp(M, q, s)
    return Ms, qs, lay.cone_diagonal(s)


@dataclass
class ScaledSolve:
    """One solver's answers to a :class:`Group` at scale s, judged in physical
    units: ``z`` with λ mapped back (``λ = s·λ_scaled``; fn, fd unchanged),
    ``w = M z + q`` and ``residual = ‖min(z, w)‖∞`` on the *unscaled* LCP;
    ``solver_residual`` what the solver saw (the scaled LCP)."""

    s: float
    status: tuple[str, ...]
    ok: NDArray[np.bool_]
    pivots: NDArray[np.int64]
    z: NDArray[np.float64]  # (b, n), λ mapped back
    w: NDArray[np.float64]
    residual: NDArray[np.float64]  # on the unscaled LCP
    solver_residual: NDArray[np.float64]  # on the scaled LCP
    basis: NDArray[np.bool_] | None


def physical_answers(
    z_scaled: NDArray[np.float64], d: NDArray[np.float64], M: NDArray[np.float64], q: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """A batch's answers solved at a cone scale, judged in physical units:
    ``z = d·z_scaled`` (``d`` the scale's diagonal), ``w = M z + q`` and
    ``‖min(z, w)‖∞`` per LCP, on the unscaled LCPs ``(M, q)``."""
    z = z_scaled * d
    w = np.einsum("bij,bj->bi", M, z) + q
    return z, w, np.abs(np.minimum(z, w)).max(axis=1)


def solve_scaled(group: Group, solver: Solver, s: float, threads: int = 1) -> ScaledSolve:
    """Solves every LCP of ``group`` scaled by ``s`` with ``solver`` and maps the answers back."""
    Ms, qs, d = scaled(group.M, group.q, group.contacts, group.friction_dirs, s)
    res = solver.solve_batch(Ms, qs, threads=threads)
    z, w, residual = physical_answers(res.z, d, group.M, group.q)
    return ScaledSolve(
        s=s,
        status=tuple(res.status),
        ok=np.asarray(res.ok),
        pivots=np.asarray(res.pivots),
        z=z,
        w=w,
        residual=residual,
        solver_residual=np.asarray(res.residual),
        basis=None if res.basis is None else np.asarray(res.basis),
    )


def experiment_corpus(cfg: Mapping[str, Any]) -> dict[str, Any]:
    """The cube-corpus config of an experiment's config: its ``corpus`` mapping,
    seeded with the experiment's ``seed``; an unknown key is a ValueError."""
    c = {**dict(cfg.get("corpus") or {})}
    c.setdefault("seed", cfg["seed"])
    unknown = set(c) - set(DEFAULTS)
    if unknown:
        raise ValueError(f"corpus: unknown key(s) {sorted(unknown)} (valid: {', '.join(sorted(DEFAULTS))})")
    return c


#: Config keys (and defaults) of an experiment that starts from :func:`scaled_case`.
SCALED_CASE_DEFAULTS: dict[str, Any] = {
    "seed": 0,
    "scale": 1e-3,
    "solver": "robust",
    "corpus": {},
    "max_lcps": None,
    "threads": 0,
}


def scaled_case(cfg: Mapping[str, Any]) -> tuple[Solver, float | str | None, float, CubeCorpus]:
    """What an experiment comparing the cube corpus unscaled with ``cfg["scale"]``
    starts from: the solver, the parsed scale, its value s and the corpus
    (``max_lcps`` of it, a subset seeded with ``seed``)."""
    solver = parse_solver(cfg["solver"])
    ccfg = experiment_corpus(cfg)
    scale = parse_cone_scale(cfg["scale"])
    s = scale_value(scale, float(ccfg.get("dt", DEFAULTS["dt"])))
    return solver, scale, s, generate(ccfg).subsample(cfg["max_lcps"], int(cfg["seed"]))
