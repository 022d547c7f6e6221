"""lcp_residual: ‖min(z, M z + q)‖∞, checked against numpy."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from lcpsim import lcp_residual, lcp_residuals

finite = st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False)


def test_exact_values():
    M = np.array([[1.0, 0.0], [0.0, 1.0]])
    q = np.array([-1.0, 2.0])
    assert lcp_residual(M, q, [1.0, 0.0]) == 0.0  # the solution
    assert lcp_residual(M, q, [0.0, 0.0]) == 1.0  # w0 = -1
    assert lcp_residual(M, q, [2.0, 0.0]) == 1.0  # z0 = 2, w0 = 1: min = 1
    assert lcp_residual(M, q, [-0.5, 0.0]) == 1.5  # z0 = -0.5, w0 = -1.5
    assert lcp_residual(M, q, [1.0, 3.0]) == 3.0  # z1 = 3, w1 = 5


def test_residuals_dict():
    M = np.array([[2.0, 1.0], [1.0, 2.0]])
    q = np.array([-1.0, 1.0])
    r = lcp_residuals(M, q, [1.0, -0.25])
    w = M @ np.array([1.0, -0.25]) + q
    np.testing.assert_allclose(r["w"], w)
    assert r["min_z"] == -0.25
    assert r["min_w"] == pytest.approx(w.min())
    assert r["residual"] == pytest.approx(np.abs(np.minimum([1.0, -0.25], w)).max())
    assert r["natural"] == r["residual"]  # the old key, kept
    assert r["max_complementarity"] == pytest.approx(np.abs(np.array([1.0, -0.25]) * w).max())


@given(st.integers(1, 8).flatmap(lambda n: st.tuples(
    hnp.arrays(np.float64, (n, n), elements=finite),
    hnp.arrays(np.float64, (n,), elements=finite),
    hnp.arrays(np.float64, (n,), elements=finite),
)))
def test_matches_numpy(data):
    M, q, z = data
    expected = np.abs(np.minimum(z, M @ z + q)).max()
    got = lcp_residual(M, q, z)
    assert got == pytest.approx(expected, rel=1e-12, abs=1e-9)


@pytest.mark.parametrize(
    "z, parts",
    [
        ([1.0], ["z", "length 1"]),
        ([1.0, np.nan], ["z[1]", "nan"]),
        ([[1.0, 2.0]], ["z", "1-D"]),
        (["a", "b"], ["z", "real numbers"]),
    ],
)
def test_invalid_z(z, parts):
    with pytest.raises(ValueError) as info:
        lcp_residual(np.eye(2), [1.0, 1.0], z)
    for p in parts:
        assert p in str(info.value)


def test_invalid_problem():
    with pytest.raises(ValueError, match="square"):
        lcp_residual(np.ones((2, 3)), [1.0, 1.0], [0.0, 0.0])
