"""The many-body scenes of ``many_bodies.py``, and the measurements taken on their states.

Every scene is built by lcpsim's public API (``lcpsim.scenes.box_stack``,
``box_pile``, ``cube_heap`` and ``cube_pour`` when lcpsim has them, else
:func:`build_heap` with ``World.add_box``) and then *exported*
(:func:`describe`): the boxes' half
extents, centres, orientations, masses and static flags, over the ground
plane ``z = 0``. 1 kg unit cubes, μ = 0.5, g = 9.81, dt = 1e-3.

Every scene is written once as MJCF (:func:`scene_mjcf`,
``benchmarks/scenes/<key>.xml``, by ``many_bodies.py --write-scenes``):
lcpsim (``World.from_mjcf``) and MuJoCo read that file, and PyBullet and
Rapier are built from the description of lcpsim's world read from it
(:func:`load`), so all engines start from the same state.
"""

from __future__ import annotations

import inspect
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

import numpy as np

DT = 1e-3
G = 9.81
MU = 0.5
HALF = 0.5  # unit cubes
#: Where the scenes' MJCF files live.
MJCF_DIR = Path(__file__).resolve().parent.parent / "scenes"


# --------------------------------------------------------------------------- the heap


def heap_layout(n: int, seed: int = 1, spacing: float = 1.8, jitter: float = 0.03) -> list[dict[str, Any]]:
    """``n`` unit cubes in a column: a ``g × g`` grid per layer (g = ⌈√(n/10)⌉,
    so about 10 layers), ``spacing`` between centres, every centre jittered by
    up to ``jitter`` per axis and every orientation uniformly random (seeded
    numpy PCG64). The lowest layer's centres are 0.966 m up (0.1 m above the
    largest reach of a turned cube, √3/2). A spacing of 1.8 with a jitter of
    0.03 keeps any two centres at least 1.74 m apart along an axis, more than
    a turned cube's diameter √3: no two cubes touch at the start."""
    rng = np.random.default_rng(seed)
    g = max(2, math.ceil(math.sqrt(n / 10)))
    z0 = math.sqrt(3) * HALF + 0.1
    cubes = []
    for i in range(n):
        layer, cell = divmod(i, g * g)
        iy, ix = divmod(cell, g)
        c = np.array([(ix - 0.5 * (g - 1)) * spacing, (iy - 0.5 * (g - 1)) * spacing, z0 + layer * spacing])
        c += rng.uniform(-jitter, jitter, 3)
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        if q[0] < 0:
            q = -q
        cubes.append({"pos": c.tolist(), "quat": q.tolist()})
    return cubes


def heap_walls(n: int, spacing: float = 1.8, height: float = 4.0) -> list[dict[str, Any]]:
    """Four static walls (1 m thick, ``height`` tall) around the heap's grid,
    1 cm above the ground and 1 cm apart at the corners (static bodies never touch)."""
    g = max(2, math.ceil(math.sqrt(n / 10)))
    a = 0.5 * g * spacing  # inner half-width
    zc = 0.5 * height + 0.01
    walls = []
    for s in (-1.0, 1.0):
        walls.append({"half": [0.5, a + 1.0, 0.5 * height], "pos": [s * (a + 0.5), 0.0, zc]})
        walls.append({"half": [a - 0.01, 0.5, 0.5 * height], "pos": [0.0, s * (a + 0.5), zc]})
    return walls


def build_heap(n: int, seed: int = 1, walls: bool = True) -> Any:
    """The heap as an lcpsim World: level ground, optional walls, ``n`` cubes of :func:`heap_layout`."""
    import lcpsim

    w = lcpsim.World(dt=DT)
    w.add_ground(mu=MU)
    if walls:
        for wall in heap_walls(n):
            w.add_box(half_extents=wall["half"], position=wall["pos"], mu=MU, static=True)
    for c in heap_layout(n, seed):
        w.add_box(half_extents=(HALF,) * 3, mass=1.0, position=c["pos"], orientation=c["quat"], mu=MU)
    return w


def heap_world(n: int, seed: int = 1) -> tuple[Any, str]:
    """lcpsim's own ``scenes.cube_heap`` when it exists (its parameters matched by
    name), else :func:`build_heap`; with a note of which."""
    from lcpsim import scenes

    make = getattr(scenes, "cube_heap", None)
    if make is None:
        return build_heap(n, seed), "built here with World.add_box (lcpsim.scenes has no cube_heap)"
    params = inspect.signature(make).parameters
    kwargs: dict[str, Any] = {"dt": DT}
    for name in ("n", "count", "cubes"):
        if name in params:
            kwargs[name] = n
            break
    else:
        return build_heap(n, seed), "built here (lcpsim.scenes.cube_heap takes no cube count)"
    if "seed" in params:
        kwargs["seed"] = seed
    if "walls" in params:
        kwargs["walls"] = True
    return make(**kwargs).world, "lcpsim.scenes.cube_heap"


def pour_world(n: int, seed: int = 0) -> tuple[Any, str]:
    """The pour of ``n`` cubes: lcpsim's ``scenes.cube_pour(n, seed, walls=True, dt=1e-3)``
    (unit cubes, 1 kg, μ 0.5, uniformly random orientations, at rest in a loose
    column of g × g cells per layer 1.8 m apart, g = max(2, ⌈√(n/10)⌉, inside
    four static walls), with a note of how it was built. Where lcpsim has no
    ``cube_pour`` yet, the same kind of column is built here (:func:`build_heap`:
    :func:`heap_layout` in :func:`heap_walls`) and the note says so: its
    figures are then not those of lcpsim's scene."""
    from lcpsim import scenes

    make = getattr(scenes, "cube_pour", None)
    if make is None:
        return build_heap(n, seed), f"built here with World.add_box (lcpsim.scenes has no cube_pour; seed {seed})"
    return make(n, seed=seed, walls=True, dt=DT).world, f"lcpsim.scenes.cube_pour({n}, seed={seed}, walls=True)"


# --------------------------------------------------------------------------- scenes


@dataclass(frozen=True)
class SceneSpec:
    key: str
    title: str
    build: Callable[[], tuple[Any, str]]  # () -> (lcpsim World, how it was built)
    seconds: float  # simulated time per run
    reps: int  # repetitions within one worker process
    rounds: int = 1  # worker processes per engine, interleaved engine after engine (see many_bodies.run_all)
    #: Steps between pose samples (0: a tenth of the run). The stepping calls
    #: never cross a sample, so the seconds of each window between samples are exact.
    sample_every: int = 0
    benchmark: str = "many_bodies"  # the RESULTS.md table it belongs to: "many_bodies" or "pours"


def _stack(n: int) -> Callable[[], tuple[Any, str]]:
    def build() -> tuple[Any, str]:
        from lcpsim import scenes

        return scenes.box_stack(n, dt=DT).world, f"lcpsim.scenes.box_stack({n})"

    return build


def _towers(nx: int, nz: int) -> Callable[[], tuple[Any, str]]:
    def build() -> tuple[Any, str]:
        from lcpsim import scenes

        return scenes.box_pile(nx, nx, nz, dt=DT).world, f"lcpsim.scenes.box_pile({nx}, {nx}, {nz})"

    return build


def _heap(n: int) -> Callable[[], tuple[Any, str]]:
    return lambda: heap_world(n)


def _pour(n: int) -> Callable[[], tuple[Any, str]]:
    return lambda: pour_world(n)


#: Pours: 3 simulated seconds, sampled (and timed) every 250 steps.
POUR_SECONDS = 3.0
POUR_WINDOW = 250


SCENES: list[SceneSpec] = [
    SceneSpec("stack10", "10-box stack", _stack(10), 2.0, 3, rounds=3),
    SceneSpec("towers3", "3×3×3 towers (9 stacks of 3)", _towers(3, 3), 2.0, 3, rounds=3),
    SceneSpec("towers10", "10×10×10 towers (100 stacks of 10)", _towers(10, 10), 1.0, 1, rounds=3),
    # The heaps are sampled every 250 steps, as the pours are, so their windows compare.
    SceneSpec("heap200", "heap of 200 cubes", _heap(200), 2.0, 3, sample_every=POUR_WINDOW),
    SceneSpec("heap1000", "heap of 1,000 cubes", _heap(1000), 1.5, 1, sample_every=POUR_WINDOW),
    SceneSpec("pour45", "pour of 45 cubes", _pour(45), POUR_SECONDS, 1, sample_every=POUR_WINDOW, benchmark="pours"),
    SceneSpec("pour90", "pour of 90 cubes", _pour(90), POUR_SECONDS, 1, sample_every=POUR_WINDOW, benchmark="pours"),
    SceneSpec("pour200", "pour of 200 cubes", _pour(200), POUR_SECONDS, 1, sample_every=POUR_WINDOW,
              benchmark="pours"),
    SceneSpec("pour1000", "pour of 1,000 cubes", _pour(1000), POUR_SECONDS, 1, sample_every=POUR_WINDOW,
              benchmark="pours"),
]
SCENE_BY_KEY = {s.key: s for s in SCENES}


def mjcf_path(key: str) -> Path:
    """The scene's MJCF file."""
    return MJCF_DIR / f"{key}.xml"


def load(key: str) -> tuple[Any, str]:
    """The scene's lcpsim world read from its MJCF file (``World.from_mjcf``), and how it was
    built — with the friction directions the file's cone gave (MuJoCo's default pyramid: 4)."""
    path = mjcf_path(key)
    if not path.exists():
        raise FileNotFoundError(f"{path} is missing: write it with many_bodies.py --write-scenes")
    import lcpsim

    world = lcpsim.World.from_mjcf(path)
    return world, f"World.from_mjcf(benchmarks/scenes/{path.name}), friction_dirs {world.params['friction_dirs']}"


def scene_mjcf(desc: dict[str, Any], key: str) -> str:
    """The scene of a description as MJCF: the ground plane, the static boxes as geoms of
    the world (``wall<k>``), each dynamic box a body ``box<k>`` on a free joint, every
    number as Python's shortest repr (read back exactly), μ with MuJoCo's default
    torsional and rolling friction (0.005, 0.0001; lcpsim has neither)."""
    fr = f'friction="{desc["mu"]!r} 0.005 0.0001"'
    num = lambda b, k: " ".join(repr(float(v)) for v in b[k])  # noqa: E731
    lines = [f'<mujoco model="{key}">',
             f'  <!-- Written by benchmarks/peers/many_bodies.py --write-scenes from {desc["built_by"]}; '
             "run by lcpsim and MuJoCo alike. -->",
             f'  <option timestep="{desc["dt"]!r}" gravity="0 0 -{desc["gravity"]!r}"/>',
             "  <worldbody>",
             f'    <geom name="floor" type="plane" size="0 0 1" {fr}/>']
    statics = [b for b in desc["boxes"] if b["static"]]
    dynamic = [b for b in desc["boxes"] if not b["static"]]
    for k, b in enumerate(statics):
        lines.append(f'    <geom name="wall{k}" type="box" pos="{num(b, "pos")}" quat="{num(b, "quat")}" '
                     f'size="{num(b, "half")}" {fr}/>')
    for k, b in enumerate(dynamic):
        lines.append(f'    <body name="box{k}" pos="{num(b, "pos")}" quat="{num(b, "quat")}"><freejoint/>'
                     f'<geom type="box" size="{num(b, "half")}" mass="{b["mass"]!r}" {fr}/></body>')
    lines += ["  </worldbody>", "</mujoco>", ""]
    return "\n".join(lines)


def describe(world: Any, how: str) -> dict[str, Any]:
    """The scene every engine is built from: boxes over the ground ``z = 0``
    (dynamic boxes in lcpsim's body order), and the top box of each tower."""
    boxes = []
    for i in range(world.body_count):
        b = world.body(i)
        if b.kind == "plane":
            if not (np.allclose(b.normal, [0, 0, 1]) and abs(b.offset) < 1e-15):
                raise ValueError(f"body {i}: only the level ground z = 0 is supported, got {b.normal}, {b.offset}")
            continue
        if b.kind != "box":
            raise ValueError(f"body {i}: only boxes are supported, got {b.kind}")
        boxes.append({
            "half": np.asarray(b.half_extents).tolist(),
            "pos": np.asarray(b.position).tolist(),
            "quat": np.asarray(b.orientation).tolist(),
            "static": bool(b.is_static),
            "mass": 1.0 if b.is_static else float(b.mass),
        })
    dyn = [b for b in boxes if not b["static"]]
    return {"dt": world.dt, "gravity": G, "mu": MU, "built_by": how, "boxes": boxes,
            "tops": tower_tops(np.array([b["pos"] for b in dyn]))}


def tower_tops(pos: np.ndarray) -> list[int]:
    """Index of the highest box of each tower (boxes sharing x, y to 1 nm) of
    two or more boxes; empty for a heap (jittered centres never share x, y)."""
    groups: dict[tuple[int, int], list[int]] = {}
    for i, p in enumerate(pos):
        groups.setdefault((round(p[0] * 1e9), round(p[1] * 1e9)), []).append(i)
    return sorted(max(g, key=lambda i: pos[i][2]) for g in groups.values() if len(g) > 1)


# --------------------------------------------------------------------------- measurements


def rotations(quat: np.ndarray) -> np.ndarray:
    """(N, 3, 3) rotation matrices of unit quaternions (w, x, y, z); columns are the body axes."""
    q = np.asarray(quat, dtype=float)
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1),
    ], axis=1)


def box_overlap(pa: np.ndarray, ra: np.ndarray, ha: np.ndarray,
                pb: np.ndarray, rb: np.ndarray, hb: np.ndarray) -> np.ndarray:
    """Penetration depth (m, 0 if apart) of box pairs by the separating-axis
    test: the smallest overlap of the two boxes' projections over the 3 + 3
    face normals and the 9 edge–edge cross products."""
    ea, eb = np.swapaxes(ra, 1, 2), np.swapaxes(rb, 1, 2)  # (P, 3 axes, 3)
    cross = np.cross(ea[:, :, None, :], eb[:, None, :, :]).reshape(-1, 9, 3)
    axes = np.concatenate([ea, eb, cross], axis=1)  # (P, 15, 3)
    norm = np.linalg.norm(axes, axis=2)
    ok = norm > 1e-9
    axes = axes / np.where(ok, norm, 1.0)[:, :, None]
    rad_a = np.einsum("pk,pkj->pj", ha, np.abs(np.einsum("pkd,pjd->pkj", ea, axes)))
    rad_b = np.einsum("pk,pkj->pj", hb, np.abs(np.einsum("pkd,pjd->pkj", eb, axes)))
    dist = np.abs(np.einsum("pd,pjd->pj", pb - pa, axes))
    overlap = np.where(ok, rad_a + rad_b - dist, np.inf)
    return np.maximum(overlap.min(axis=1), 0.0)


def penetration(desc: dict[str, Any], pos: np.ndarray, quat: np.ndarray) -> float:
    """Deepest penetration (m) in a state of the dynamic boxes: box–ground,
    box–box and box–static box."""
    from scipy.spatial import cKDTree

    boxes = desc["boxes"]
    dyn_half = np.array([b["half"] for b in boxes if not b["static"]])
    stat = [b for b in boxes if b["static"]]
    r = rotations(quat)
    lowest = pos[:, 2] - np.einsum("nk,nk->n", dyn_half, np.abs(r[:, 2, :]))
    deepest = float(max(0.0, -lowest.min(initial=0.0)))
    reach = float(np.linalg.norm(dyn_half, axis=1).max(initial=0.0))
    pairs = np.array(sorted(cKDTree(pos).query_pairs(2 * reach)), dtype=np.int64).reshape(-1, 2)
    if len(pairs):
        i, j = pairs.T
        deepest = max(deepest, float(box_overlap(pos[i], r[i], dyn_half[i], pos[j], r[j], dyn_half[j]).max()))
    for s in stat:
        n = len(pos)
        sp = np.broadcast_to(np.array(s["pos"]), (n, 3))
        sr = np.broadcast_to(rotations(np.array([s["quat"]]))[0], (n, 3, 3))
        sh = np.broadcast_to(np.array(s["half"]), (n, 3))
        deepest = max(deepest, float(box_overlap(pos, r, dyn_half, sp, sr, sh).max(initial=0.0)))
    return deepest


def drift(desc: dict[str, Any], pos0: np.ndarray, pos1: np.ndarray) -> dict[str, float] | None:
    """How far the towers' top boxes moved: the largest |Δp| and the lowest Δz (m); None for a heap."""
    tops = desc["tops"]
    if not tops:
        return None
    d = pos1[tops] - pos0[tops]
    return {"max_m": float(np.linalg.norm(d, axis=1).max()), "min_dz_m": float(d[:, 2].min())}
