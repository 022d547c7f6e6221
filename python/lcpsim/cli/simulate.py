"""``lcpsim simulate SCENE``: run one of the test scenes and summarize it.

::

    lcpsim simulate cube_on_slope --angle-deg 45.2 --mu 1 --steps 2000 --scale dt --pivoting classic
    lcpsim simulate box_stack --n 10 --capture stack.h5 --json
    lcpsim simulate scene.xml --steps 1000      # an MJCF model (pip install lcpsim[mjcf])

Scene parameters are options (``--angle-deg``, ``--mu``, ``--force``, ``--n``
…; ``lcpsim simulate --help`` lists them, each scene uses its own); any other
world argument can be given as ``--set NAME=VALUE`` (e.g. ``--set erp=0.1``).
Exit codes: 0 every LCP solved, 1 some LCP was not solved, 2 invalid input.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

import numpy as np

from .command import EXIT_NOT_SOLVED, EXIT_OK, CliError, Command, lemke_options, register_command
from .. import _core
from ..lcp import METHODS, PIVOTINGS
from ..scale import cone_scale_argument
from ..scenes import SCENES, Scene, scene_parameters
from ..world import Trajectory, World

__all__ = ["simulate_summary", "add_run_arguments", "build_scene"]

# Scene parameters as options: the union over all scenes; type from the default.
_INT_PARAMS = {"n", "nx", "ny", "nz", "seed"}
_STR_PARAMS = {"downhill"}
_BOOL_PARAMS = {"walls"}


def _all_scene_params() -> dict[str, set[str]]:
    out: dict[str, set[str]] = {}
    for name in SCENES:
        for p in scene_parameters(name):
            out.setdefault(p, set()).add(name)
    return out


def _configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("scene", type=_scene_or_xml, metavar="SCENE", help=f"one of: {', '.join(SCENES)}; or an MJCF file (FILE.xml)")
    add_run_arguments(p)
    p.add_argument("--capture", metavar="FILE", default=None, help="stream every LCP solved to this HDF5 capture")
    p.add_argument("--overwrite", action="store_true", help="replace an existing capture FILE (default: refuse it)")
    p.add_argument("--fclib", metavar="DIR", default=None, help="write every LCP solved as an FCLib local problem into DIR")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")


def _scene_or_xml(text: str) -> str:
    """A scene name or an MJCF file name (``*.xml``), else argparse's usage error."""
    if text in SCENES or text.lower().endswith(".xml"):
        return text
    raise argparse.ArgumentTypeError(f"invalid choice: {text!r} (choose from {', '.join(SCENES)}, or an MJCF FILE.xml)")


def add_run_arguments(p: argparse.ArgumentParser) -> None:
    """The options of a scene run (steps, world, solver, scene parameters); ``lcpsim view`` shares them."""
    p.add_argument("--steps", type=int, default=2000, help="time steps to run (default: 2000)")
    world, lemke = _core.WORLD_DEFAULTS, _core.LEMKE_DEFAULTS  # the defaults of lcpsim.World and Lemke
    p.add_argument("--dt", type=float, default=world["dt"], help=f"time step h in s (default: {world['dt']:g})")
    p.add_argument(
        "--scale", type=cone_scale_argument, default=None, metavar="none|dt|FLOAT",
        help="friction-cone scale s (default: none, s = 1; dt: s = h)",
    )
    p.add_argument("--friction-dirs", type=int, default=world["friction_dirs"], metavar="K",
                   help=f"friction directions per contact (default: {world['friction_dirs']})")
    p.add_argument("--method", choices=METHODS, default=world["method"], help=f"LCP solver (default: {world['method']})")
    p.add_argument("--pivoting", choices=PIVOTINGS, default=None,
                   help=f"Lemke pivoting rule (default: {lemke['pivoting']})")
    p.add_argument("--piv-tol", type=float, default=None, help="Lemke: smallest pivot")
    p.add_argument("--zero-tol", type=float, default=None, help="Lemke: the user zero")
    p.add_argument("--max-pivots", type=int, default=None, help="Lemke: pivot limit")
    p.add_argument(
        "--set", action="append", default=[], metavar="NAME=VALUE",
        help="any other World argument, e.g. --set erp=0.1 --set restitution=0.5 (repeatable)",
    )
    g = p.add_argument_group("scene parameters (each scene takes its own; defaults are the scene's)")
    for name, users in sorted(_all_scene_params().items()):
        if name in _BOOL_PARAMS:
            g.add_argument(
                "--" + name.replace("_", "-"), dest=f"scene_{name}", action=argparse.BooleanOptionalAction, default=None,
                help=f"({', '.join(sorted(users))})",
            )
            continue
        kind: Any = int if name in _INT_PARAMS else str if name in _STR_PARAMS else float
        g.add_argument(
            "--" + name.replace("_", "-"), dest=f"scene_{name}", type=kind, default=None,
            help=f"({', '.join(sorted(users))})",
        )
    g.add_argument("--angle", dest="scene_angle_deg", type=float, default=None, help="alias of --angle-deg")


def _parse_value(text: str) -> Any:
    t = text.strip()
    if t.lower() in ("true", "false"):
        return t.lower() == "true"
    if t.lower() == "none":
        return None
    for conv in (int, float):
        try:
            return conv(t)
        except ValueError:
            pass
    return t


def _world_kwargs(args: argparse.Namespace) -> dict[str, Any]:
    kw: dict[str, Any] = {
        "dt": args.dt,
        "cone_scale": args.scale,
        "friction_dirs": args.friction_dirs,
        "method": args.method,
    }
    kw.update(lemke_options(args, args.method))
    for item in args.set:
        if "=" not in item:
            raise CliError(f"--set expects NAME=VALUE, got {item!r}")
        k, v = item.split("=", 1)
        kw[k.strip()] = _parse_value(v)
    return kw


def _scene_kwargs(args: argparse.Namespace) -> dict[str, Any]:
    accepted = scene_parameters(args.scene)
    out: dict[str, Any] = {}
    for name in _all_scene_params():
        v = getattr(args, f"scene_{name}", None)
        if v is None:
            continue
        if name not in accepted:
            raise CliError(
                f"scene {args.scene} has no parameter --{name.replace('_', '-')} "
                f"(its parameters: {', '.join('--' + p.replace('_', '-') for p in accepted)})"
            )
        out[name] = v
    return out


def simulate_summary(scene: Scene, traj: Trajectory, wall: float) -> dict[str, Any]:
    """The JSON-ready summary ``lcpsim simulate`` prints."""
    b = scene.body
    w = scene.world
    disp = traj.displacement(b)
    tilt = traj.tilt(b)
    t_end = float(traj.time[-1]) if len(traj) else 0.0
    t_start = t_end - len(traj) * traj.dt if len(traj) else 0.0
    slide = float(disp @ scene.direction) if scene.direction is not None else None
    expected = scene.expected_slide(t_end - t_start) if scene.direction is not None and len(traj) else None
    stats = traj.lcp_stats()
    final_v = traj.velocities[-1, b] if len(traj) else traj.initial_velocities[b]
    return {
        "scene": scene.name,
        "params": scene.params,
        "world": {k: v for k, v in w.params.items() if k != "method_config"},
        "steps": len(traj),
        "time": t_end,
        "body": b,
        "bodies": len(scene.bodies),
        "final_position": (traj.positions[-1, b] if len(traj) else traj.initial_positions[b]).tolist(),
        "final_orientation": (traj.orientations[-1, b] if len(traj) else traj.initial_orientations[b]).tolist(),
        "final_velocity": final_v.tolist(),
        "displacement": disp.tolist(),
        "distance": float(np.linalg.norm(disp)),
        "tilt_deg": float(np.degrees(tilt[-1])) if len(traj) else 0.0,
        "max_tilt_deg": float(np.degrees(tilt.max(initial=0.0))),
        "direction": None if scene.direction is None else scene.direction.tolist(),
        "slide": slide,
        "expected_slide": expected,
        "lcp": stats.to_dict(),
        "islands": {
            "max": int(traj.islands.max(initial=0)),
            "max_lcp_size": int(traj.max_island_size.max(initial=0)),
        },
        "wall_time": wall,
        "steps_per_second": len(traj) / wall if wall > 0 else None,
    }


def _fmt_vec(v: Any, digits: int = 6) -> str:
    return "(" + ", ".join(f"{x:.{digits}g}" for x in v) + ")"


def _text(s: dict[str, Any]) -> str:
    wp = s["world"]
    scale = wp["cone_scale"]
    scale_txt = "none (s = 1)" if scale == "none" else f"dt (s = {wp['scale']:g})" if scale == "dt" else f"s = {scale:g}"
    opts = wp.get("solver_options") or {}
    solver = s["world"]["method"] + (f" ({', '.join(f'{k}={v}' for k, v in opts.items())})" if opts else "")
    params = ", ".join(f"{k}={v}" for k, v in s["params"].items())
    lcp = s["lcp"]
    fails = ", ".join(f"{k} {v}" for k, v in lcp["by_status"].items() if k != "solved") or "none"
    lines = [
        f"scene:         {s['scene']} ({params})",
        f"world:         dt = {wp['dt']:g} s, {s['steps']} steps to t = {s['time']:.6g} s, "
        f"k = {wp['friction_dirs']}, cone scale {scale_txt}, {solver}",
        f"body {s['body']}:        final position {_fmt_vec(s['final_position'])}",
        f"               orientation {_fmt_vec(s['final_orientation'])}, velocity [v; ω] {_fmt_vec(s['final_velocity'], 4)}",
        f"displacement:  {_fmt_vec(s['displacement'])}, |d| = {s['distance']:.6g} m",
        f"tilt:          {s['tilt_deg']:.6g}° (max {s['max_tilt_deg']:.6g}°)",
    ]
    if s["slide"] is not None:
        exp = f"   (analytic: {s['expected_slide']:.6g} m)" if s["expected_slide"] is not None else ""
        lines.append(f"slide:         {s['slide']:.6g} m along {_fmt_vec(s['direction'], 4)}{exp}")
    lines += [
        f"LCPs:          {lcp['lcps']} in {lcp['steps']} steps, failures {lcp['failures']} ({fails})"
        + (f", {lcp['retaken']} steps retaken in parts" if lcp["retaken"] else ""),
        f"residual:      max {lcp['max_residual']:.3e} (physical units, ‖min(z, w)‖∞)",
        f"pivots:        median {lcp['pivots_median']:g}, max {lcp['pivots_max']}",
        f"LCP size:      max {lcp['max_lcp_size']} ({lcp['max_contacts']} contacts)",
        f"islands:       max {s['islands']['max']} per step, largest island LCP {s['islands']['max_lcp_size']}",
    ]
    sps = s["steps_per_second"]
    lines.append(f"wall time:     {s['wall_time']:.3f} s" + (f" ({sps:,.0f} steps/s)" if sps else ""))
    if s.get("capture"):
        lines.append(f"capture:       {s['capture']} ({s['captured']} LCPs)")
    if s.get("fclib"):
        lines.append(f"fclib:         {s['fclib']} ({s['fclib_files']} FCLib files)")
    return "\n".join(lines)


def build_scene(args: argparse.Namespace) -> Scene:
    """The scene ``args`` (from :func:`add_run_arguments`, ``args.scene`` its name) describe."""
    from ..scenes import make_scene

    if args.steps < 0:
        raise CliError(f"--steps must be >= 0, got {args.steps}")
    if str(args.scene).lower().endswith(".xml"):
        return _mjcf_scene(args)
    if args.scene not in SCENES:
        raise CliError(f"unknown scene {args.scene!r} (valid: {', '.join(SCENES)}, or an MJCF FILE.xml)")
    scene_kw = _scene_kwargs(args)
    world_kw = _world_kwargs(args)
    overlap = set(scene_kw) & set(world_kw)
    if overlap:
        raise CliError(f"{', '.join(sorted(overlap))} given both as a scene parameter and with --set")
    try:
        return make_scene(args.scene, **scene_kw, **world_kw)
    except TypeError as e:  # an unknown --set name
        raise CliError(str(e)) from None


def _mjcf_scene(args: argparse.Namespace) -> Scene:
    """An MJCF file as a Scene: its first moving body is the body reported."""
    from ..mjcf import load_mjcf

    given = [n for n in _all_scene_params() if getattr(args, f"scene_{n}", None) is not None]
    if given:
        raise CliError(f"an MJCF scene takes no scene parameters, got --{given[0].replace('_', '-')}")
    world_kw = _world_kwargs(args)
    # The model's own time step unless --dt was given.
    if args.dt == _core.WORLD_DEFAULTS["dt"]:
        world_kw.pop("dt")
    try:
        loaded = load_mjcf(args.scene, World, **world_kw)
    except TypeError as e:  # an unknown --set name
        raise CliError(str(e)) from None
    w = loaded.world
    dynamic = tuple(i for i in range(w.body_count) if not w.body(i).is_static)
    static = [i for i in range(w.body_count) if w.body(i).is_static]
    g = np.asarray(w.params["gravity"], dtype=float)
    up = -g / np.linalg.norm(g) if np.linalg.norm(g) > 0 else np.array([0.0, 0.0, 1.0])
    return Scene(
        name="mjcf",
        world=w,
        body=dynamic[0] if dynamic else 0,
        ground=static[0] if static else -1,
        bodies=dynamic,
        params={"file": str(args.scene)},
        normal=up,
    )


def _run(args: argparse.Namespace) -> int:
    scene = build_scene(args)
    t0 = time.perf_counter()
    if args.overwrite and not args.capture:
        raise CliError("--overwrite applies only with --capture FILE")
    traj = scene.world.run(args.steps, capture=args.capture, fclib=args.fclib, overwrite=args.overwrite)
    wall = time.perf_counter() - t0
    summary = simulate_summary(scene, traj, wall)
    summary["capture"] = args.capture
    if args.capture:
        from ..io.capture import open_capture

        with open_capture(args.capture) as c:
            summary["captured"] = len(c)
    else:
        summary["captured"] = 0
    if args.fclib:
        summary["fclib"], summary["fclib_files"] = args.fclib, len(list(Path(args.fclib).glob("*.hdf5")))
    if args.json:
        print(json.dumps(summary))
    else:
        print(_text(summary))
    return EXIT_OK if summary["lcp"]["failures"] == 0 else EXIT_NOT_SOLVED


register_command(
    Command(
        "simulate",
        "run a test scene (cube_on_slope, pushed_cube, box_stack, …) and summarize it",
        _configure,
        _run,
    )
)
