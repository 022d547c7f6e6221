"""The public Python API: result shape and types, accepted inputs, and a
ValueError naming the field and the value for every invalid input."""

from __future__ import annotations

import dataclasses
import pickle
import re

import numpy as np
import pytest

import lcpsim
from lcpsim import LcpBatchResult, LcpResult, lcp_residual, solve_lcp, solve_lcp_batch

from conftest import raises_naming

M2 = np.array([[2.0, 1.0], [1.0, 2.0]])
Q2 = np.array([-1.0, -1.0])

ALL_STATUSES = {
    "solved",
    "ray_termination",
    "max_pivots",
    "max_iterations",
    "singular_basis",
    "cycling",
    "numerical",
    "regularized",
}


def test_exports():
    for name in ("solve_lcp", "solve_lcp_batch", "lcp_residual", "LcpResult", "__version__"):
        assert hasattr(lcpsim, name), name
    assert re.fullmatch(r"\d+\.\d+\.\d+.*", lcpsim.__version__)
    assert set(lcpsim.STATUSES) == ALL_STATUSES
    assert lcpsim.METHODS == ("lemke", "pgs", "newton_fb")
    assert lcpsim.PIVOTINGS == ("lexicographic", "classic")


@pytest.mark.parametrize("method", ["lemke", "pgs", "newton_fb"])
def test_result_fields_and_types(method):
    res = solve_lcp(M2, Q2, method=method)
    assert isinstance(res, LcpResult)
    assert dataclasses.is_dataclass(res)
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.status = "solved"  # type: ignore[misc]
    assert isinstance(res.z, np.ndarray) and res.z.dtype == np.float64 and res.z.shape == (2,)
    assert isinstance(res.w, np.ndarray) and res.w.dtype == np.float64 and res.w.shape == (2,)
    assert res.status in ALL_STATUSES
    assert isinstance(res.ok, bool) and res.ok == (res.status == "solved")
    assert isinstance(res.pivots, int) and res.pivots >= 0
    for f in ("residual", "min_z", "min_w", "max_complementarity"):
        assert isinstance(getattr(res, f), float), f
    assert res.method == method
    if method == "lemke":
        assert res.basis is not None and res.basis.dtype == np.bool_ and res.basis.shape == (2,)
    # w and the residuals are recomputed from z in the units given.
    np.testing.assert_allclose(res.w, M2 @ res.z + Q2, rtol=0, atol=1e-14)
    assert res.residual == pytest.approx(np.abs(np.minimum(res.z, res.w)).max(), abs=1e-15)
    assert res.min_z == pytest.approx(res.z.min(), abs=0)
    assert res.min_w == pytest.approx(res.w.min(), abs=1e-15)
    assert res.max_complementarity == pytest.approx(np.abs(res.z * res.w).max(), abs=1e-15)
    d = res.to_dict()
    assert set(d) >= {"status", "ok", "pivots", "residual", "z", "w"}


@pytest.mark.parametrize("method", ["lemke", "pgs", "newton_fb"])
def test_result_equals_one_built_by_its_constructor(method):
    # solve_lcp builds its result without LcpResult.__init__; it must
    # behave exactly like one that went through it.
    res = solve_lcp(M2, Q2, method=method)
    built = LcpResult(**{f.name: getattr(res, f.name) for f in dataclasses.fields(LcpResult)})
    assert repr(res) == repr(built)
    assert res.certified is None and res.certificate is None and res.dump_path is None
    assert dataclasses.asdict(res).keys() == dataclasses.asdict(built).keys()
    assert res.to_dict() == built.to_dict()
    again = pickle.loads(pickle.dumps(res))
    assert repr(again) == repr(res)
    for mutate in (lambda: setattr(res, "ok", False), lambda: delattr(res, "z"),
                   lambda: setattr(res, "extra", 1)):
        with pytest.raises(dataclasses.FrozenInstanceError):
            mutate()


def test_defaults_solve_small_spd():
    res = solve_lcp(M2, Q2)
    assert res.ok, res
    np.testing.assert_allclose(res.z, [1 / 3, 1 / 3], atol=1e-12)


@pytest.mark.parametrize(
    "M, q",
    [
        (np.array([[2, 1], [1, 2]]), np.array([-1, -1])),  # int arrays
        (np.array([[2, 1], [1, 2]], dtype=np.float32), np.array([-1, -1], dtype=np.float32)),
        (np.asfortranarray(M2), Q2),  # Fortran order
        ([[2.0, 1.0], [1.0, 2.0]], [-1.0, -1.0]),  # nested lists
        (np.array([[2, 1], [1, 2]], dtype=np.uint8), np.array([-1, -1], dtype=np.int64)),
    ],
    ids=["int", "float32", "fortran", "lists", "uint8"],
)
def test_accepts_float_convertible_inputs(M, q):
    res = solve_lcp(M, q)
    np.testing.assert_allclose(res.z, [1 / 3, 1 / 3], atol=1e-6)


def test_accepts_non_contiguous_views():
    big = np.zeros((6, 6))
    big[::3, ::3] = M2  # a strided 2×2 view
    view = big[::3, ::3]
    assert not view.flags.c_contiguous
    qbig = np.array([-1.0, 0.0, -1.0, 0.0])
    res = solve_lcp(view, qbig[::2])
    np.testing.assert_allclose(res.z, [1 / 3, 1 / 3], atol=1e-12)
    # A transposed (Fortran-ordered) view of a non-symmetric matrix is read as its values.
    A = np.array([[2.0, 0.5], [-0.5, 2.0]])
    r1 = solve_lcp(A.T, Q2)
    r2 = solve_lcp(np.ascontiguousarray(A.T), Q2)
    np.testing.assert_array_equal(r1.z, r2.z)


def _raises_naming(match_parts, fn, *args, **kwargs):
    return raises_naming(ValueError, lambda: fn(*args, **kwargs), match_parts)


@pytest.mark.parametrize(
    "M, q, parts",
    [
        (np.array([[1.0, np.nan], [0.0, 1.0]]), Q2, ["M[0, 1]", "nan"]),
        (np.array([[1.0, 0.0], [np.inf, 1.0]]), Q2, ["M[1, 0]", "inf"]),
        (M2, np.array([-1.0, -np.inf]), ["q[1]", "inf"]),
        (M2, np.array([np.nan, 1.0]), ["q[0]", "nan"]),
        (np.ones((2, 3)), Q2, ["M", "square", "(2, 3)"]),
        (M2, np.array([1.0, 2.0, 3.0]), ["q", "length 3", "(2, 2)"]),
        (np.zeros((0, 0)), np.zeros(0), ["empty", "(0, 0)"]),
        (np.array([1.0, 2.0]), Q2, ["M", "2-D", "(2,)"]),
        (np.ones((2, 2, 2)), Q2, ["M", "2-D", "(2, 2, 2)"]),
        (M2, np.ones((2, 1)), ["q", "1-D", "(2, 1)"]),
        (M2, 3.0, ["q", "1-D", "()"]),
        (np.array([["a", "b"], ["c", "d"]]), Q2, ["M", "real numbers", "<U1"]),
        (M2.astype(complex), Q2, ["M", "real numbers", "complex128"]),
        (np.array([[1, None], [0, 1]], dtype=object), Q2, ["M", "real numbers", "object"]),
        ([[1.0, 2.0], [3.0]], Q2, ["M"]),  # ragged
    ],
    ids=[
        "nan-M", "inf-M", "inf-q", "nan-q", "not-square", "length-mismatch", "empty",
        "M-1d", "M-3d", "q-2d", "q-scalar", "str-dtype", "complex-dtype", "object-dtype", "ragged",
    ],
)
def test_invalid_input_raises_value_error(M, q, parts):
    msg = _raises_naming(parts, solve_lcp, M, q)
    assert "panic" not in msg.lower()


@pytest.mark.parametrize(
    "kwargs, parts",
    [
        (dict(method="dantzig"), ["method", "'dantzig'"]),
        (dict(method=3), ["method", "3"]),
        (dict(pivoting="bland"), ["pivoting", "'bland'"]),
        (dict(piv_tol=-1e-12), ["piv_tol", "-1e-12"]),
        (dict(zero_tol=-1.0), ["zero_tol", "-1.0"]),
        (dict(accept_tol=-0.5), ["accept_tol", "-0.5"]),
        (dict(piv_tol="small"), ["piv_tol", "'small'"]),
        (dict(piv_tol=float("nan")), ["piv_tol", "nan"]),
        (dict(piv_tol=True), ["piv_tol", "True"]),
        (dict(max_pivots=-3), ["max_pivots", "-3"]),
        (dict(max_pivots=2.5), ["max_pivots", "2.5"]),
        (dict(max_pivots="10"), ["max_pivots", "'10'"]),
        (dict(equilibrate="yes"), ["equilibrate", "'yes'"]),
        (dict(frobnicate=1), ["frobnicate"]),
        (dict(method="pgs", omega=2.5), ["omega", "2.5"]),
        (dict(method="pgs", omega=0.0), ["omega", "0.0"]),
        (dict(method="pgs", tol=-1e-3), ["tol", "-0.001"]),
        (dict(method="pgs", max_iterations=-1), ["max_iterations", "-1"]),
        (dict(method="pgs", pivoting="classic"), ["pivoting", "'classic'", "lemke"]),
        (dict(method="pgs", piv_tol=1e-3), ["piv_tol", "lemke"]),
        (dict(method="newton_fb", omega=1.0), ["omega"]),
        (dict(method="newton_fb", tol="x"), ["tol", "'x'"]),
        (dict(method="newton_fb", backtrack=1.5), ["backtrack", "1.5"]),
        (dict(method="lemke", omega=1.0), ["omega"]),
    ],
    ids=lambda x: str(x) if not isinstance(x, dict) else ",".join(f"{k}={v!r}" for k, v in x.items()),
)
def test_invalid_options_raise_value_error(kwargs, parts):
    _raises_naming(parts, solve_lcp, M2, Q2, **kwargs)


def test_valid_options_accepted():
    assert solve_lcp(M2, Q2, pivoting="classic").ok
    assert solve_lcp(M2, Q2, piv_tol=0.0, zero_tol=0.0, max_pivots=100, accept_tol=1e-8, equilibrate=False).ok
    assert solve_lcp(M2, Q2, max_pivots=np.int64(50)).ok
    r = solve_lcp(M2, Q2, method="pgs", omega=1.2, max_iterations=10_000, tol=1e-12)
    assert r.method == "pgs"
    r = solve_lcp(M2, Q2, method="newton_fb", max_iterations=50, tol=1e-12, armijo_sigma=1e-4, backtrack=0.5)
    assert r.method == "newton_fb"
    # None means "the default".
    assert solve_lcp(M2, Q2, method="pgs", tol=None).method == "pgs"


def test_pivot_limit_is_reported_not_raised():
    # This problem needs 3 pivots; a limit of 2 must end in max_pivots.
    assert solve_lcp(M2, Q2).pivots > 2
    res = solve_lcp(M2, Q2, max_pivots=2)
    assert res.status == "max_pivots" and not res.ok
    assert res.z.shape == (2,) and res.w.shape == (2,)
    assert res.pivots >= 2  # the limit applies per attempt of Lemke's repair ladder


def test_iteration_limit_is_reported_not_raised():
    res = solve_lcp(M2, Q2, method="pgs", max_iterations=1, tol=0.0)
    assert res.status == "max_iterations" and not res.ok
    assert res.pivots == 1


def test_keyword_defaults_are_the_compiled_defaults():
    # solve_lcp passes no options when given none, so its defaults
    # must be the compiled ones; solve_lcp_batch passes them all, but agrees.
    from lcpsim import _core

    for fn in (solve_lcp, solve_lcp_batch):
        kw = fn.__kwdefaults__
        assert kw["method"] == "lemke", fn
        for name in ("pivoting", "piv_tol", "zero_tol", "max_pivots"):
            assert kw[name] == _core.LEMKE_DEFAULTS[name], (fn, name)
    assert _core.solve_lcp(M2, Q2)["method"] == "lemke"
    assert set(_core.LEMKE_DEFAULTS) == set(_core.METHOD_OPTIONS["lemke"])


@pytest.mark.parametrize("seed", range(8))
def test_default_call_equals_explicit_options(seed):
    # The inline default path and the general path (taken as soon as any
    # option is given, even None = default) solve identically.
    M, q, *_ = lcpsim._core.contact_lcp(4, 8, 1e-3, seed)
    fast = solve_lcp(M, q)
    general = solve_lcp(M, q, method="lemke", pivoting="lexicographic", piv_tol=1e-12, zero_tol=1e-6,
                        accept_tol=None)
    assert repr(fast) == repr(general)
    np.testing.assert_array_equal(fast.z, general.z)
    # ... including for non-float64, non-contiguous or list input.
    for M_, q_ in ((np.asfortranarray(M), np.repeat(q, 2)[::2]), (M.astype(np.float32).astype(np.float64), q),
                   (M.tolist(), q.tolist())):
        assert repr(solve_lcp(M_, q_)) == repr(solve_lcp(np.array(M_, dtype=float), np.array(q_, dtype=float)))


def test_bad_input_on_the_default_path_is_a_value_error():
    for M, q, match in ((np.ones((2, 3)), Q2, "square"), (M2, np.ones(3), "q has length 3"),
                        (np.array([[1.0, np.inf], [0.0, 1.0]]), Q2, r"M\[0, 1\] = inf"),
                        (M2.astype(complex), Q2, "M must hold real numbers"), (np.ones(2), Q2, "M must be 2-D"),
                        (M2, np.array([np.nan, 1.0]), r"q\[0\] = nan"), ("M", Q2, "M must")):
        with pytest.raises(ValueError, match=match):
            solve_lcp(M, q)
    with pytest.raises(ValueError, match="certify must be True or False"):
        solve_lcp(M2, Q2, certify=1)
    with pytest.raises(ValueError, match="unknown method"):
        solve_lcp(M2, Q2, method=np.array(["lemke"]))


def test_private_core_validates_too():
    from lcpsim import _core

    with pytest.raises(ValueError, match=r"M\[0, 0\] = (NaN|nan)"):
        _core.solve_lcp(np.array([[np.nan]]), np.array([1.0]))
    with pytest.raises(ValueError, match="square"):
        _core.solve_lcp(np.ones((1, 2)), np.ones(1))
    with pytest.raises(ValueError, match="M must be a 2-D array"):
        _core.solve_lcp(np.ones(3), np.ones(3))
    with pytest.raises(ValueError, match="unknown method"):
        _core.solve_lcp(M2, Q2, "simplex")
    with pytest.raises(ValueError, match="unknown option"):
        _core.solve_lcp(M2, Q2, "lemke", nope=1)
    with pytest.raises(ValueError, match="z has length 3"):
        _core.lcp_residual(M2, Q2, np.ones(3))
    # The dict becomes an LcpResult's __dict__: its keys are the result's fields
    # but the three that only the Python layer sets (their defaults apply).
    python_only = {"certified", "certificate", "dump_path"}
    fields = {f.name for f in dataclasses.fields(LcpResult)}
    for method in ("lemke", "pgs", "newton_fb"):
        d = _core.solve_lcp(M2, Q2, method)
        assert set(d) == fields - python_only, method
        assert all(LcpResult.__dataclass_fields__[k].default is None for k in python_only)


def test_lcp_result_dataclass_fields():
    names = [f.name for f in dataclasses.fields(LcpResult)]
    assert names[:6] == ["z", "w", "status", "ok", "pivots", "residual"]
    assert {"min_z", "min_w", "max_complementarity", "method", "basis"} <= set(names)
    assert dataclasses.is_dataclass(LcpBatchResult)


def test_residual_function_is_exported():
    assert lcp_residual(M2, Q2, [1 / 3, 1 / 3]) == pytest.approx(0.0, abs=1e-15)
    assert isinstance(solve_lcp_batch(M2[None], Q2[None]), LcpBatchResult)
