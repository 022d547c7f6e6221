"""The shapes beyond boxes, spheres and planes — :meth:`World.add_capsule`,
``add_cylinder``, ``add_convex``, ``add_mesh``, ``add_compound``, ``add_heightfield``
(:class:`ShapesMixin`, a base of
:class:`lcpsim.World`) — and every body's collision bits (MuJoCo's
``contype``/``conaffinity``). Array shapes, size limits and the bits are checked
here, the rest (finite values, index ranges, degenerate faces) in Rust
(``sim::geometry``), always before a body is added: a refused one adds nothing."""

from __future__ import annotations

import inspect
from collections.abc import Iterable, Mapping
from typing import Any, Callable, Concatenate, ParamSpec, Sequence, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core
from ._validate import as_real_array, real as _real, vec as _vec, velocities as _velocities

_BODY = _core.BODY_DEFAULTS
Vec = Union[Sequence[float], NDArray[np.float64]]

#: The most points :meth:`World.add_convex` takes, and the most vertices and
#: triangles of :meth:`World.add_mesh` (``sim::geometry::MAX_*``).
MAX_HULL_POINTS = 100_000
MAX_MESH_VERTICES = 1_000_000
MAX_MESH_FACES = 2_000_000
#: The most grid points of :meth:`World.add_heightfield` (``sim::geometry::MAX_HFIELD_POINTS``).
MAX_HFIELD_POINTS = 16_000_000
#: The most parts of :meth:`World.add_compound` (``sim::geometry::MAX_COMPOUND_PARTS``).
MAX_COMPOUND_PARTS = 10_000
#: A compound part's kinds and the field(s) giving each one's size.
PART_FIELDS = {
    "box": ("half_extents",),
    "sphere": ("radius",),
    "capsule": ("radius", "half_length"),
    "cylinder": ("radius", "half_length"),
    "convex": ("vertices",),
}


def points_array(x: Any, name: str, limit: int) -> NDArray[np.float64]:
    """An (N, 3) float array, N ≤ ``limit``, else a ValueError naming ``name``."""
    try:
        a = np.ascontiguousarray(np.asarray(x, dtype=np.float64))
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be an (N, 3) array of real numbers, got {x!r}") from None
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name} must be an (N, 3) array of real numbers, got shape {a.shape}")
    if a.shape[0] > limit:
        raise ValueError(f"{name} has {a.shape[0]} points, more than the limit of {limit}")
    return a


def faces_array(faces: Any, limit: int) -> NDArray[np.int64]:
    """An (M, 3) int64 array, M ≤ ``limit``, else a ValueError naming ``faces``."""
    try:
        f = np.asarray(faces)
    except (TypeError, ValueError):
        raise ValueError(f"faces must be an (M, 3) array of integers, got {faces!r}") from None
    if f.ndim != 2 or f.shape[1] != 3 or not (f.size == 0 or np.issubdtype(f.dtype, np.integer)):
        raise ValueError(f"faces must be an (M, 3) array of integers, got shape {f.shape}, dtype {f.dtype}")
    if f.shape[0] > limit:
        raise ValueError(f"faces has {f.shape[0]} triangles, more than the limit of {limit}")
    return np.ascontiguousarray(f, dtype=np.int64)


def compound_parts(parts: Any) -> list[tuple[str, Any, Any, Any]]:
    """``(kind, size, position, orientation)`` of each part of :meth:`World.add_compound`,
    else a ValueError naming ``parts[k]`` and the field (the values are checked in Rust)."""
    if isinstance(parts, (str, bytes, Mapping)) or not isinstance(parts, Iterable):
        raise ValueError(f"parts must be a list of parts (dicts with 'kind'), got {parts!r}")
    parts = list(parts)
    if not parts:
        raise ValueError("parts must hold at least one part, got none")
    if len(parts) > MAX_COMPOUND_PARTS:
        raise ValueError(f"parts has {len(parts)} parts, more than the limit of {MAX_COMPOUND_PARTS}")
    out = []
    for k, p in enumerate(parts):
        if not isinstance(p, Mapping):
            raise ValueError(f"parts[{k}] must be a dict with 'kind', got {p!r}")
        kind = p.get("kind")
        if kind not in PART_FIELDS:
            raise ValueError(f"parts[{k}].kind must be one of {', '.join(PART_FIELDS)}, got {kind!r}")
        unknown = set(p) - {"kind", "position", "orientation", *PART_FIELDS[kind]}
        if unknown:
            raise ValueError(f"parts[{k}] ({kind}) has unknown field(s) {', '.join(sorted(map(str, unknown)))}")
        missing = [f for f in PART_FIELDS[kind] if p.get(f) is None]
        if missing:
            raise ValueError(f"parts[{k}] ({kind}) needs {', '.join(missing)}")
        if kind == "box":
            size: Any = _vec(p["half_extents"], f"parts[{k}].half_extents")
        elif kind == "convex":
            size = points_array(p["vertices"], f"parts[{k}].vertices", MAX_HULL_POINTS)
        else:
            size = tuple(_real(p[f], f"parts[{k}].{f}") for f in PART_FIELDS[kind])
            size = size[0] if kind == "sphere" else size
        position = _vec(p.get("position", (0.0, 0.0, 0.0)), f"parts[{k}].position")
        orientation = _vec(p.get("orientation", (1.0, 0.0, 0.0, 0.0)), f"parts[{k}].orientation", 4)
        out.append((kind, size, position, orientation))
    return out


def collision_bits(contype: Any, conaffinity: Any) -> tuple[int, int]:
    """MuJoCo's ``contype``, ``conaffinity`` as integers in [0, 2**32), else a ValueError
    naming the field and value (checked before a body is added, so a bad one adds nothing)."""
    out = []
    for name, v in (("contype", contype), ("conaffinity", conaffinity)):
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer)) or not 0 <= int(v) < 2**32:
            raise ValueError(f"{name} must be an integer in [0, 2**32), got {v!r}")
        out.append(int(v))
    return out[0], out[1]


P = ParamSpec("P")


def _for_kind(add: Callable[Concatenate[Any, str, P], int], kind: str, doc: str) -> Callable[Concatenate[Any, P], int]:
    """``add`` with its ``kind`` given: ``add_capsule``, ``add_cylinder`` share ``_add_round``'s signature."""

    def method(self: Any, *args: P.args, **kwargs: P.kwargs) -> int:
        return add(self, kind, *args, **kwargs)

    sig = inspect.signature(add)  # help() and type checkers see it without `kind`
    params = [p for p in sig.parameters.values() if p.name != "kind"]
    method.__signature__ = sig.replace(parameters=params)  # type: ignore[attr-defined]
    method.__name__, method.__qualname__, method.__doc__ = f"add_{kind}", f"add_{kind}", doc
    return method


class ShapesMixin:
    """The methods of :class:`lcpsim.World` for capsules, cylinders, hulls, meshes and
    collision bits."""

    _core: Any

    def _add_round(
        self,
        kind: str,
        radius: float,
        half_length: float,
        mass: float = _BODY["mass"],
        position: Vec = tuple(_BODY["position"]),
        orientation: Vec = tuple(_BODY["orientation"]),
        velocity: Vec = tuple(_BODY["velocity"]),
        angular_velocity: Vec = tuple(_BODY["angular_velocity"]),
        mu: float = _BODY["mu"],
        *,
        static: bool = _BODY["static"],
        inertia: ArrayLike | None = None,
        contype: int = _BODY["contype"],
        conaffinity: int = _BODY["conaffinity"],
    ) -> int:
        """A capsule or cylinder (``kind``) of ``radius`` and ``half_length`` along body z."""
        v, wv = _velocities(velocity, angular_velocity)
        size = (_real(radius, "radius"), _real(half_length, "half_length"))
        return self._filtered(contype, conaffinity, lambda: self._core.add_body(
            kind, size, mass, position, orientation, v, wv, mu, bool(static), inertia))

    add_capsule = _for_kind(_add_round, "capsule", "Adds a capsule (a segment of ±``half_length`` along body z, "
                            "swept by ``radius``) and returns its index.")
    add_cylinder = _for_kind(_add_round, "cylinder", "Adds a solid cylinder, axis along the body's z (as in "
                             "MJCF), and returns its index.")

    def add_convex(
        self,
        vertices: ArrayLike,
        mass: float = _BODY["mass"],
        position: Vec = tuple(_BODY["position"]),
        orientation: Vec = tuple(_BODY["orientation"]),
        velocity: Vec = tuple(_BODY["velocity"]),
        angular_velocity: Vec = tuple(_BODY["angular_velocity"]),
        mu: float = _BODY["mu"],
        *,
        static: bool = _BODY["static"],
        inertia: ArrayLike | None = None,
        contype: int = _BODY["contype"],
        conaffinity: int = _BODY["conaffinity"],
    ) -> int:
        """Adds the convex hull of ``vertices`` ((N, 3), ≥ 4 not in one plane, ≤ MAX_HULL_POINTS);
        the body frame is at the solid hull's centre of mass (``position`` places it;
        ``body(i).com_offset`` is where it was among the points), inertia its full tensor."""
        pts = points_array(vertices, "vertices", MAX_HULL_POINTS)
        v, wv = _velocities(velocity, angular_velocity)
        return self._filtered(contype, conaffinity, lambda: self._core.add_body(
            "convex", pts, mass, position, orientation, v, wv, mu, bool(static), inertia))

    def add_compound(
        self,
        parts: Sequence[Mapping[str, Any]],
        mass: float = _BODY["mass"],
        position: Vec = tuple(_BODY["position"]),
        orientation: Vec = tuple(_BODY["orientation"]),
        velocity: Vec = tuple(_BODY["velocity"]),
        angular_velocity: Vec = tuple(_BODY["angular_velocity"]),
        mu: float = _BODY["mu"],
        *,
        static: bool = _BODY["static"],
        inertia: ArrayLike | None = None,
        com: Vec | None = None,
        contype: int = _BODY["contype"],
        conaffinity: int = _BODY["conaffinity"],
    ) -> int:
        """Adds one rigid body made of several solid ``parts`` (a table of a top and legs, a
        dumbbell), each a dict: ``kind`` ("box", "sphere", "capsule", "cylinder", "convex"),
        its size (``half_extents``; ``radius``; ``radius`` and ``half_length``; ``vertices``),
        and its ``position`` and ``orientation`` (w, x, y, z) in the compound's frame (default
        origin, identity; a hull's points are in its part's frame). As :meth:`add_convex`, the
        body frame is at the centre of mass of the parts at uniform density (overlaps count
        twice), ``position`` places that centre and ``body(i).com_offset`` says where it was in
        the parts' frame; ``inertia`` (body frame) overrides the parts' own. ``com`` (in the
        parts' frame) puts the centre of mass elsewhere, for a density that is not uniform
        (give ``inertia`` with it). ``body(i).parts`` gives the parts back, their poses about
        the centre of mass."""
        items = (compound_parts(parts), None if com is None else _vec(com, "com"))
        v, wv = _velocities(velocity, angular_velocity)
        return self._filtered(contype, conaffinity, lambda: self._core.add_body(
            "compound", items, mass, position, orientation, v, wv, mu, bool(static), inertia))

    def add_mesh(
        self,
        vertices: ArrayLike,
        faces: ArrayLike,
        mu: float = _BODY["mu"],
        *,
        position: Vec = tuple(_BODY["position"]),
        orientation: Vec = tuple(_BODY["orientation"]),
        contype: int = _BODY["contype"],
        conaffinity: int = _BODY["conaffinity"],
    ) -> int:
        """Adds a static triangle mesh: ``vertices`` (N, 3) in its frame (placed by ``position``,
        ``orientation``), ``faces`` (M, 3) indices; limits MAX_MESH_VERTICES, MAX_MESH_FACES."""
        pts = points_array(vertices, "vertices", MAX_MESH_VERTICES)
        f = faces_array(faces, MAX_MESH_FACES)
        return self._filtered(contype, conaffinity, lambda: self._core.add_mesh(pts, f, mu, position, orientation))

    def add_heightfield(
        self,
        heights: ArrayLike,
        size: Vec,
        mu: float = _BODY["mu"],
        *,
        position: Vec = tuple(_BODY["position"]),
        orientation: Vec = tuple(_BODY["orientation"]),
        contype: int = _BODY["contype"],
        conaffinity: int = _BODY["conaffinity"],
    ) -> int:
        """Adds static terrain: ``heights`` (nrow, ncol), both ≥ 2, the surface's z on a grid
        over x ∈ [−size[0], size[0]] (columns) and y ∈ [−size[1], size[1]] (rows, row 0 at
        −size[1], as MJCF's ``hfield``), in its frame (placed by ``position``, ``orientation``);
        solids rest on its top. At most MAX_HFIELD_POINTS points."""
        h = as_real_array(heights, "heights", 2)
        if h.shape[0] < 2 or h.shape[1] < 2:
            raise ValueError(f"heights must be an (nrow, ncol) array with nrow, ncol >= 2, got shape {h.shape}")
        if h.size > MAX_HFIELD_POINTS:
            raise ValueError(f"heights has {h.size} points, more than the limit of {MAX_HFIELD_POINTS}")
        hx, hy = _vec(size, "size", 2)
        h = np.ascontiguousarray(h, dtype=np.float64)
        return self._filtered(contype, conaffinity, lambda: self._core.add_heightfield(
            h, hx, hy, mu, position, orientation))

    def _filtered(self, contype: Any, conaffinity: Any, add: Callable[[], Any]) -> int:
        """``add()``'s body with its collision bits, checked first: bad bits add nothing."""
        bits = collision_bits(contype, conaffinity)
        index = int(add())
        if bits != (_BODY["contype"], _BODY["conaffinity"]):
            self._core.set_collision_filter(index, *bits)
        return index

    def set_collision_filter(self, body: int, contype: int, conaffinity: int) -> None:
        """Sets which bodies ``body`` may touch, by MuJoCo's rule: two bodies collide iff
        ``(contype1 & conaffinity2) | (contype2 & conaffinity1) != 0``. Every ``add_*``
        takes ``contype``, ``conaffinity`` too (default 1, 1: everything collides)."""
        self._core.set_collision_filter(body, *collision_bits(contype, conaffinity))

    def exclude_pair(self, body_a: int, body_b: int) -> None:
        """Keeps two different bodies from touching, whatever their collision bits
        (MJCF's ``<contact><exclude>``; MuJoCo's parent filter in :meth:`from_mjcf`)."""
        self._core.exclude_pair(body_a, body_b)

    def excluded_pairs(self) -> list[tuple[int, int]]:
        """The pairs :meth:`exclude_pair` keeps apart, lower index first, sorted."""
        return [(int(a), int(b)) for a, b in self._core.excluded_pairs()]

    def add_contact_pair(self, body_a: int, body_b: int, mu: float) -> None:
        """Makes two different bodies (not both static) touch whatever their collision bits
        and exclusions, their contacts with friction ``mu`` (0: frictionless) in place of the
        bodies' combined μ (MJCF's ``<contact><pair>``; ``World(mu_override=...)`` still wins). Bodies
        joined by a joint still never touch. Given again, the pair takes the new ``mu``."""
        self._core.add_contact_pair(body_a, body_b, mu)

    def contact_pairs(self) -> list[tuple[int, int, float]]:
        """The pairs :meth:`add_contact_pair` makes touch, ``(body_a, body_b, mu)``, lower
        index first, sorted."""
        return [(int(a), int(b), float(mu)) for a, b, mu in self._core.contact_pairs()]

    def collision_filter(self, body: int) -> tuple[int, int]:
        """``(contype, conaffinity)`` of a body."""
        d = self._core.body(body)
        return int(d["contype"]), int(d["conaffinity"])
