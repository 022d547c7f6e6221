"""``lcpsim view``: a run as one self-contained 3-D page (:mod:`lcpsim.viewer`).

::

    lcpsim view cube_on_slope --angle-deg 45.2 --mu 1 --out slope.html [--save slope.h5]
    lcpsim view slope.h5 --out slope.html

``SCENE`` takes the options of ``lcpsim simulate`` (steps, world, solver,
scene parameters) and is run with its contacts recorded; a trajectory file
is one written by ``Trajectory.save`` or ``--save``. Exit codes: 0 the page
was written (failed LCPs are shown in it), 2 invalid input (a missing,
truncated or foreign file, a bad option: one line on stderr).
"""

from __future__ import annotations

import argparse
import os
from typing import Any

from .command import EXIT_OK, CliError, Command, register_command
from .simulate import add_run_arguments, build_scene

__all__: list[str] = []


def _configure(p: argparse.ArgumentParser) -> None:
    from ..scenes import SCENES

    p.add_argument(
        "source", metavar="SCENE|FILE.h5",
        help=f"a scene ({', '.join(SCENES)}), an MJCF file (FILE.xml) or a trajectory file written by Trajectory.save / --save",
    )
    p.add_argument("--out", metavar="FILE.html", required=True, help="the page to write")
    p.add_argument("--save", metavar="FILE.h5", default=None, help="also save the trajectory (HDF5)")
    p.add_argument("--title", default=None, help="the page's title (default: the scene and its parameters)")
    p.add_argument("--body", type=int, default=None, help="the body selected at first (default: the scene's)")
    p.add_argument("--max-bytes", type=int, default=None, metavar="N",
                   help="size cap of the page; longer runs are downsampled (default: 2,000,000)")
    before = {a.dest for a in p._actions}
    add_run_arguments(p)
    # Defaults of the scene-run options, to tell a trajectory file that it was given some.
    p.set_defaults(_run_defaults={a.dest: a.default for a in p._actions if a.dest not in before})


def _run(args: argparse.Namespace) -> int:
    from ..scenes import SCENES
    from ..trajectory import Trajectory
    from ..viewer import DEFAULT_MAX_BYTES

    options: dict[str, Any] = {"title": args.title, "body": args.body,
                               "max_bytes": args.max_bytes or DEFAULT_MAX_BYTES}
    if args.source in SCENES or args.source.lower().endswith(".xml"):  # a scene, or MJCF
        args.scene = args.source
        scene = build_scene(args)
        traj = scene.world.run(args.steps, record_contacts=True)
        d = scene.direction
        if options["body"] is None:
            options["body"] = scene.body
        if d is not None:
            options["direction"] = d
            options["direction_label"] = "down-slope distance" if d[2] < -1e-12 else "distance along the scene's direction"
    else:
        given = [k for k, v in args._run_defaults.items() if getattr(args, k) != v]
        if given:
            raise CliError(f"--{given[0].removeprefix('scene_').replace('_', '-')} applies to a scene, not to a trajectory file")
        if not os.path.exists(args.source) and not args.source.endswith((".h5", ".hdf5")):
            raise CliError(f"{args.source!r} is neither a scene ({', '.join(SCENES)}) nor an existing file")
        traj = Trajectory.load(args.source)
    if args.save:
        traj.save(args.save)
    path = traj.to_html(args.out, **options)
    stats = traj.lcp_stats()
    print(f"wrote {path} ({os.path.getsize(path) / 1e6:.2f} MB): {len(traj)} steps, "
          f"{stats.failures} LCPs not solved" + (f"; trajectory saved to {args.save}" if args.save else ""))
    return EXIT_OK


register_command(Command("view", "write a run (a scene, or a saved trajectory) as a self-contained 3-D page", _configure, _run))
