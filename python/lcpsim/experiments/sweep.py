"""Sweeps: experiment cases mapped over a Dask cluster, resumable.

A sweep config (YAML or JSON) lists a grid of cases::

    experiment: slope                 # one of lcpsim.experiments.EXPERIMENTS
    base: {seconds: 1.0, mu: 1.0}     # config shared by every case
    grid:                             # the Cartesian product of these lists
      angle_deg: [45.0001, 45.2]
      scale: [none, 1.0e-3, 1.0e-6]
      solver: [classic, robust]
    seeds: [0]                        # optional: one case per seed
    output: slope_sweep.h5            # .h5 (HDF5) or .parquet (a directory)

or several such blocks under ``cases:`` (each with its ``experiment``,
``base``, ``grid``, ``seeds``) sharing one ``output``.

Every case is ``{"id", "experiment", "config"}``; its id is the experiment
plus a hash of its full config (defaults filled in), so the same case always
has the same id. :func:`run_sweep` submits every case not yet in the output
to the cluster — an embedded ``LocalCluster`` by default, or an existing
scheduler (``scheduler="tcp://…"``) — and appends each result as it arrives,
flushed at once. Results are written by the client only, so a worker killed
mid-case loses nothing finished (Dask reruns its running case elsewhere), and
a sweep interrupted at any point resumes where it stopped: run it again with
the same config and only the missing cases run.

Output formats:

* **HDF5** (``.h5``, the default): the records as JSON in one growing byte
  dataset with an offset/length index, written in single-writer /
  multiple-reader mode and flushed after every record, so a killed sweep
  leaves a readable file holding every record up to the last flush.
* **Parquet** (``.parquet``, needs ``pyarrow``): a directory with one small
  file per case (``id``, ``experiment``, ``json`` columns), each written to a
  temporary name and renamed, so a file exists only when complete.

:func:`load_results` reads either back as a list of records.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import os
import sys
import time
from pathlib import Path
from typing import IO, Any, Callable, Iterable, Mapping

import numpy as np

from ._common import jsonable, merge_config

__all__ = [
    "load_config",
    "expand_cases",
    "case_id",
    "run_case",
    "run_sweep",
    "ResultStore",
    "load_results",
    "summary_text",
]


# ---------------------------------------------------------------- config


def load_config(path: str | os.PathLike[str]) -> dict[str, Any]:
    """A sweep config from YAML (``.yaml``/``.yml``) or JSON; relative ``output`` paths are
    taken relative to the config file."""
    p = Path(path)
    text = p.read_text()
    if p.suffix.lower() in (".yaml", ".yml"):
        import yaml  # type: ignore[import-untyped]

        try:
            cfg = yaml.safe_load(text)
        except yaml.YAMLError as e:
            raise ValueError(f"{path}: not valid YAML ({' '.join(str(e).split())})") from None
    else:
        try:
            cfg = json.loads(text)
        except json.JSONDecodeError as e:
            raise ValueError(f"{path}: not valid JSON ({e})") from None
    if not isinstance(cfg, dict):
        raise ValueError(f"{path}: a sweep config must be a mapping, got {type(cfg).__name__}")
    out = cfg.get("output")
    if out and not os.path.isabs(out):
        cfg["output"] = str(p.parent / out)
    return cfg


def _yaml_number(v: Any) -> Any:
    """YAML reads 1e-3 (no dot) as a string: numbers written so become floats
    (lists too); other strings ("none", "dt", "classic", …) stay."""
    if isinstance(v, list):
        return [_yaml_number(x) for x in v]
    if isinstance(v, str):
        try:
            return float(v)
        except ValueError:
            return v
    return v


def case_id(experiment: str, config: Mapping[str, Any]) -> str:
    """A stable id: ``experiment-<16 hex digits of the config's hash>``."""
    blob = json.dumps({"experiment": experiment, "config": jsonable(dict(config))}, sort_keys=True)
    return f"{experiment}-{hashlib.sha1(blob.encode()).hexdigest()[:16]}"


def expand_cases(cfg: Mapping[str, Any]) -> list[dict[str, Any]]:
    """The cases of a sweep config, each ``{"id", "experiment", "config"}`` with the
    experiment's defaults filled in (an unknown experiment or key is a ValueError)."""
    from . import DEFAULTS, experiment_name

    blocks = cfg.get("cases")
    if blocks is None:
        blocks = [cfg]
    if not isinstance(blocks, list) or not blocks:
        raise ValueError("sweep: 'cases' must be a non-empty list of {experiment, base, grid} blocks")
    cases: list[dict[str, Any]] = []
    seen: set[str] = set()
    for block in blocks:
        if not isinstance(block, Mapping) or "experiment" not in block:
            raise ValueError("sweep: every case block needs an 'experiment'")
        exp = experiment_name(block["experiment"])
        unknown = set(block) - {"experiment", "base", "grid", "seeds", "output", "cases"}
        if unknown:
            raise ValueError(f"sweep: unknown key(s) {sorted(unknown)} in a case block")
        base = dict(block.get("base") or {})
        grid = dict(block.get("grid") or {})
        for k, v in grid.items():
            if not isinstance(v, list) or not v:
                raise ValueError(f"sweep: grid entry {k!r} must be a non-empty list, got {v!r}")
        seeds = block.get("seeds")
        if seeds is None:
            seeds = [base.get("seed", 0)]
        keys = list(grid)
        for values in itertools.product(*(grid[k] for k in keys)):
            for seed in seeds:
                c = {k: _yaml_number(v) if k != "solver" else v for k, v in {**base, **dict(zip(keys, values))}.items()}
                c["seed"] = int(seed)
                full = merge_config(exp, DEFAULTS[exp], c)
                check_case(exp, full)
                cid = case_id(exp, full)
                if cid in seen:
                    continue
                seen.add(cid)
                cases.append({"id": cid, "experiment": exp, "config": jsonable(full)})
    return cases


# Config keys whose values are integers (the others of numeric default are reals).
_INT_KEYS = {"seed", "friction_dirs", "threads", "max_lcps", "max_listed", "certify_max_n", "count"}


def _check_value(key: str, value: Any, default: Any) -> None:
    """``value`` of the kind of ``default`` (None: anything); a ValueError says which kind."""
    if default is None or value is None and key in ("max_lcps", "certify", "solvers"):
        return
    if isinstance(default, bool):
        ok = isinstance(value, bool)
        kind = "true or false"
    elif isinstance(default, (int, float)):
        real = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
        ok = real and (not (key in _INT_KEYS) or float(value).is_integer())
        kind = "an integer" if key in _INT_KEYS else "a finite number"
    elif isinstance(default, str):
        ok, kind = isinstance(value, str), "a string"
    elif isinstance(default, Mapping):
        ok, kind = isinstance(value, Mapping), "a mapping"
    elif isinstance(default, list):
        ok, kind = isinstance(value, (list, str)), "a list"
    else:
        return
    if not ok:
        raise ValueError(f"must be {kind}")


def check_case(experiment: str, config: Mapping[str, Any]) -> None:
    """Checks every value of one case's config before anything runs: numbers
    where the default is a number (integers for counts and seeds), booleans,
    strings, solvers (``solver``, ``solvers``) and cone scales (``scale``,
    ``scales``) that parse. A ValueError names the experiment, key and value."""
    from .. import scale as cone
    from . import DEFAULTS
    from .presets import parse_solver

    for key, value in config.items():
        try:
            if key == "solver":
                parse_solver(value)
            elif key == "solvers" and value is not None:
                for spec in value.split(",") if isinstance(value, str) else value:
                    parse_solver(spec)
            elif key == "scale":
                cone.parse_cone_scale(value)
            elif key == "scales":
                cone.parse_cone_scales(value)
            else:
                _check_value(key, value, DEFAULTS[experiment].get(key))
        except (TypeError, ValueError) as e:
            raise ValueError(f"sweep: {experiment}: {key} = {value!r}: {' '.join(str(e).split())}") from None


def run_case(case: Mapping[str, Any]) -> dict[str, Any]:
    """Runs one case (a plain function: this is what the Dask workers execute)."""
    import socket

    from . import run_experiment

    t0 = time.perf_counter()
    result = run_experiment(case["experiment"], case["config"])
    return {
        "id": case["id"],
        "experiment": case["experiment"],
        "config": case["config"],
        "result": jsonable(result),
        "worker": f"{socket.gethostname()}:{os.getpid()}",
        "seconds": time.perf_counter() - t0,
    }


# ---------------------------------------------------------------- storage


class ResultStore:
    """Append-only result records (see the module docs for the two formats)."""

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = Path(path)
        self.kind = "parquet" if self.path.suffix.lower() == ".parquet" else "hdf5"
        self._f: Any = None
        if self.kind == "parquet":
            try:
                import pyarrow  # type: ignore[import-untyped, import-not-found]  # noqa: F401
            except ImportError:
                raise ValueError(f"{path}: Parquet output needs pyarrow (pip install pyarrow); use a .h5 file") from None
            self.path.mkdir(parents=True, exist_ok=True)
        else:
            self._open_hdf5()

    # -- HDF5

    def _open_hdf5(self) -> None:
        import h5py  # type: ignore[import-untyped]

        if self.path.exists():
            try:
                f = h5py.File(self.path, "a", libver="latest")
            except OSError:
                # A writer died with the file open: copy what is readable to a fresh file.
                records = _read_hdf5(self.path)
                tmp = self.path.with_name(self.path.name + ".recovered")
                self._create_hdf5(tmp, records)
                os.replace(tmp, self.path)
                f = h5py.File(self.path, "a", libver="latest")
        else:
            self._create_hdf5(self.path, [])
            f = h5py.File(self.path, "a", libver="latest")
        if f.attrs.get("format") != "lcpsim-sweep":
            f.close()
            raise ValueError(f"{self.path}: not an lcpsim sweep results file")
        # Trim a partly written last record, then write in SWMR mode.
        n = min(f["offset"].shape[0], f["length"].shape[0])
        f["offset"].resize((n,))
        f["length"].resize((n,))
        end = int(f["offset"][n - 1] + f["length"][n - 1]) if n else 0
        f["json"].resize((end,))
        f.swmr_mode = True
        self._f = f

    @staticmethod
    def _create_hdf5(path: Path, records: list[dict[str, Any]]) -> None:
        import h5py

        from .. import __version__

        with h5py.File(path, "w", libver="latest") as f:
            f.attrs["format"] = "lcpsim-sweep"
            f.attrs["format_version"] = 1
            f.attrs["lcpsim_version"] = __version__
            f.create_dataset("json", shape=(0,), maxshape=(None,), chunks=(1 << 14,), dtype="u1")
            f.create_dataset("offset", shape=(0,), maxshape=(None,), chunks=(1024,), dtype="i8")
            f.create_dataset("length", shape=(0,), maxshape=(None,), chunks=(1024,), dtype="i8")
            for r in records:
                _append_hdf5(f, r)

    # -- both

    def ids(self) -> set[str]:
        return {r["id"] for r in self.records()}

    def records(self) -> list[dict[str, Any]]:
        if self.kind == "parquet":
            return _read_parquet(self.path)
        assert self._f is not None
        return _records_from(self._f)

    def append(self, record: Mapping[str, Any]) -> None:
        if self.kind == "parquet":
            _write_parquet_part(self.path, record)
            return
        assert self._f is not None
        _append_hdf5(self._f, record)
        self._f.flush()

    def close(self) -> None:
        if self._f is not None:
            self._f.close()
            self._f = None

    def __enter__(self) -> "ResultStore":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


def _append_hdf5(f: Any, record: Mapping[str, Any]) -> None:
    blob = np.frombuffer(json.dumps(jsonable(dict(record))).encode(), dtype=np.uint8)
    js, off, ln = f["json"], f["offset"], f["length"]
    start = js.shape[0]
    js.resize((start + blob.size,))
    js[start:] = blob
    n = off.shape[0]
    off.resize((n + 1,))
    off[n] = start
    ln.resize((n + 1,))
    ln[n] = blob.size  # written last: a record counts once its length is there


def _records_from(f: Any) -> list[dict[str, Any]]:
    n = min(f["offset"].shape[0], f["length"].shape[0])
    if n == 0:
        return []
    off = f["offset"][:n]
    ln = f["length"][:n]
    data = f["json"][()].tobytes()
    out = []
    for o, k in zip(off, ln):
        chunk = data[int(o) : int(o) + int(k)]
        if len(chunk) < int(k):
            break
        try:
            out.append(json.loads(chunk.decode()))
        except ValueError:
            break
    return out


def _read_hdf5(path: Path) -> list[dict[str, Any]]:
    import h5py

    try:
        f = h5py.File(path, "r", libver="latest", swmr=True)
    except OSError:
        f = h5py.File(path, "r")
    with f:
        return _records_from(f)


def _write_parquet_part(directory: Path, record: Mapping[str, Any]) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq  # type: ignore[import-untyped, import-not-found]

    table = pa.table(
        {"id": [record["id"]], "experiment": [record["experiment"]], "json": [json.dumps(jsonable(dict(record)))]}
    )
    final = directory / f"{record['id']}.parquet"
    tmp = directory / f".{record['id']}.parquet.tmp"
    pq.write_table(table, tmp)
    os.replace(tmp, final)


def _read_parquet(directory: Path) -> list[dict[str, Any]]:
    import pyarrow.parquet as pq

    out: list[dict[str, Any]] = []
    for p in sorted(directory.glob("*.parquet")):
        t = pq.read_table(p)
        out.extend(json.loads(s) for s in t.column("json").to_pylist())
    return out


def load_results(path: str | os.PathLike[str]) -> list[dict[str, Any]]:
    """Every record of a sweep output (HDF5 file or Parquet directory), in the order written."""
    p = Path(path)
    if not p.exists():
        raise FileNotFoundError(f"{path}: no such file")
    if p.suffix.lower() == ".parquet":
        return _read_parquet(p)
    return _read_hdf5(p)


# ---------------------------------------------------------------- running


class _Progress:
    def __init__(self, stream: IO[str] | None, total: int, done: int) -> None:
        self.stream = stream
        self.total = total
        self.done = done
        self.start_done = done
        self.t0 = time.perf_counter()
        self.tty = bool(stream is not None and hasattr(stream, "isatty") and stream.isatty())

    def update(self, last: str = "") -> None:
        if self.stream is None:
            return
        el = time.perf_counter() - self.t0
        new = self.done - self.start_done
        left = self.total - self.done
        eta = f", ~{el / new * left:.0f} s left" if new and left else ""
        width = 30
        fill = int(width * self.done / max(self.total, 1))
        line = f"[{'#' * fill}{'.' * (width - fill)}] {self.done}/{self.total} cases, {el:.1f} s{eta}"
        if self.tty:
            self.stream.write("\r" + line + " " * 8)
        else:
            self.stream.write(line + (f"  {last}" if last else "") + "\n")
        self.stream.flush()

    def close(self) -> None:
        if self.stream is not None and self.tty:
            self.stream.write("\n")
            self.stream.flush()


def run_sweep(
    cfg: Mapping[str, Any],
    *,
    output: str | os.PathLike[str] | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    processes: bool = True,
    progress: IO[str] | None = sys.stderr,
    stop_after: int | None = None,
    on_result: Callable[[dict[str, Any], Any], None] | None = None,
) -> dict[str, Any]:
    """Runs every case of ``cfg`` not yet in the output; returns a summary
    ``{"output", "cases", "done_before", "ran", "failed", "errors", "wall_time_s"}``.

    ``scheduler``: address of an existing Dask scheduler, else a local cluster
    of ``workers`` processes (``processes=False``: threads in this process).
    ``stop_after``: stop after that many new results (for tests: an interrupted
    sweep). ``on_result(record, client)`` is called after each record is stored.
    """
    import importlib

    distributed: Any = importlib.import_module("dask.distributed")  # untyped
    Client, LocalCluster, as_completed = distributed.Client, distributed.LocalCluster, distributed.as_completed

    t0 = time.perf_counter()
    out = output or cfg.get("output")
    if not out:
        raise ValueError("sweep: no output file (give 'output' in the config or --output)")
    cases = expand_cases(cfg)
    errors: list[dict[str, Any]] = []
    with ResultStore(out) as store:
        done = store.ids()
        pending = [c for c in cases if c["id"] not in done]
        before = len(cases) - len(pending)
        bar = _Progress(progress, len(cases), before)
        ran = 0
        if pending and (stop_after is None or stop_after > 0):
            import logging

            cluster = None
            if scheduler:
                client = Client(scheduler)
            else:
                n = workers or os.cpu_count() or 1
                cluster = LocalCluster(
                    n_workers=n, threads_per_worker=1, processes=processes, dashboard_address=None,
                    silence_logs=logging.ERROR,
                )
                client = Client(cluster)
            try:
                bar.update()
                futures = client.map(run_case, pending, key=[f"lcpsim-{c['id']}" for c in pending], pure=False)
                ac = as_completed(futures, with_results=False)
                for fut in ac:
                    try:
                        rec = fut.result()
                    except Exception as e:  # the case raised: report it, keep going
                        errors.append({"key": str(fut.key), "error": f"{type(e).__name__}: {e}"})
                        continue
                    store.append(rec)
                    ran += 1
                    bar.done += 1
                    bar.update(rec["id"])
                    if on_result is not None:
                        on_result(rec, client)
                    if stop_after is not None and ran >= stop_after:
                        for f in futures:
                            f.cancel()
                        break
            finally:
                client.close()
                if cluster is not None:
                    cluster.close()
        bar.close()
        total = len(store.ids() & {c["id"] for c in cases})
    return {
        "output": str(out),
        "cases": len(cases),
        "case_ids": [c["id"] for c in cases],
        "done_before": before,
        "ran": ran,
        "complete": total == len(cases),
        "finished": total,
        "failed": len(errors),
        "errors": errors,
        "wall_time_s": time.perf_counter() - t0,
    }


_SUMMARY_KEYS = {
    "slope": ("outcome", "slide_distance_m", "tilt_deg", "lcp_failures"),
    "push": ("outcome", "friction_force_N", "lambda_max"),
    "critical-scale": ("critical_scale", "bracket"),
    "invariance": ("lcps", "max_abs_dfn", "max_abs_dfd", "max_rel_lambda_err"),
    "patterns": ("lcps", "changed", "impossible"),
    "failure-rate": ("rows",),
}


def summary_text(summary: Mapping[str, Any], records: Iterable[Mapping[str, Any]] | None = None) -> str:
    """A short text summary of a sweep and its results."""
    recs = list(records) if records is not None else load_results(summary["output"])
    order = {cid: i for i, cid in enumerate(summary.get("case_ids", []))}
    recs.sort(key=lambda r: order.get(r["id"], len(order)))
    lines = [
        f"sweep: {summary['finished']}/{summary['cases']} cases in {summary['output']} "
        f"({summary['done_before']} already there, {summary['ran']} run now, {summary['failed']} failed) "
        f"in {summary['wall_time_s']:.1f} s"
    ]
    for e in summary.get("errors", []):
        lines.append(f"  error {e['key']}: {e['error']}")
    for r in recs:
        res = r["result"]
        keys = _SUMMARY_KEYS.get(r["experiment"], ())
        cfg = r["config"]
        varied = ", ".join(f"{k}={cfg[k]}" for k in ("angle_deg", "force", "scale", "scales", "solver", "seed") if k in cfg)
        vals = []
        for k in keys:
            v = res.get(k)
            if k == "rows":
                v = "; ".join(f"s={row['scale']}: {100 * row['rate']:.2f}%" for row in v)
            elif isinstance(v, float):
                v = f"{v:.4g}"
            vals.append(f"{k}={v}")
        lines.append(f"  {r['id']}  {varied}  →  {', '.join(vals)}")
    return "\n".join(lines)
