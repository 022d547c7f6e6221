"""The problem sets of the peers' run: contact LCPs, the cube corpus, the
hard corpus and random SPD LCPs, each problem with what its physical
residual needs (the cone-scaling diagonal and the unscaled problem)."""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field

import numpy as np


@dataclass
class Problem:
    """``(M, q)`` as given to the solvers; ``d`` the cone-scaling diagonal and
    ``(M1, q1)`` the unscaled problem for the physical residual (None: the
    problem is its own physical form)."""

    M: np.ndarray
    q: np.ndarray
    label: str
    group: str
    d: np.ndarray | None = None
    M1: np.ndarray | None = None
    q1: np.ndarray | None = None

    @property
    def n(self) -> int:
        return int(self.q.shape[0])

    def residuals(self, z: np.ndarray) -> tuple[float, float]:
        """(natural residual in the units given, in physical units); NaN → inf."""

        def nat(M: np.ndarray, q: np.ndarray, z: np.ndarray) -> float:
            if z.shape != q.shape or not np.all(np.isfinite(z)):
                return float("inf")
            with np.errstate(all="ignore"):
                r = float(np.max(np.abs(np.minimum(z, M @ z + q))))
            return r if np.isfinite(r) else float("inf")

        given = nat(self.M, self.q, z)
        if self.d is None or self.M1 is None or self.q1 is None:
            return given, given
        return given, nat(self.M1, self.q1, self.d * z)


@dataclass
class ProblemSet:
    key: str
    title: str
    description: str
    problems: list[Problem]
    back_to_back: bool = True
    passes: int | None = None  # None: the --passes default
    group_order: list[str] = field(default_factory=list)


def scale_label(s: float) -> str:
    return "none" if s == 1.0 else f"{s:g}"


def contact_sets(scales: list[float], per_size: int, seed: int) -> list[ProblemSet]:
    from lcpsim import generate

    out = []
    for s in scales:
        probs = []
        for nc in (1, 2, 4):
            for i in range(per_size):
                p = generate.contact_lcp(nc, 8, s, seed + i)
                p1 = p.at_scale(1.0)
                probs.append(
                    Problem(p.M, p.q, p.label, f"n = {p.n}", p.cone_diagonal() if s != 1.0 else None, p1.M, p1.q)
                )
        out.append(
            ProblemSet(
                f"contact/s={scale_label(s)}",
                f"Contact LCPs (one-cube generator), s = {scale_label(s)}",
                f"`lcpsim.generate.contact_lcp(nc, 8, s, seed)`, nc ∈ {{1, 2, 4}} (n = 10, 20, 40), seeds "
                f"{seed}…{seed + per_size - 1}: unit cube on a 0–60° slope, μ ∈ [0.1, 1.5], random velocity, "
                f"h = 0.01, friction-cone scale s = {scale_label(s)}.",
                probs,
                group_order=["n = 10", "n = 20", "n = 40"],
            )
        )
    return out


def cube_corpus_sets(scales: list[float], per_size: int, seed: int) -> tuple[list[ProblemSet], str]:
    """The experiments' cube corpus (``lcpsim.experiments.cube_corpus``), if installed.

    Hook: any module providing ``generate(config) -> corpus`` whose ``groups``
    each have ``M`` (b, n, n), ``q`` (b, n) unscaled, ``contacts`` and
    ``friction_dirs`` is used; the LCPs are scaled here by ``D = diag(I, I, s·I)``.
    """
    try:
        from lcpsim import ContactLayout

        sc = importlib.import_module("lcpsim.experiments.cube_corpus")
        corpus = sc.generate()
    except Exception as e:  # not there yet, or broken: say so in the report
        return [], f"cube corpus not included: `lcpsim.experiments.cube_corpus` unavailable ({type(e).__name__}: {e})"
    rng = np.random.default_rng(seed)
    picked = []
    for g in corpus.groups:
        idx = np.sort(rng.choice(len(g.q), size=min(per_size, len(g.q)), replace=False))
        picked.append((g, idx))
    out = []
    for s in scales:
        probs = []
        for g, idx in picked:
            lay = ContactLayout(int(g.contacts), int(g.friction_dirs))
            d = lay.cone_diagonal(s)
            for i in idx:
                M1, q1 = np.ascontiguousarray(g.M[i]), np.ascontiguousarray(g.q[i])
                M, q = (M1, q1) if s == 1.0 else lay.scale_lcp(M1, q1, s)
                probs.append(
                    Problem(M, q, f"cubes/{int(g.index[i])}", f"n = {g.n}", d if s != 1.0 else None, M1, q1)
                )
        out.append(
            ProblemSet(
                f"cubes/s={scale_label(s)}",
                f"Cube corpus (simulation LCPs), s = {scale_label(s)}",
                f"`lcpsim.experiments.cube_corpus.generate()` (default config, {len(corpus)} LCPs from cube "
                f"simulations at h = 1e-3, assembled unscaled); a seeded subset of at most {per_size} per size, "
                f"scaled by D = diag(I, I, s·I) with s = {scale_label(s)}.",
                probs,
                group_order=[f"n = {g.n}" for g, _ in picked],
            )
        )
    return out, f"cube corpus: {len(corpus)} LCPs, {per_size} per size sampled"


def hard_sets(scales: list[float], count: int, seed: int) -> list[ProblemSet]:
    from lcpsim import generate

    def bucket(n: int) -> str:
        return "n ≤ 40" if n <= 40 else "41 ≤ n ≤ 100" if n <= 100 else "n > 100"

    out = []
    for s in scales:
        probs = []
        for p in generate.hard_corpus(seed, count, s):
            p1 = p.at_scale(1.0)
            probs.append(Problem(p.M, p.q, p.label, bucket(p.n), p.cone_diagonal() if s != 1.0 else None, p1.M, p1.q))
        out.append(
            ProblemSet(
                f"hard/s={scale_label(s)}",
                f"Hard contact LCPs, s = {scale_label(s)}",
                f"`lcpsim.generate.hard_corpus({seed}, {count}, s)`: the hard corpus's seven families in turn (many, "
                f"duplicate, nearly parallel, collinear contacts; mass ratios to 1e4; thin rods with cond(M_b) to 1e8; "
                f"mixed), k = 8 (some 4 and 16), n = "
                f"{min(p.n for p in probs)}–{max(p.n for p in probs)}, s = {scale_label(s)}.",
                probs,
                back_to_back=False,
                group_order=["n ≤ 40", "41 ≤ n ≤ 100", "n > 100"],
            )
        )
    return out


def spd_sets(sizes: list[tuple[int, int]], seed: int) -> list[ProblemSet]:
    from lcpsim import generate

    out = []
    for n, count in sizes:
        probs = []
        for i in range(count):
            p = generate.spd_lcp(n, seed + i)
            probs.append(Problem(p.M, p.q, p.label, f"n = {n}"))
        big = n >= 500
        out.append(
            ProblemSet(
                f"spd/n={n}",
                f"Random SPD LCPs, n = {n}",
                f"`lcpsim.generate.spd_lcp({n}, seed)`, seeds {seed}…{seed + count - 1}: M = A Aᵀ/n + 0.1 I "
                f"(A uniform in [−1, 1]), q uniform in [−1, 1].",
                probs,
                back_to_back=not big,
                passes=1 if big else None,
                group_order=[f"n = {n}"],
            )
        )
    return out
