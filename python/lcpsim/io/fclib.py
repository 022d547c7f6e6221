"""FCLib files: the HDF5 format of the friction-contact benchmark library
(Acary, Brémond & Huber 2018; the C reference is ``libfclib``, FCLib 3.1.0).

Only **local** problems are read and written: find ``u, r`` with

    u = W r + q,   K ∋ r ⊥ u + Φ(u) ∈ K*   (per contact: normal, then two tangents)

where ``K`` is the product of Coulomb cones ``‖r_T‖ ≤ μ r_N`` and ``Φ`` De
Saxcé's ``(μ‖u_T‖, 0, 0)``. The layout, as libfclib writes it::

    /fclib_local/spacedim              int [1]           3
    /fclib_local/W/{nzmax, m, n, nz}   int [1] each      nz ≥ 0 triplet, −1 CSC, −2 CSR
    /fclib_local/W/{p, i, x}           int, int, double  triplet: p rows, i columns (nz each);
                                                         CSC/CSR: p pointers (n+1 / m+1), i indices (nzmax)
    /fclib_local/V, /fclib_local/R     optional, same layout (equality constraints)
    /fclib_local/vectors/{q, mu, s}    double            q (3·nc), mu (nc), s (rows of R)
    /fclib_local/info/{title, description, math_info}   strings, optional
    /solution/{u, r}                   double (3·nc), optional (v, l for problems with R)
    /guesses/number_of_guesses, /guesses/1/{u, r}, …    optional

A file holding ``/fclib_global`` is recognised and refused ("global problems
are not supported"). Every malformed input raises :class:`FclibError` naming
the dataset. The faceted-LCP import, the exact-cone residual and the export
from the simulator are in :mod:`lcpsim.faceting`.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .hdf5 import HDF5_READ_ERRORS, is_hdf5_file, open_hdf5

__all__ = [
    "FclibError",
    "FclibSolution",
    "FclibLocal",
    "STORAGES",
    "read_fclib",
    "write_fclib",
    "fclib_kind",
    "is_fclib",
]

#: Matrix storages and their ``nz`` code (triplet: nz = number of entries ≥ 0).
STORAGES = {"triplet": None, "csc": -1, "csr": -2}


class FclibError(ValueError):
    """A file that is not a valid FCLib local problem (the message names the dataset)."""


@dataclass
class FclibSolution:
    """A solution or guess: local velocity ``u`` and impulse ``r`` (3·nc each);
    ``v``, ``l`` only for problems with equality constraints."""

    u: NDArray[np.float64]
    r: NDArray[np.float64]
    v: NDArray[np.float64] | None = None
    l: NDArray[np.float64] | None = None


@dataclass
class FclibLocal:
    """An FCLib local problem. ``W`` is a ``scipy.sparse`` CSC matrix (3·nc square; given dense, converted),
    ``q`` (3·nc) and ``mu`` (nc) arrays, contacts ordered normal, tangent 1, tangent 2."""

    W: Any
    q: NDArray[np.float64]
    mu: NDArray[np.float64]
    V: Any = None
    R: Any = None
    s: NDArray[np.float64] | None = None
    title: str | None = None
    description: str | None = None
    math_info: str | None = None
    solution: FclibSolution | None = None
    guesses: list[FclibSolution] = field(default_factory=list)
    spacedim: int = 3
    storage: str = "csc"
    path: Path | None = None

    def __post_init__(self) -> None:
        # Any matrix-like W (dense or scipy.sparse) and array-like vectors.
        self.W = as_sparse(self.W)
        self.q = np.asarray(self.q, dtype=np.float64).reshape(-1)
        self.mu = np.asarray(self.mu, dtype=np.float64).reshape(-1)

    @property
    def nc(self) -> int:
        """Number of contacts."""
        return int(self.mu.shape[0])

    def dense_W(self) -> NDArray[np.float64]:
        return np.asarray(self.W.toarray(), dtype=np.float64)

    def validate(self, where: str = "problem") -> "FclibLocal":
        """Checks sizes and values; raises :class:`FclibError` naming the dataset."""
        if self.spacedim != 3:
            raise FclibError(f"{where}: /fclib_local/spacedim is {self.spacedim}; only 3-D problems (3) are supported")
        m, n = self.W.shape
        if m != n:
            raise FclibError(f"{where}: /fclib_local/W is {m}×{n}, not square")
        if m % 3:
            raise FclibError(f"{where}: /fclib_local/W has {m} rows, not a multiple of spacedim 3")
        nc = m // 3
        _check_vec(self.q, 3 * nc, f"{where}: /fclib_local/vectors/q", f"3·nc = {3 * nc} (W is {m}×{n})")
        _check_vec(self.mu, nc, f"{where}: /fclib_local/vectors/mu", f"nc = {nc} (W is {m}×{n})")
        if np.any(self.mu < 0):
            i = int(np.argmax(self.mu < 0))
            raise FclibError(f"{where}: /fclib_local/vectors/mu[{i}] = {self.mu[i]!r} is negative")
        if not np.all(np.isfinite(self.W.data)):
            raise FclibError(f"{where}: /fclib_local/W/x holds a non-finite value")
        if (self.V is None) != (self.R is None):
            raise FclibError(f"{where}: /fclib_local/V and /fclib_local/R must be given together")
        for k, sol in [("solution", self.solution)] + [(f"guesses/{j + 1}", g) for j, g in enumerate(self.guesses)]:
            if sol is not None:
                _check_vec(sol.u, 3 * nc, f"{where}: /{k}/u", f"3·nc = {3 * nc}")
                _check_vec(sol.r, 3 * nc, f"{where}: /{k}/r", f"3·nc = {3 * nc}")
        return self


def _check_vec(x: NDArray[np.float64], n: int, name: str, expect: str) -> None:
    if x.ndim != 1 or x.shape[0] != n:
        raise FclibError(f"{name} has {x.size} values, expected {expect}")
    if not np.all(np.isfinite(x)):
        i = int(np.argmax(~np.isfinite(x)))
        raise FclibError(f"{name}[{i}] = {x[i]!r} is not finite")


# ---------------------------------------------------------------- reading


def _h5py() -> Any:
    import h5py  # type: ignore[import-untyped]

    return h5py


def fclib_kind(path: str | os.PathLike[str]) -> str | None:
    """``"local"``, ``"global"`` or ``None`` (not an HDF5 file with an FCLib group)."""
    p = Path(path)
    if not is_hdf5_file(p):
        return None
    try:
        with open_hdf5(p) as f:
            if "fclib_local" in f:
                return "local"
            if "fclib_global" in f:
                return "global"
    except HDF5_READ_ERRORS:  # damaged: not an FCLib file we can read
        return None
    return None


def is_fclib(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` is an HDF5 file holding an FCLib problem (local or global)."""
    return fclib_kind(path) is not None


def _dataset(g: Any, name: str, where: str) -> Any:
    full = f"{g.name.rstrip('/')}/{name}"
    if name not in g:
        raise FclibError(f"{where}: dataset {full} is missing")
    ds = g[name]
    if not hasattr(ds, "shape"):
        raise FclibError(f"{where}: {full} is a group, expected a dataset")
    return ds


def _int(g: Any, name: str, where: str) -> int:
    ds = _dataset(g, name, where)
    a = np.asarray(ds[()]).reshape(-1)
    if a.size != 1 or a.dtype.kind not in "iu":
        raise FclibError(f"{where}: {ds.name} must be one integer, got {a.size} value(s) of type {a.dtype}")
    return int(a[0])


def _array(g: Any, name: str, where: str, kind: str) -> NDArray[Any]:
    ds = _dataset(g, name, where)
    a = np.asarray(ds[()])
    if a.dtype.kind not in ("iu" if kind == "int" else "iuf"):
        raise FclibError(f"{where}: {ds.name} has type {a.dtype}, expected {kind}")
    a = a.reshape(-1)
    return a.astype(np.int64) if kind == "int" else a.astype(np.float64)


def _string(g: Any, name: str) -> str | None:
    if name not in g:
        return None
    v = g[name][()]
    if isinstance(v, np.ndarray):
        v = v.reshape(-1)[0] if v.size else b""
    if isinstance(v, bytes):
        return v.split(b"\0", 1)[0].decode("utf-8", "replace")
    return str(v)


def _read_matrix(g: Any, where: str) -> tuple[Any, str]:
    """A sparse matrix group → (scipy CSC matrix, storage name)."""
    import scipy.sparse as sp  # type: ignore[import-untyped]

    gn = g.name
    m, n, nz, nzmax = (_int(g, k, where) for k in ("m", "n", "nz", "nzmax"))
    if m < 0 or n < 0:
        raise FclibError(f"{where}: {gn} has a negative size m = {m}, n = {n}")
    p = _array(g, "p", where, "int")
    i = _array(g, "i", where, "int")
    x = _array(g, "x", where, "float")
    if nz >= 0:
        storage = "triplet"
        for nm, a in (("p", p), ("i", i), ("x", x)):
            if a.size < nz:
                raise FclibError(f"{where}: {gn}/{nm} has {a.size} values, expected nz = {nz}")
        p, i, x = p[:nz], i[:nz], x[:nz]
        _check_index(p, m, f"{gn}/p", "row", where)
        _check_index(i, n, f"{gn}/i", "column", where)
        _check_finite(x, f"{gn}/x", where)
        return sp.coo_matrix((x, (p, i)), shape=(m, n)).tocsc(), storage
    if nz not in (-1, -2):
        raise FclibError(f"{where}: {gn}/nz = {nz}: expected ≥ 0 (triplet), −1 (CSC) or −2 (CSR)")
    storage = "csc" if nz == -1 else "csr"
    major, minor = (n, m) if nz == -1 else (m, n)
    if p.size != major + 1:
        raise FclibError(f"{where}: {gn}/p has {p.size} values, expected {major + 1} ({storage.upper()} pointers)")
    if p[0] != 0 or np.any(np.diff(p) < 0) or p[-1] > nzmax:
        raise FclibError(f"{where}: {gn}/p is not a pointer array (starts at 0, non-decreasing, ends ≤ nzmax = {nzmax})")
    used = int(p[-1])
    if i.size < used or x.size < used:
        raise FclibError(f"{where}: {gn}/i and {gn}/x have {i.size} and {x.size} values, the pointers use {used}")
    i, x = i[:used], x[:used]
    _check_index(i, minor, f"{gn}/i", "row" if nz == -1 else "column", where)
    _check_finite(x, f"{gn}/x", where)
    cls = sp.csc_matrix if nz == -1 else sp.csr_matrix
    mat = cls((x, i, p), shape=(m, n))
    mat.sum_duplicates()
    return mat.tocsc(), storage


def _check_index(a: NDArray[np.int64], bound: int, name: str, what: str, where: str) -> None:
    bad = (a < 0) | (a >= bound)
    if np.any(bad):
        j = int(np.argmax(bad))
        raise FclibError(f"{where}: {name}[{j}] = {a[j]} is out of range: {what} indices run 0 … {bound - 1}")


def _check_finite(x: NDArray[np.float64], name: str, where: str) -> None:
    if not np.all(np.isfinite(x)):
        j = int(np.argmax(~np.isfinite(x)))
        raise FclibError(f"{where}: {name}[{j}] = {x[j]!r} is not finite")


def _read_solution(g: Any, where: str) -> FclibSolution:
    opt = {k: _array(g, k, where, "float") if k in g else None for k in ("v", "l")}
    return FclibSolution(u=_array(g, "u", where, "float"), r=_array(g, "r", where, "float"), **opt)


def read_fclib(path: str | os.PathLike[str]) -> FclibLocal:
    """Reads an FCLib local problem (with its solution and guesses, if any)."""
    p = Path(path)
    where = str(p)
    kind = fclib_kind(p)
    if kind is None:
        if not p.is_file():
            raise FclibError(f"{where}: no such file")
        raise FclibError(f"{where}: not an FCLib file (no HDF5 group /fclib_local or /fclib_global)")
    if kind == "global":
        raise FclibError(
            f"{where}: /fclib_global: global problems (M, H, G, w, b) are not supported; "
            "lcpsim reads FCLib local problems (/fclib_local: W, q, mu)"
        )
    try:
        return _read_local(p, where)
    except (KeyError, RuntimeError, TypeError, OSError) as e:  # h5py on a damaged file
        raise FclibError(f"{where}: damaged FCLib file ({type(e).__name__}: {e})") from None


def _read_local(p: Path, where: str) -> FclibLocal:
    with open_hdf5(p, FclibError) as f:
        g = f["fclib_local"]
        spacedim = _int(g, "spacedim", where)
        if "W" not in g:
            raise FclibError(f"{where}: group /fclib_local/W is missing")
        W, storage = _read_matrix(g["W"], where)
        if "vectors" not in g:
            raise FclibError(f"{where}: group /fclib_local/vectors is missing")
        vec = g["vectors"]
        prob = FclibLocal(
            W=W,
            q=_array(vec, "q", where, "float"),
            mu=_array(vec, "mu", where, "float"),
            spacedim=spacedim,
            storage=storage,
            path=p,
        )
        if "V" in g or "R" in g:
            if "V" not in g or "R" not in g:
                raise FclibError(f"{where}: /fclib_local/V and /fclib_local/R must be given together")
            prob.V, _ = _read_matrix(g["V"], where)
            prob.R, _ = _read_matrix(g["R"], where)
            prob.s = _array(vec, "s", where, "float")
        if "info" in g:
            prob.title, prob.description, prob.math_info = (
                _string(g["info"], k) for k in ("title", "description", "math_info")
            )
        if "solution" in f:
            prob.solution = _read_solution(f["solution"], where)
        if "guesses" in f:
            count = _int(f["guesses"], "number_of_guesses", where)
            for j in range(count):
                if str(j + 1) not in f["guesses"]:
                    raise FclibError(f"{where}: group /guesses/{j + 1} is missing (number_of_guesses = {count})")
                prob.guesses.append(_read_solution(f["guesses"][str(j + 1)], where))
    return prob.validate(where)


# ---------------------------------------------------------------- writing


def _write_int(g: Any, name: str, v: int) -> None:
    g.create_dataset(name, data=np.array([v], dtype=np.int32))


def _write_string(g: Any, name: str, text: str) -> None:
    # libfclib reads strings as C strings of the dataset's size: store the terminator.
    b = text.encode("utf-8") + b"\0"
    g.create_dataset(name, data=np.array(b, dtype=f"S{len(b)}"))


def _write_matrix(g: Any, mat: Any, storage: str) -> None:
    import scipy.sparse as sp  # type: ignore[import-untyped]

    if storage not in STORAGES:
        raise ValueError(f"storage must be one of {', '.join(STORAGES)}, got {storage!r}")
    m, n = mat.shape
    if storage == "triplet":
        coo = sp.coo_matrix(mat)
        coo.sum_duplicates()
        p, i, x, nz, nzmax = coo.row, coo.col, coo.data, int(coo.nnz), int(coo.nnz)
    else:
        c = sp.csc_matrix(mat) if storage == "csc" else sp.csr_matrix(mat)
        c.sum_duplicates()
        p, i, x, nz, nzmax = c.indptr, c.indices, c.data, -1 if storage == "csc" else -2, int(c.nnz)
    for k, v in (("nzmax", nzmax), ("m", m), ("n", n), ("nz", nz)):
        _write_int(g, k, int(v))
    g.create_dataset("p", data=np.asarray(p, dtype=np.int32))
    g.create_dataset("i", data=np.asarray(i, dtype=np.int32))
    g.create_dataset("x", data=np.asarray(x, dtype=np.float64))


def _write_solution(g: Any, sol: FclibSolution) -> None:
    for k in ("v", "l", "u", "r"):
        a = getattr(sol, k)
        if a is not None:
            g.create_dataset(k, data=np.asarray(a, dtype=np.float64))


def as_sparse(W: ArrayLike | Any) -> Any:
    """``W`` as a scipy CSC matrix (dense arrays keep their exact zeros out)."""
    import scipy.sparse as sp  # type: ignore[import-untyped]

    if sp.issparse(W):
        return sp.csc_matrix(W, dtype=np.float64)
    return sp.csc_matrix(np.asarray(W, dtype=np.float64))


def write_fclib(path: str | os.PathLike[str], problem: FclibLocal, *, storage: str | None = None) -> Path:
    """Writes ``problem`` as an FCLib local problem (overwrites ``path``); W, V,
    R in ``storage`` (``"csc"`` — the one libfclib's merit function reads —,
    ``"csr"`` or ``"triplet"``; default the problem's own)."""
    problem.validate(str(path))
    storage = storage or problem.storage
    p = Path(path)
    with _h5py().File(p, "w") as f:
        g = f.create_group("fclib_local")
        _write_int(g, "spacedim", problem.spacedim)
        _write_matrix(g.create_group("W"), problem.W, storage)
        if problem.V is not None:
            _write_matrix(g.create_group("V"), as_sparse(problem.V), storage)
            _write_matrix(g.create_group("R"), as_sparse(problem.R), storage)
        vec = g.create_group("vectors")
        vec.create_dataset("q", data=problem.q)
        vec.create_dataset("mu", data=problem.mu)
        if problem.s is not None:
            vec.create_dataset("s", data=np.asarray(problem.s, dtype=np.float64))
        texts = {"title": problem.title, "description": problem.description, "math_info": problem.math_info}
        if any(v is not None for v in texts.values()):
            info = g.create_group("info")
            for k, v in texts.items():
                if v is not None:
                    _write_string(info, k, v)
        if problem.solution is not None:
            _write_solution(f.create_group("solution"), problem.solution)
        if problem.guesses:
            gg = f.create_group("guesses")
            _write_int(gg, "number_of_guesses", len(problem.guesses))
            for j, sol in enumerate(problem.guesses):
                _write_solution(gg.create_group(str(j + 1)), sol)
    return p
