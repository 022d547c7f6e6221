#!/usr/bin/env python3
"""Fuzzes lcpsim's file readers on damaged files for a fixed time.

The readers — ``lcpsim.io.load_lcp`` (``.npz``, HDF5, capture, dump),
``open_capture`` (and reading every record), ``load_dump``,
``load_trajectory`` (``Trajectory.load``: the viewer's files), ``read_fclib`` (FCLib files) — are given
mutations (bit flips, overwritten runs, truncations, spliced bytes) of small
valid files of each kind. A reader must return or raise a clean error (a
``ValueError`` such as ``LcpFileError``/``CaptureError``, or an ``OSError``)
within ``--timeout`` seconds. Anything else is a finding, saved under
``--out`` with the reader's name: another exception (``*.exception``), a
crash of the interpreter (``*.crash``), or a hang (``*.hang``).

The inputs run in a worker process that the driver restarts after a crash
or a hang, so HDF5's C library cannot take the fuzzer down with it.

    python3 scripts/fuzz_readers.py --seconds 180 [--out fuzz/artifacts/readers] [--readers read_fclib,...]

``--readers`` fuzzes only the named readers (default: all of them), so that
one reader can be given a run of its own. ``read_fclib`` is given mutations of
the valid FCLib file three times in four (its other inputs are the other valid files).

A reader added later joins by one entry in ``_readers`` (name → function
of a path) and one valid file in ``_valid_files``.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time
import traceback
from pathlib import Path
from typing import Any, Callable

CLEAN = (ValueError, OSError)


def _read_capture(path: str) -> None:
    from lcpsim import open_capture

    with open_capture(path) as c:
        for rec in c:
            rec.unscaled()


def _readers() -> dict[str, Callable[[str], Any]]:
    from lcpsim.io import load_dump, load_lcp
    from lcpsim import Trajectory

    readers: dict[str, Callable[[str], Any]] = {
        "load_lcp": load_lcp,
        "load_lcp_index0": lambda p: load_lcp(p, 0),
        "open_capture": _read_capture,
        "load_dump": load_dump,
        "load_trajectory": Trajectory.load,
    }
    from lcpsim.io.fclib import read_fclib

    readers["read_fclib"] = read_fclib
    return readers


def _valid_files(directory: Path) -> list[Path]:
    """Small valid files of every kind the readers read."""
    import numpy as np

    from lcpsim import solve_lcp
    from lcpsim.io import save_lcp
    from lcpsim.io.capture import CaptureWriter

    M = np.array([[2.0, 1.0], [1.0, 2.0]])
    q = np.array([-1.0, -1.0])
    valid = [save_lcp(directory / "p.npz", M, q), save_lcp(directory / "p.h5", M, q)]
    with CaptureWriter(directory / "c.h5", {"scene": "fuzz"}) as w:
        for s in (1.0, 1e-3):
            w.add(M * s, q, np.array([1 / 3, 1 / 3]), np.zeros(2), scale=s, contacts=0)
    valid.append(directory / "c.h5")
    res = solve_lcp(-np.eye(2), q, dump=str(directory / "dumps"))
    valid.append(Path(res.dump_path))
    from lcpsim import scenes

    traj = scenes.resting_cube().world.run(3, record_contacts=True)
    valid.append(Path(traj.save(directory / "t.h5")))
    s = scenes.resting_cube(friction_dirs=4)
    s.world.run(2, fclib=directory / "fclib")
    valid.extend(sorted((directory / "fclib").glob("*.hdf5"))[:1])
    return valid


def _mutate(data: bytes, rng: random.Random) -> bytes:
    b = bytearray(data)
    for _ in range(rng.choice([1, 1, 2, 4, 16])):
        kind = rng.randrange(6)
        i = rng.randrange(len(b)) if b else 0
        if kind == 0 and b:  # bit flip
            b[i] ^= 1 << rng.randrange(8)
        elif kind == 1 and b:  # an interesting byte
            b[i] = rng.choice([0, 1, 0x7F, 0x80, 0xFF])
        elif kind == 2:  # overwrite a run
            n = rng.randrange(1, 64)
            b[i : i + n] = bytes(rng.choice([0, 0xFF, rng.randrange(256)]) for _ in range(n))
        elif kind == 3:  # truncate
            del b[rng.randrange(len(b) + 1) :]
        elif kind == 4:  # splice random bytes in
            b[i:i] = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 32)))
        elif b:  # copy a block elsewhere
            j, n = rng.randrange(len(b)), rng.randrange(1, 256)
            b[i : i + n] = b[j : j + n]
    return bytes(b)


def worker(valid_dir: str, state_dir: str, seed: int, only: str) -> None:
    """Runs inputs forever; before each one writes it to ``state_dir/current``."""
    readers = _readers()
    if only:
        readers = {k: readers[k] for k in only.split(",")}
    files = sorted(p for p in Path(valid_dir).iterdir() if p.is_file())
    valid = [p.read_bytes() for p in files]
    fclib_valid = [p.read_bytes() for p in files if p.suffix == ".hdf5"]
    rng = random.Random(seed)
    state = Path(state_dir)
    target = state / "input.bin"
    n = 0
    while True:
        name = rng.choice(sorted(readers))
        pool = fclib_valid if name == "read_fclib" and fclib_valid and rng.random() < 0.75 else valid
        data = _mutate(rng.choice(pool), rng)
        suffix = rng.choice([".npz", ".h5", ".bin"])
        path = target.with_suffix(suffix)
        path.write_bytes(data)
        (state / "current").write_text(json.dumps({"reader": name, "path": str(path), "n": n}))
        try:
            readers[name](str(path))
        except CLEAN:
            pass
        except Exception:  # a finding: not a clean error
            digest = abs(hash(data)) % 10**12
            out = state / "findings" / f"{name}-{digest}{suffix}"
            out.parent.mkdir(exist_ok=True)
            out.write_bytes(data)
            out.with_name(out.name + ".exception").write_text(traceback.format_exc())
        n += 1
        if n % 50 == 0:
            (state / "count").write_text(str(n))


def drive(seconds: float, timeout: float, out: Path, only: str = "") -> dict[str, Any]:
    out.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix="lcpsim-fuzz-readers-"))
    valid_dir, state = work / "valid", work / "state"
    valid_dir.mkdir()
    state.mkdir()
    (work / "make").mkdir()
    for p in _valid_files(work / "make"):
        shutil.copy(p, valid_dir / p.name)
    deadline = time.monotonic() + seconds
    total, crashes, hangs, restarts = 0, 0, 0, 0
    while time.monotonic() < deadline:
        (state / "count").write_text("0")
        proc = subprocess.Popen(
            [sys.executable, __file__, "--worker", str(valid_dir), str(state), str(restarts), only],
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
        )
        last, last_change = None, time.monotonic()
        while time.monotonic() < deadline and proc.poll() is None:
            time.sleep(0.2)
            cur = (state / "current").read_text() if (state / "current").exists() else None
            if cur != last:
                last, last_change = cur, time.monotonic()
            elif time.monotonic() - last_change > timeout:
                proc.kill()
                hangs += 1
                _keep(state, out, "hang")
                break
        else:
            if proc.poll() is None:
                proc.kill()
            elif proc.returncode != 0:
                crashes += 1
                _keep(state, out, "crash")
        proc.wait()
        total += int((state / "count").read_text() or 0)
        restarts += 1
    findings = sorted((state / "findings").glob("*.exception")) if (state / "findings").exists() else []
    for f in (state / "findings").glob("*") if (state / "findings").exists() else []:
        shutil.copy(f, out / f.name)
    shutil.rmtree(work, ignore_errors=True)
    return {"readers": only or "all", "inputs": total, "seconds": seconds, "exceptions": len(findings), "crashes": crashes, "hangs": hangs,
            "worker_restarts": restarts - 1, "artifacts": str(out)}


def _keep(state: Path, out: Path, kind: str) -> None:
    cur = json.loads((state / "current").read_text())
    src = Path(cur["path"])
    if src.exists():
        dst = out / f"{cur['reader']}-{kind}-{int(time.time())}{src.suffix}"
        shutil.copy(src, dst)
        dst.with_name(dst.name + f".{kind}").write_text(json.dumps(cur))


def main() -> int:
    if len(sys.argv) > 1 and sys.argv[1] == "--worker":
        worker(sys.argv[2], sys.argv[3], int(sys.argv[4]), sys.argv[5] if len(sys.argv) > 5 else "")
        return 0
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=180.0)
    ap.add_argument("--timeout", type=float, default=10.0, help="seconds one input may take (default 10)")
    ap.add_argument("--out", default="fuzz/artifacts/readers")
    ap.add_argument("--readers", default="", help="comma-separated reader names (default: all)")
    args = ap.parse_args()
    if args.readers:
        unknown = set(args.readers.split(",")) - set(_readers())
        if unknown:
            ap.error(f"unknown readers: {', '.join(sorted(unknown))} (known: {', '.join(sorted(_readers()))})")
    summary = drive(args.seconds, args.timeout, Path(args.out), args.readers)
    print(json.dumps(summary))
    return 1 if summary["exceptions"] or summary["crashes"] or summary["hangs"] else 0


if __name__ == "__main__":
    sys.exit(main())
