"""Shared test helpers: an independent residual check and a brute-force LCP
enumeration, both in plain numpy so that no test trusts the solver's word; and
the check that bad input is refused with a message naming it."""

from __future__ import annotations

import itertools
import os

import numpy as np
import pytest
from hypothesis import HealthCheck, settings

settings.register_profile(
    "ci", max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=True
)
settings.register_profile("dev", max_examples=100, deadline=None)
settings.load_profile("ci" if os.environ.get("CI") else os.environ.get("HYPOTHESIS_PROFILE", "dev"))


def lcp_tolerance(M: np.ndarray, q: np.ndarray, z: np.ndarray, rel: float = 1e-8) -> float:
    """Round-off allowance for recomputing ``w = M z + q`` in float64."""
    M = np.asarray(M, dtype=float)
    scale = 1.0 + np.abs(q).max() + np.abs(M).sum(axis=1).max() * np.abs(z).max(initial=0.0)
    return rel * scale


def check_solution(M, q, z, rel: float = 1e-8) -> None:
    """Asserts that ``z`` solves the LCP ``(M, q)``, recomputing ``w`` here."""
    M = np.asarray(M, dtype=float)
    q = np.asarray(q, dtype=float)
    z = np.asarray(z, dtype=float)
    assert z.shape == q.shape, f"z has shape {z.shape}, expected {q.shape}"
    assert np.all(np.isfinite(z)), f"z is not finite: {z}"
    w = M @ z + q
    tol = lcp_tolerance(M, q, z, rel)
    assert z.min() >= -tol, f"z infeasible: min z = {z.min():.3e} < -{tol:.1e}\nz = {z}"
    assert w.min() >= -tol, f"w infeasible: min w = {w.min():.3e} < -{tol:.1e}\nz = {z}\nw = {w}"
    nat = np.abs(np.minimum(z, w)).max()
    assert nat <= tol, f"not complementary: ‖min(z, w)‖∞ = {nat:.3e} > {tol:.1e}\nz = {z}\nw = {w}"


def enumerate_solutions(M, q, tol: float = 1e-9) -> list[np.ndarray]:
    """All solutions of the LCP found by trying every complementary basis
    (``z_α = −M_αα⁻¹ q_α``, ``z_ᾱ = 0``); bases with a singular or badly
    conditioned ``M_αα`` are skipped. Duplicates are merged. For n ≤ ~12."""
    M = np.asarray(M, dtype=float)
    q = np.asarray(q, dtype=float)
    n = q.shape[0]
    found: list[np.ndarray] = []
    scale = 1.0 + np.abs(q).max()
    for r in range(n + 1):
        for alpha in itertools.combinations(range(n), r):
            z = np.zeros(n)
            if alpha:
                idx = np.array(alpha)
                sub = M[np.ix_(idx, idx)]
                if np.linalg.cond(sub) > 1e10:
                    continue
                z[idx] = np.linalg.solve(sub, -q[idx])
            w = M @ z + q
            t = tol * (scale + np.abs(M).max() * np.abs(z).max(initial=0.0))
            if z.min() >= -t and w.min() >= -t:
                if not any(np.allclose(z, f, atol=1e-7 * (1 + np.abs(f).max())) for f in found):
                    found.append(np.maximum(z, 0.0))
    return found


def raises_naming(exc: type[BaseException], call, words, *, one_line: bool = False, any_case: bool = False) -> str:
    """Asserts that ``call()`` raises ``exc`` whose message holds each of ``words`` (ignoring case
    with ``any_case``; on one line with ``one_line``); returns the message."""
    with pytest.raises(exc) as e:
        call()
    msg = str(e.value)
    assert not one_line or "\n" not in msg, msg
    for word in words:
        assert (word.lower() in msg.lower()) if any_case else (word in msg), (word, msg)
    return msg
