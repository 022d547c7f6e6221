"""The test scenes with analytic answers, built by the Rust ``sim::scenes`` (one implementation).

Each function takes the scene's own parameters, then any :class:`lcpsim.World`
argument (``dt``, ``cone_scale``, ``method``, ``friction_dirs``, solver
options such as ``pivoting="classic"`` …), and returns a :class:`Scene`: the
ready world plus what matters about it::

    from lcpsim import scenes
    s = scenes.cube_on_slope(45.2, 1.0, cone_scale="dt", pivoting="classic")
    traj = s.world.run(2000)
    slide = traj.displacement(s.body) @ s.direction      # down-slope distance (m)

Bodies start exactly touching (gap 0) and at rest unless a speed is given;
the scene's μ is given to every body, ground included. Slopes descend towards
+x (or −x) and their downhill direction is the first friction direction.
"""

from __future__ import annotations

import inspect
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

from . import _core
from .world import CaptureTarget, Trajectory, World

__all__ = [
    "Scene",
    "SCENES",
    "make_scene",
    "scene_parameters",
    "cube_on_slope",
    "pushed_cube",
    "cube_drop",
    "ball_drop",
    "box_stack",
    "ball_on_incline",
    "box_pile",
    "cube_heap",
    "cube_pour",
]

G = 9.81

# The defaults of the scene parameters that the Rust scene structs default
# (sim::scenes), read from the compiled module; the rest (slope angle, μ of the
# slope scenes, push force, counts) are the Python functions' own.
_D: dict[str, dict[str, Any]] = _core.SCENE_DEFAULTS


@dataclass
class Scene:
    """A built scene.

    ``world`` is ready to step; ``body`` is the body the scene is about (the
    cube, the ball, the top box of a stack); ``ground`` the static plane;
    ``bodies`` every dynamic body (bottom to top for a stack). ``direction``
    is the direction of interest — the slope's downhill direction, or the push
    — or None; ``normal`` the ground's outward normal; ``params`` the scene
    parameters as given.
    """

    name: str
    world: World
    body: int
    ground: int
    bodies: tuple[int, ...]
    params: dict[str, Any]
    normal: NDArray[np.float64]
    direction: NDArray[np.float64] | None = None
    extra: dict[str, Any] = field(default_factory=dict)

    def run(self, steps: int, capture: CaptureTarget = None, **kwargs: Any) -> Trajectory:
        """``self.world.run(steps, capture, …)``."""
        return self.world.run(steps, capture, **kwargs)

    def expected_slide(self, t: float) -> float | None:
        """The analytic distance (m) travelled along :attr:`direction` after
        ``t`` seconds from the start, where the physics gives one (the slope
        scenes and the pushed cube; None otherwise, e.g. for a cube that tips)."""
        p = self.world.params
        g = float(np.linalg.norm(p["gravity"]))
        if self.name in ("cube_on_slope", "resting_cube", "ball_on_incline"):
            th = np.radians(self.params.get("angle_deg", 0.0))
            mu = self.params["mu"]
            v0 = self.params.get("speed", 0.0)
            tan = np.tan(th)
            if self.name == "ball_on_incline":
                a = 5.0 / 7.0 * g * np.sin(th) if mu >= 2.0 / 7.0 * tan else g * (np.sin(th) - mu * np.cos(th))
                return float(0.5 * a * t * t)
            if self.params.get("tangent_angle", 0.0) != 0.0:
                return None  # the cone's bisector threshold is μ·cos(π/k): not modelled here
            if tan > 1.0 and mu > 1.0:
                return None  # tips
            a = g * (np.sin(th) - mu * np.cos(th))
            if v0 == 0.0:
                return float(0.5 * a * t * t) if a > 0 else 0.0
            if a >= 0:
                return float(v0 * t + 0.5 * a * t * t)
            t_stop = v0 / -a
            tt = min(t, t_stop)
            return float(v0 * tt + 0.5 * a * tt * tt)
        if self.name == "pushed_cube":
            F, mu, m = self.params["force"], self.params["mu"], self.params["mass"]
            if self.params.get("height", 0.0) != 0.0:
                return None
            a = F / m - mu * g
            return float(0.5 * a * t * t) if a > 0 else 0.0
        return None


def _build(name: str, arguments: dict[str, Any]) -> Scene:
    """Scene ``name`` built by ``sim::scenes`` from a scene function's own
    arguments (its ``locals()`` on entry): the scene's parameters, and
    ``world`` with the :class:`World` arguments."""
    params = {k: v for k, v in arguments.items() if k != "world"}
    template = World(**arguments["world"])
    core, ids = _core.build_scene(name, {k: v for k, v in params.items() if v is not None}, template._core)
    w = World._wrap(core, template.method, template.solver_options)
    w.scene = name
    w.scene_params = dict(params)
    ground = w.body(int(ids["ground"]))
    normal = ground.normal if ground.normal is not None else np.array([0.0, 0.0, 1.0])
    return Scene(
        name=name,
        world=w,
        body=int(ids["body"]),
        ground=int(ids["ground"]),
        bodies=tuple(int(b) for b in ids["bodies"]),
        params=dict(params),
        normal=np.asarray(normal, dtype=float),
        direction=None,
    )


def _slope_direction(s: Scene) -> NDArray[np.float64]:
    g = s.world.body(s.ground)
    d = g.downhill if g.downhill is not None else g.tangent
    assert d is not None
    return np.asarray(d, dtype=float)


def cube_on_slope(
    angle_deg: float = 30.0,
    mu: float = 0.5,
    *,
    size: float = _D["cube_on_slope"]["size"],
    mass: float = _D["cube_on_slope"]["mass"],
    downhill: str = _D["cube_on_slope"]["downhill"],
    speed: float = _D["cube_on_slope"]["speed"],
    tangent_angle: float = _D["cube_on_slope"]["tangent_angle"],
    **world: Any,
) -> Scene:
    """A cube resting on a slope of ``angle_deg`` (a level plane at 0°), one face
    on the surface, edges along the downhill and horizontal directions.

    Rests iff tan θ ≤ min(μ, 1); tips iff tan θ > 1 and μ > 1; slides without
    tipping with a = g(sin θ − μ cos θ) if μ ≤ 1. ``speed``: initial speed
    down the slope (m/s); ``tangent_angle`` turns the friction directions
    about the normal (π/k puts the slope on a bisector). ``direction`` is the
    downhill direction (+x on level ground)."""
    s = _build("cube_on_slope", locals())
    s.direction = _slope_direction(s)
    if angle_deg == 0.0:
        s.direction = np.array([1.0, 0.0, 0.0]) if downhill != "-x" else np.array([-1.0, 0.0, 0.0])
    return s


def resting_cube(
    mu: float = 0.5,
    *,
    size: float = _D["cube_on_slope"]["size"],
    mass: float = _D["cube_on_slope"]["mass"],
    **world: Any,
) -> Scene:
    """A cube at rest on level ground: Σfn = m·g·h every step, no drift."""
    s = cube_on_slope(0.0, mu, size=size, mass=mass, **world)
    s.name = s.world.scene = "resting_cube"
    return s


def pushed_cube(
    force: float = 5.0,
    mu: float = 1.0,
    *,
    size: float = _D["pushed_cube"]["size"],
    mass: float = _D["pushed_cube"]["mass"],
    height: float = _D["pushed_cube"]["height"],
    **world: Any,
) -> Scene:
    """A cube at rest on level ground pushed along +x by a constant ``force`` (N)
    at ``height`` above its centre of mass (body frame; 0: at the centre of mass).

    Stays iff F ≤ μmg with friction = F exactly; else slides with
    a = (F − μmg)/m. ``direction`` is +x."""
    s = _build("pushed_cube", locals())
    s.direction = np.array([1.0, 0.0, 0.0])
    return s


def cube_drop(
    height: float = _D["cube_drop"]["height"],
    *,
    size: float = _D["cube_drop"]["size"],
    mass: float = _D["cube_drop"]["mass"],
    mu: float = _D["cube_drop"]["mu"],
    restitution: float | None = _D["cube_drop"]["restitution"],
    **world: Any,
) -> Scene:
    """A cube dropped flat from ``height`` (gap between its bottom face and the
    ground, m); ``restitution`` overrides the world's coefficient."""
    return _build("cube_drop", locals())


def ball_drop(
    height: float = _D["ball_drop"]["height"],
    *,
    radius: float = _D["ball_drop"]["radius"],
    mass: float = _D["ball_drop"]["mass"],
    mu: float = _D["ball_drop"]["mu"],
    restitution: float | None = _D["ball_drop"]["restitution"],
    **world: Any,
) -> Scene:
    """A ball dropped from ``height`` (gap below it, m): impact at √(2H/g)
    within 2h; with restitution e it leaves at e times the impact speed."""
    return _build("ball_drop", locals())


def box_stack(
    n: int = 3,
    *,
    size: float = _D["box_stack"]["size"],
    mass: float = _D["box_stack"]["mass"],
    mu: float = _D["box_stack"]["mu"],
    **world: Any,
) -> Scene:
    """A tower of ``n`` cubes on level ground: the force at interface j (from
    the ground, j = 0) is (n − j)·m·g; ``bodies`` bottom to top, ``body`` the top box."""
    return _build("box_stack", locals())


def ball_on_incline(
    angle_deg: float = 30.0,
    mu: float = 0.3,
    *,
    radius: float = _D["ball_on_incline"]["radius"],
    mass: float = _D["ball_on_incline"]["mass"],
    downhill: str = _D["ball_on_incline"]["downhill"],
    **world: Any,
) -> Scene:
    """A solid ball at rest on a slope: rolls iff μ ≥ (2/7) tan θ with
    a = (5/7) g sin θ, else slips with a = g(sin θ − μ cos θ).
    ``direction`` is the downhill direction."""
    s = _build("ball_on_incline", locals())
    s.direction = _slope_direction(s)
    return s


def box_pile(
    nx: int = _D["box_pile"]["nx"],
    ny: int = _D["box_pile"]["ny"],
    nz: int = _D["box_pile"]["nz"],
    *,
    size: float = _D["box_pile"]["size"],
    mass: float = _D["box_pile"]["mass"],
    mu: float = _D["box_pile"]["mu"],
    spacing: float = _D["box_pile"]["spacing"],
    yaw: float = _D["box_pile"]["yaw"],
    seed: int = _D["box_pile"]["seed"],
    **world: Any,
) -> Scene:
    """``nx × ny`` towers of ``nz`` cubes on a grid (``spacing`` × size between
    tower axes), each cube turned about the vertical by a seeded random angle
    in [−yaw, yaw] (rad)."""
    return _build("box_pile", locals())


def cube_heap(
    n: int = 50,
    seed: int = 0,
    walls: bool = _D["cube_heap"]["walls"],
    *,
    size: float = _D["cube_heap"]["size"],
    mass: float = _D["cube_heap"]["mass"],
    mu: float = _D["cube_heap"]["mu"],
    spacing: float = _D["cube_heap"]["spacing"],
    jitter: float = _D["cube_heap"]["jitter"],
    **world: Any,
) -> Scene:
    """``n`` cubes dropped into one connected heap: a stepped pyramid whose
    layer L holds (g − L)² cubes above the gaps of the layer below (``spacing``
    × size between neighbours), each turned (rad) and shifted (× size) by
    seeded random amounts up to ``jitter`` and starting a little above its
    resting place; ``walls`` adds four static boxes around the base."""
    return _build("cube_heap", locals())


def cube_pour(
    n: int = 45,
    seed: int = 0,
    walls: bool = _D["cube_pour"]["walls"],
    *,
    size: float = _D["cube_pour"]["size"],
    mass: float = _D["cube_pour"]["mass"],
    mu: float = _D["cube_pour"]["mu"],
    spacing: float = _D["cube_pour"]["spacing"],
    jitter: float = _D["cube_pour"]["jitter"],
    **world: Any,
) -> Scene:
    """``n`` cubes poured into one heap: each with a uniformly random
    orientation (seeded), released at rest from a loose column of ``g × g``
    cells per layer (``g = max(2, ⌈√(n/10)⌉)``, cells ``spacing`` × size
    apart, each cube shifted by up to ``jitter`` × size per axis) above the
    floor, so that they tumble and their contacts change every step while the
    heap forms; ``walls`` puts the column in a bin of four static walls."""
    return _build("cube_pour", locals())


#: Every scene by name.
SCENES: dict[str, Callable[..., Scene]] = {
    "cube_on_slope": cube_on_slope,
    "resting_cube": resting_cube,
    "pushed_cube": pushed_cube,
    "cube_drop": cube_drop,
    "ball_drop": ball_drop,
    "box_stack": box_stack,
    "ball_on_incline": ball_on_incline,
    "box_pile": box_pile,
    "cube_heap": cube_heap,
    "cube_pour": cube_pour,
}


def scene_parameters(name: str) -> dict[str, Any]:
    """The scene's own parameters and their defaults (world arguments excluded)."""
    fn = _scene(name)
    return {
        p.name: p.default
        for p in inspect.signature(fn).parameters.values()
        if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)
    }


def make_scene(name: str, **kwargs: Any) -> Scene:
    """Builds scene ``name`` with scene and world keyword arguments."""
    return _scene(name)(**kwargs)


def _scene(name: str) -> Callable[..., Scene]:
    try:
        return SCENES[name]
    except KeyError:
        raise ValueError(f"unknown scene {name!r} (valid: {', '.join(SCENES)})") from None
