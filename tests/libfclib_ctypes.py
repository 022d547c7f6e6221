"""libfclib (FCLib 3.1.0, Debian's libfclib-dev) through ctypes, run as a
separate process by tests/test_fclib_libfclib.py so that the C library's HDF5
never shares a process with h5py's (and its exit() on a failed HDF5 call
cannot take pytest down). No lcpsim, no h5py here.

    python libfclib_ctypes.py read FILE [--solution] [--guesses]
                                                 → JSON: every array libfclib reads, merit of solution/guesses
                                                   (say which exist: libfclib exits on a missing dataset)
    python libfclib_ctypes.py write FILE < JSON  → libfclib writes the problem (and solution, guesses)
"""

from __future__ import annotations

import ctypes as C
import ctypes.util
import json
import sys

LIB_NAMES = ("libfclib.so.0", "libfclib.so")


class Info(C.Structure):
    _fields_ = [("title", C.c_char_p), ("description", C.c_char_p), ("math_info", C.c_char_p)]


class MatrixInfo(C.Structure):
    _fields_ = [("comment", C.c_char_p), ("conditioning", C.c_double), ("determinant", C.c_double), ("rank", C.c_int)]


class Matrix(C.Structure):
    _fields_ = [
        ("nzmax", C.c_int), ("m", C.c_int), ("n", C.c_int),
        ("p", C.POINTER(C.c_int)), ("i", C.POINTER(C.c_int)), ("x", C.POINTER(C.c_double)),
        ("nz", C.c_int), ("info", C.POINTER(MatrixInfo)),
    ]


class Local(C.Structure):
    _fields_ = [
        ("W", C.POINTER(Matrix)), ("V", C.POINTER(Matrix)), ("R", C.POINTER(Matrix)),
        ("mu", C.POINTER(C.c_double)), ("q", C.POINTER(C.c_double)), ("s", C.POINTER(C.c_double)),
        ("spacedim", C.c_int), ("info", C.POINTER(Info)),
    ]


class Solution(C.Structure):
    _fields_ = [(k, C.POINTER(C.c_double)) for k in ("v", "u", "r", "l")]


def load() -> C.CDLL | None:
    for name in LIB_NAMES + ((ctypes.util.find_library("fclib") or ""),):
        if not name:
            continue
        try:
            lib = C.CDLL(name)
        except OSError:
            continue
        lib.fclib_read_local.restype = C.POINTER(Local)
        lib.fclib_read_local.argtypes = [C.c_char_p]
        lib.fclib_read_solution.restype = C.POINTER(Solution)
        lib.fclib_read_solution.argtypes = [C.c_char_p]
        lib.fclib_read_guesses.restype = C.POINTER(Solution)
        lib.fclib_read_guesses.argtypes = [C.c_char_p, C.POINTER(C.c_int)]
        lib.fclib_merit_local.restype = C.c_double
        lib.fclib_merit_local.argtypes = [C.POINTER(Local), C.c_int, C.POINTER(Solution)]
        lib.fclib_write_local.restype = C.c_int
        lib.fclib_write_local.argtypes = [C.POINTER(Local), C.c_char_p]
        lib.fclib_write_solution.restype = C.c_int
        lib.fclib_write_solution.argtypes = [C.POINTER(Solution), C.c_char_p]
        lib.fclib_write_guesses.restype = C.c_int
        lib.fclib_write_guesses.argtypes = [C.c_int, C.POINTER(Solution), C.c_char_p]
        return lib
    return None


def _arr(ptr: object, n: int) -> list:
    return [ptr[j] for j in range(n)]  # type: ignore[index]


def _matrix(mp: object) -> dict:
    m = mp.contents  # type: ignore[attr-defined]
    if m.nz >= 0:
        np_, ni, nx = m.nz, m.nz, m.nzmax
    else:
        np_ = (m.n if m.nz == -1 else m.m) + 1
        ni = nx = m.nzmax
    return {"nzmax": m.nzmax, "m": m.m, "n": m.n, "nz": m.nz, "p": _arr(m.p, np_), "i": _arr(m.i, ni), "x": _arr(m.x, nx)}


def _solution(s: Solution, nr: int) -> dict:
    return {"u": _arr(s.u, nr), "r": _arr(s.r, nr)}


def read(path: str, solution: bool, guesses: bool) -> dict:
    lib = load()
    p = lib.fclib_read_local(path.encode())
    if not p:
        raise SystemExit("fclib_read_local returned NULL")
    loc = p.contents
    W = _matrix(loc.W)
    nr = W["m"]
    out = {
        "spacedim": loc.spacedim, "W": W, "q": _arr(loc.q, nr), "mu": _arr(loc.mu, nr // loc.spacedim),
        "info": None, "solution": None, "guesses": [],
    }
    if loc.info:
        out["info"] = {k: (getattr(loc.info.contents, k) or b"").decode() for k in ("title", "description", "math_info")}
    if solution:
        s = lib.fclib_read_solution(path.encode())
        out["solution"] = _solution(s.contents, nr)
        out["solution_merit"] = lib.fclib_merit_local(p, 0, s)
    if guesses:
        count = C.c_int(0)
        g = lib.fclib_read_guesses(path.encode(), C.byref(count))
        out["guesses"] = [_solution(g[j], nr) for j in range(count.value)]
        out["guess_merits"] = [lib.fclib_merit_local(p, 0, C.pointer(g[j])) for j in range(count.value)]
    return out


def _c_matrix(d: dict, keep: list) -> C.POINTER(Matrix):  # type: ignore[valid-type]
    p = (C.c_int * len(d["p"]))(*d["p"])
    i = (C.c_int * len(d["i"]))(*d["i"])
    x = (C.c_double * len(d["x"]))(*d["x"])
    keep += [p, i, x]
    m = Matrix(nzmax=d["nzmax"], m=d["m"], n=d["n"], p=p, i=i, x=x, nz=d["nz"], info=None)
    keep.append(m)
    return C.pointer(m)


def _c_solution(d: dict, keep: list) -> Solution:
    u = (C.c_double * len(d["u"]))(*d["u"])
    r = (C.c_double * len(d["r"]))(*d["r"])
    keep += [u, r]
    return Solution(v=None, u=u, r=r, l=None)


def write(path: str, d: dict) -> None:
    lib = load()
    keep: list = []
    q = (C.c_double * len(d["q"]))(*d["q"])
    mu = (C.c_double * len(d["mu"]))(*d["mu"])
    info = Info(*(d["info"][k].encode() for k in ("title", "description", "math_info"))) if d.get("info") else None
    loc = Local(W=_c_matrix(d["W"], keep), V=None, R=None, mu=mu, q=q, s=None, spacedim=d["spacedim"],
                info=C.pointer(info) if info else None)
    if lib.fclib_write_local(C.byref(loc), path.encode()) != 1:
        raise SystemExit("fclib_write_local failed")
    if d.get("solution"):
        if lib.fclib_write_solution(C.byref(_c_solution(d["solution"], keep)), path.encode()) != 1:
            raise SystemExit("fclib_write_solution failed")
    if d.get("guesses"):
        arr = (Solution * len(d["guesses"]))(*(_c_solution(g, keep) for g in d["guesses"]))
        if lib.fclib_write_guesses(len(d["guesses"]), arr, path.encode()) != 1:
            raise SystemExit("fclib_write_guesses failed")


if __name__ == "__main__":
    if sys.argv[1] == "available":
        print(json.dumps(load() is not None))
    elif sys.argv[1] == "read":
        print(json.dumps(read(sys.argv[2], "--solution" in sys.argv, "--guesses" in sys.argv)))
    else:
        write(sys.argv[2], json.load(sys.stdin))
