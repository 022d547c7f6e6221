"""MJCF scenes through MuJoCo's own compiler (``pip install lcpsim[mjcf]``).

::

    from lcpsim import World
    w = World.from_mjcf("scene.xml")          # or an XML string starting with "<"
    ball = w.body_id("ball")

The model is compiled by ``mujoco.MjModel`` and read from its arrays
(``body_*``, ``geom_*``, ``mesh_*``, ``opt.timestep``, ``opt.gravity``), with
the poses of ``qpos0`` (``mj_forward``). What lcpsim can simulate exactly:

- moving bodies (a joint, or welded to a moving body) with one colliding
  geom or several (sphere, box, capsule, cylinder, mesh — a mesh as the
  convex hull of its vertices, as MuJoCo collides it); geoms with ``contype``
  and ``conaffinity`` both 0 are visual and skipped; mass and inertia are the
  compiled ``body_mass``, ``body_inertia`` (turned into the geom's frame).
  Several geoms (or one off its body's centre of mass) make one compound body
  (:meth:`lcpsim.World.add_compound`) at the compiled ``xipos``/``ximat``, its
  geoms sharing one friction and one ``contype``/``conaffinity``;
- ``hinge``, ``slide`` and ``ball`` joints, one per body, between a body and
  its parent (the world when the parent is the world or welded to it): anchor
  ``xanchor`` and axis ``xaxis`` at ``qpos0``, ``range`` (when ``limited``) as
  the joint's limits, measured from ``qpos0``; bodies nested in bodies, a body
  with no joint welded to its moving parent (``add_fixed``), a massless one
  with no joint and no colliding geom (a frame) skipped, its children hung on
  the body above it;
- MuJoCo's body filter: a body never touches its own weld group (itself and
  the bodies welded to it) nor, unless the flag ``filterparent`` is disabled,
  its parent's weld group when neither group is the world's
  (``body_weldid``, ``body_parentid``; :meth:`lcpsim.World.exclude_pair` for
  the pairs that no joint already keeps apart), and ``<contact><exclude>``
  pairs; with ``filterparent`` disabled, a body on a joint to a moving body
  that its bits let touch is refused (lcpsim never collides bodies joined by a joint);
- ``<velocity>`` actuators on a hinge or slide joint with a symmetric
  ``forcerange``: a motor on the joint (``kv`` is not used: lcpsim's motor is a
  hard velocity constraint with the force bound), driven by
  :meth:`lcpsim.World.set_control` (``ctrl`` starts at 0: the joint is held still);
- static geoms of the world body and of bodies welded to it (plane, box,
  sphere, capsule, cylinder, mesh as its convex hull, ``hfield`` as a height
  field: :meth:`lcpsim.World.add_heightfield` of the compiled ``hfield_data``
  times its elevation ``size[2]``, from elevation data or a PNG alike; its
  ``base`` below the surface is not a solid);
- μ = ``geom_friction[0]`` (0 for a frictionless geom, ``condim`` 1), combined by
  ``max`` as MuJoCo does (unless ``mu_combine`` is given): geoms of one
  ``priority``, ``condim`` 1, 3 or 4, no condim-1 geom with more friction than a
  condim-3 or 4 one (MuJoCo's pair would slide with it); with ``condim`` 4 the
  torsional friction ``friction[1]`` (:meth:`lcpsim.World.set_torsional_friction`:
  bounded by the patch's normal force where MuJoCo bounds each contact point's,
  the same total over a face; a single point has none), no condim-1 or 3 geom
  with a larger ``friction[1]`` than a condim-4 one; ``dt`` = ``opt.timestep``, ``gravity`` = ``opt.gravity``;
- the friction cone ``opt.cone``: MuJoCo's default ``pyramidal`` cone of a condim-3 contact is
  the pyramid with the 4 edges n ± μ t1, n ± μ t2, lcpsim's polyhedral cone with
  ``friction_dirs`` = 4 (±t1, ±t2), which is then the default; under ``elliptic`` (the round
  cone) the default stays 8 directions, a polyhedral stand-in for the circle. A caller's
  ``friction_dirs=`` always wins;
- the option flags that turn off gravity (zero gravity), contacts or all
  constraints (no contacts, no joint limits), joint limits, dampers, springs
  and friction loss (not read); ``override`` enabled and ``actuation``
  disabled with actuators are refused;
- ``geom_contype``, ``geom_conaffinity`` as each body's collision bits (MuJoCo's
  rule: two geoms collide iff ``(contype1 & conaffinity2) | (contype2 & conaffinity1)``);
- ``<contact><pair>`` (``pair_geom1``, ``pair_geom2``) as :meth:`lcpsim.World.add_contact_pair`:
  the two geoms' bodies touch whatever their bits, exclusions and body filter, with the
  pair's ``friction[0]`` (0 at ``condim`` 1) in place of the geoms'; a geom with both bits 0
  is built when a pair names it. Refused naming the pair: ``condim`` 4 or 6, a ``margin``
  or ``gap``, different friction in the two sliding directions, a geom of ``condim`` 4, a geom
  sharing its moving body with other colliding geoms, two bodies joined by a joint or welded.

Everything else is refused with :class:`MjcfError` (a ``ValueError``) naming
the element and its name: fluid forces (``density``, ``viscosity``), a body's
``gravcomp``, ``condim`` 6 (rolling friction),
geoms of different ``priority``, a geom ``margin`` (MuJoCo's bodies rest that far apart), several joints on one body, a ball joint's
``range``, joint stiffness, a ball joint's damping (a hinge's or slide's is
the joint's ``damping``), armature or friction loss, a moving body with no
colliding geom, a body's geoms of different friction or collision bits, other
actuators (motor, position, ...; a
velocity actuator without a symmetric ``forcerange`` or on a ball joint),
ellipsoids, height fields on moving bodies, SDFs, tendons and equality constraints.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

__all__ = ["MjcfError", "MjcfScene", "load_mjcf", "GEOM_TYPES"]

#: MuJoCo's ``mjtGeom`` codes, by name.
GEOM_TYPES = {0: "plane", 1: "hfield", 2: "sphere", 3: "capsule", 4: "ellipsoid", 5: "cylinder", 6: "box", 7: "mesh", 8: "sdf"}
_JOINT_TYPES = {0: "free", 1: "ball", 2: "slide", 3: "hinge"}


class MjcfError(ValueError):
    """An MJCF model lcpsim cannot simulate (or MuJoCo could not compile); one line."""


@dataclass
class MjcfScene:
    """What :func:`load_mjcf` built: the world, body names → indices, and MuJoCo's model."""

    world: Any  # the lcpsim.World built
    names: dict[str, int]
    model: Any


def _mujoco() -> Any:
    try:
        import mujoco  # type: ignore[import-untyped,unused-ignore]
    except ImportError:
        raise MjcfError("MJCF needs MuJoCo: pip install 'lcpsim[mjcf]' (or pip install mujoco)") from None
    return mujoco


def _name(mujoco: Any, m: Any, kind: Any, i: int) -> str:
    n = mujoco.mj_id2name(m, kind, i)
    return n if n else f"#{i}"


def _quat_of(mujoco: Any, mat: NDArray[np.float64]) -> NDArray[np.float64]:
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(mat, dtype=np.float64).reshape(9))
    return q


def compile_model(source: str | os.PathLike[str]) -> Any:
    """``mujoco.MjModel`` from a path or an XML string (starting with ``<``)."""
    mujoco = _mujoco()
    try:
        if isinstance(source, str) and source.lstrip().startswith("<"):
            return mujoco.MjModel.from_xml_string(source)
        path = os.fspath(source)
        if not os.path.exists(path):
            raise MjcfError(f"MJCF file {path!r} does not exist")
        return mujoco.MjModel.from_xml_path(path)
    except MjcfError:
        raise
    except Exception as e:  # MuJoCo's compiler errors (ValueError, mujoco.FatalError, ...)
        msg = " ".join(str(e).split())
        raise MjcfError(f"MuJoCo could not compile the model: {msg}") from None


def load_mjcf(source: str | os.PathLike[str], new_world: Callable[..., Any], **world_kwargs: Any) -> MjcfScene:
    """Builds a world with ``new_world(**world_kwargs)`` (:class:`lcpsim.World`; the model's time
    step and gravity unless given) from an MJCF file or string (see the module docs)."""
    mujoco = _mujoco()
    m = compile_model(source)
    OBJ = mujoco.mjtObj
    _check_model(mujoco, m)
    _check_joints(mujoco, m)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)

    # Which bodies move: those with a joint, and those welded (no joint) to a moving body.
    moving = np.zeros(m.nbody, dtype=bool)
    for b in range(1, m.nbody):  # parents come before their children
        parent = int(m.body_parentid[b])
        moving[b] = int(m.body_jntnum[b]) > 0 or bool(moving[parent])

    colliding = [g for g in range(m.ngeom) if int(m.geom_contype[g]) != 0 or int(m.geom_conaffinity[g]) != 0]
    pairs = _contact_pairs(mujoco, m)
    # Geoms that only touch through a <pair> (bits 0, 0) are built too: their pairs go past the bits.
    built = sorted(set(colliding).union(*((g1, g2) for g1, g2, _mu, _name in pairs)))
    for g in built:
        t = int(m.geom_type[g])
        if t in (4, 8):
            raise MjcfError(f"geom {_name(mujoco, m, OBJ.mjOBJ_GEOM, g)!r} is a {GEOM_TYPES[t]}, which is not supported")
        if t == 1 and moving[int(m.geom_bodyid[g])]:
            raise MjcfError(f"geom {_name(mujoco, m, OBJ.mjOBJ_GEOM, g)!r} is an hfield on a moving body (terrain is static)")
    _check_friction_model(mujoco, m, colliding)
    per_body: dict[int, list[int]] = {}
    for g in built:
        per_body.setdefault(int(m.geom_bodyid[g]), []).append(g)
    _check_pair_geoms(mujoco, m, pairs, per_body, moving)
    # A massless body with no joint and no colliding geom under a moving body is a
    # frame (a site, a camera mount): it adds nothing, its children hang on its parent.
    frame = np.zeros(m.nbody, dtype=bool)
    for b in range(1, m.nbody):
        frame[b] = moving[b] and int(m.body_jntnum[b]) == 0 and b not in per_body and float(m.body_mass[b]) == 0.0
    compound: dict[int, list[int]] = {}  # moving bodies made of several geoms (or one off its centre of mass)
    for b in range(1, m.nbody):
        if moving[b] and not frame[b]:
            gs = per_body.get(b, [])
            bname = _name(mujoco, m, OBJ.mjOBJ_BODY, b)
            if not gs:
                raise MjcfError(f"body {bname!r} has no colliding geom (a moving body needs at least one)")
            if len(gs) > 1 or _off_centre(m, d, gs[0], b):
                _check_same_surface(mujoco, m, gs, bname)
                compound[b] = gs
    if "dt" not in world_kwargs and not float(m.opt.timestep) > 0.0:
        raise MjcfError(f"option timestep must be > 0 (it is lcpsim's dt), got {float(m.opt.timestep)!r}")
    world_kwargs.setdefault("dt", float(m.opt.timestep))
    world_kwargs.setdefault("gravity", (0.0, 0.0, 0.0) if _disabled(m, "GRAVITY") else tuple(float(x) for x in m.opt.gravity))
    world_kwargs.setdefault("mu_combine", "max")
    world_kwargs.setdefault("friction_dirs", _friction_dirs(mujoco, m))
    world = new_world(**world_kwargs)
    names: dict[str, int] = {}
    body_index: dict[int, int] = {}  # a moving MuJoCo body -> its lcpsim body
    of_body: dict[int, list[int]] = {}  # a MuJoCo body -> its lcpsim bodies (a static one: one per geom)
    of_geom: dict[int, int] = {}  # a built geom -> its lcpsim body
    try:
        for g in built:
            b = int(m.geom_bodyid[g])
            if b in compound:
                if g == compound[b][0]:
                    body_index[b] = _add_compound(mujoco, m, d, world, compound[b], b, names)
                    of_body[b] = [body_index[b]]
                of_geom[g] = body_index[b]
                continue
            idx = _add_geom(mujoco, m, d, world, g, b, bool(moving[b]), names)
            of_geom[g] = idx
            of_body.setdefault(b, []).append(idx)
            if moving[b]:
                body_index[b] = idx
    except ValueError as e:
        raise MjcfError(f"geom {_name(mujoco, m, OBJ.mjOBJ_GEOM, g)!r}: {e}") from None
    joined: set[tuple[int, int]] = set()
    joint_index = _add_joints(mujoco, m, d, world, moving & ~frame, body_index, joined)
    _exclude_filtered(mujoco, m, world, body_index, of_body, joined)
    if _disabled(m, "CONTACT") or _disabled(m, "CONSTRAINT"):  # no contact at all
        for i in range(world.body_count):
            world.set_collision_filter(i, 0, 0)
    else:
        _add_contact_pairs(world, pairs, of_geom, joined, body_index)
    world._actuators = _actuators(mujoco, m, world, joint_index)
    world.scene = "mjcf"
    world.scene_params = {"source": source if not (isinstance(source, str) and source.lstrip().startswith("<")) else "<xml>"}
    world._body_names = dict(names)
    return MjcfScene(world, names, m)


def _check_model(mujoco: Any, m: Any) -> None:
    """Refuses the whole-model features lcpsim has no counterpart for, naming them."""
    OBJ = mujoco.mjtObj
    for count, what, kind in (
        (m.ntendon, "tendon", OBJ.mjOBJ_TENDON),
        (m.neq, "equality", OBJ.mjOBJ_EQUALITY),
    ):
        if count:
            raise MjcfError(f"{what} {_name(mujoco, m, kind, 0)!r} is not supported (lcpsim: bodies, joints, velocity actuators)")
    if m.nu and _disabled(m, "ACTUATION"):
        raise MjcfError("option flag actuation is disabled with actuators in the model, which is not supported")
    for field in ("density", "viscosity"):
        if float(getattr(m.opt, field)) != 0.0:
            raise MjcfError(f"option {field}={float(getattr(m.opt, field)):g} (fluid forces) is not supported")
    for b in range(1, m.nbody):
        if float(m.body_gravcomp[b]) != 0.0:
            raise MjcfError(f"body {_name(mujoco, m, OBJ.mjOBJ_BODY, b)!r} has gravcomp={float(m.body_gravcomp[b]):g} "
                            "(gravity compensation), which is not supported")
    if int(m.opt.enableflags) & int(mujoco.mjtEnableBit.mjENBL_OVERRIDE):
        raise MjcfError("option flag override is enabled (o_margin, o_solref, o_friction), which is not supported")


#: lcpsim's friction directions for MuJoCo's cone (``opt.cone``) when the caller gives none.
CONE_FRICTION_DIRS = {"pyramidal": 4, "elliptic": 8}


def _friction_dirs(mujoco: Any, m: Any) -> int:
    """The model's cone as lcpsim's ``friction_dirs``: MuJoCo's pyramidal cone (edges n ± μ t1,
    n ± μ t2) is exactly lcpsim's 4-direction cone; its elliptic (round) cone gets 8 directions."""
    elliptic = int(m.opt.cone) == int(mujoco.mjtCone.mjCONE_ELLIPTIC)
    return CONE_FRICTION_DIRS["elliptic" if elliptic else "pyramidal"]


def _disabled(m: Any, flag: str) -> bool:
    """Whether the option flag ``mjDSBL_<flag>`` is set (``<flag gravity="disable"/>``, ...)."""
    return bool(int(m.opt.disableflags) & int(getattr(_mujoco().mjtDisableBit, f"mjDSBL_{flag}")))


def _check_joints(mujoco: Any, m: Any) -> None:
    """Refuses what the joints cannot express: several joints on a body, a
    limited ball joint, joint springs, a ball joint's damping, armature or friction loss."""
    OBJ = mujoco.mjtObj
    for b in range(1, m.nbody):
        n = int(m.body_jntnum[b])
        if n > 1:
            first = int(m.body_jntadr[b])
            kinds = "+".join(_JOINT_TYPES.get(int(m.jnt_type[j]), str(int(m.jnt_type[j]))) for j in range(first, first + n))
            raise MjcfError(
                f"body {_name(mujoco, m, OBJ.mjOBJ_BODY, b)!r} has {n} joints ({kinds}); "
                "lcpsim takes one joint per body (hinge, slide, ball or free)"
            )
    for j in range(m.njnt):
        jt = int(m.jnt_type[j])
        what = f"joint {_name(mujoco, m, OBJ.mjOBJ_JOINT, j)!r} ({_JOINT_TYPES.get(jt, jt)})"
        if jt == 1 and bool(m.jnt_limited[j]):
            raise MjcfError(f"{what} has a range: cone limits of ball joints are not supported")
        dofs = range(int(m.jnt_dofadr[j]), int(m.jnt_dofadr[j]) + {0: 6, 1: 3}.get(jt, 1))
        # Hinge and slide damping becomes the joint's (`_add_joint`).
        damping = 0.0 if jt in (2, 3) or _disabled(m, "DAMPER") else max(abs(float(m.dof_damping[k])) for k in dofs)
        off = _disabled(m, "CONSTRAINT") or _disabled(m, "FRICTIONLOSS")
        for field, value in (
            ("stiffness", 0.0 if _disabled(m, "SPRING") else float(m.jnt_stiffness[j])),
            ("damping", damping),
            ("armature", max(abs(float(m.dof_armature[k])) for k in dofs)),
            ("frictionloss", 0.0 if off else max(abs(float(m.dof_frictionloss[k])) for k in dofs)),
        ):
            if value != 0.0:
                raise MjcfError(f"{what} has {field}={value:g}, which is not supported")


def _add_joints(
    mujoco: Any, m: Any, d: Any, world: Any, moving: NDArray[np.bool_], body_index: dict[int, int],
    joined: set[tuple[int, int]],
) -> dict[int, int]:
    """Each moving body's joint to its parent (``None``: the world or a static
    body): hinge, slide and ball at MuJoCo's anchor and axis at ``qpos0``,
    ranges as limits (relative to ``qpos0``); a body with no joint welded to
    its parent; ``moving`` leaves out frames (their children hang on the nearest
    body above them). A freejoint adds nothing. Returns MuJoCo's joint id -> lcpsim's;
    ``joined`` gets the pairs of lcpsim bodies a joint or weld joins (lower index first)."""
    out: dict[int, int] = {}
    for b in range(1, m.nbody):
        if not moving[b]:
            continue
        parent = int(m.body_parentid[b])
        while parent not in body_index and int(m.body_weldid[parent]) != 0:  # past frames
            parent = int(m.body_parentid[parent])
        a = body_index.get(parent)
        child = body_index[b]
        if a is not None and not (int(m.body_jntnum[b]) == 1 and int(m.jnt_type[int(m.body_jntadr[b])]) == 0):
            joined.add((min(a, child), max(a, child)))
        try:
            _add_joint(m, d, world, a, child, b, out)
        except ValueError as e:
            raise MjcfError(f"body {_name(mujoco, m, mujoco.mjtObj.mjOBJ_BODY, b)!r}: {e}") from None
    return out


def _add_joint(m: Any, d: Any, world: Any, a: int | None, child: int, b: int, out: dict[int, int]) -> None:
    """Body ``b``'s joint (or weld) to ``a`` (None: the world), recorded in ``out``."""
    if int(m.body_jntnum[b]) == 0:
        world.add_fixed(a, child)
        return
    j = int(m.body_jntadr[b])
    jt = int(m.jnt_type[j])
    anchor = tuple(float(x) for x in d.xanchor[j])
    axis = tuple(float(x) for x in d.xaxis[j])
    limits = None
    if jt in (2, 3) and bool(m.jnt_limited[j]) and not (_disabled(m, "LIMIT") or _disabled(m, "CONSTRAINT")):
        q0 = float(m.qpos0[int(m.jnt_qposadr[j])])
        limits = (float(m.jnt_range[j][0]) - q0, float(m.jnt_range[j][1]) - q0)
    damping = 0.0 if _disabled(m, "DAMPER") else float(m.dof_damping[int(m.jnt_dofadr[j])])
    if jt == 3:
        out[j] = world.add_hinge(a, child, anchor, axis, limits=limits, damping=damping)
    elif jt == 2:
        out[j] = world.add_slider(a, child, anchor, axis, limits=limits, damping=damping)
    elif jt == 1:
        out[j] = world.add_ball(a, child, anchor)


def _exclude_filtered(
    mujoco: Any, m: Any, world: Any, body_index: dict[int, int], of_body: dict[int, list[int]],
    joined: set[tuple[int, int]],
) -> None:
    """MuJoCo's body filter as excluded pairs (``filterBodyPair``): bodies of one weld
    group never touch, nor (``filterparent`` on) a group and its parent's unless either is
    the world's; then the ``<contact><exclude>`` pairs. Pairs a joint already joins are
    left out. With ``filterparent`` off, MuJoCo collides a jointed body with its moving
    parent, which lcpsim cannot: refused when their bits let them touch."""
    weld = {b: int(m.body_weldid[b]) for b in body_index}
    groups: dict[int, list[int]] = {}
    for b, w in weld.items():
        groups.setdefault(w, []).append(b)
    filter_parent = not _disabled(m, "FILTERPARENT")
    excluded: set[tuple[int, int]] = set()

    def keep_apart(xs: list[int], ys: list[int]) -> None:
        for x in xs:
            for y in ys:
                p = (min(x, y), max(x, y))
                if x != y and p not in joined:
                    excluded.add(p)

    for w, members in groups.items():
        ours = [body_index[b] for b in members]
        keep_apart(ours, ours)
        parent = int(m.body_weldid[int(m.body_parentid[w])])
        if filter_parent and parent != 0 and parent in groups:
            keep_apart(ours, [body_index[b] for b in groups[parent]])
    for e in range(m.nexclude):
        sig = int(m.exclude_signature[e])
        keep_apart(of_body.get((sig >> 16) - 1, []), of_body.get((sig & 0xFFFF) - 1, []))
    if not filter_parent:
        OBJ = mujoco.mjtObj
        by_lcpsim = {i: b for b, i in body_index.items()}
        for x, y in sorted(joined):
            bx, by = by_lcpsim[x], by_lcpsim[y]
            (tx, ax), (ty, ay) = world.collision_filter(x), world.collision_filter(y)
            if weld[bx] == weld[by] or (x, y) in excluded or not (tx & ay) | (ty & ax):
                continue
            raise MjcfError(
                f"bodies {_name(mujoco, m, OBJ.mjOBJ_BODY, bx)!r} and {_name(mujoco, m, OBJ.mjOBJ_BODY, by)!r} "
                "are joined by a joint and filterparent is disabled: MuJoCo collides them, "
                "lcpsim never collides bodies joined by a joint"
            )
    for x, y in sorted(excluded):
        world.exclude_pair(x, y)


def _contact_pairs(mujoco: Any, m: Any) -> list[tuple[int, int, float, str]]:
    """The ``<contact><pair>`` elements as ``(geom1, geom2, μ, name)``: μ = the pair's
    ``friction[0]`` (0 at ``condim`` 1), as MuJoCo takes it, whatever the geoms' own friction
    and bits. Refused naming the pair: ``condim`` 4 or 6 (torsional, rolling friction), a
    ``margin`` or ``gap``, friction that differs between the two sliding directions."""
    out = []
    for p in range(m.npair):
        what = f"contact pair {_name(mujoco, m, mujoco.mjtObj.mjOBJ_PAIR, p)!r}"
        dim = int(m.pair_dim[p])
        if dim not in (1, 3):
            raise MjcfError(f"{what} has condim={dim} (torsional or rolling friction), which is not "
                            "supported: lcpsim's friction is sliding only (condim 1 or 3)")
        for field in ("margin", "gap"):
            value = float(getattr(m, f"pair_{field}")[p])
            if value != 0.0:
                raise MjcfError(f"{what} has {field}={value:g}, which is not supported: "
                                "MuJoCo's contacts then act apart, lcpsim's at touch")
        f1, f2 = float(m.pair_friction[p][0]), float(m.pair_friction[p][1])
        if dim == 3 and f1 != f2:
            raise MjcfError(f"{what} has friction {f1:g} and {f2:g} in its two sliding directions, "
                            "which is not supported: lcpsim's friction is the same in every direction")
        out.append((int(m.pair_geom1[p]), int(m.pair_geom2[p]), 0.0 if dim == 1 else f1, what))
    return out


def _check_pair_geoms(
    mujoco: Any, m: Any, pairs: list[tuple[int, int, float, str]], per_body: dict[int, list[int]],
    moving: NDArray[np.bool_],
) -> None:
    """lcpsim's contact pair joins two bodies: refuses a pair whose moving geom shares its
    body with other colliding geoms (the pair would take them along), or whose geom has
    torsional friction (``condim`` 4: the body's, which the pair's contacts would take), naming the pair."""
    for g1, g2, _mu, what in pairs:
        for g in (g1, g2):
            if _mu_torsion(m, g) > 0.0:
                raise MjcfError(f"{what}: geom {_name(mujoco, m, mujoco.mjtObj.mjOBJ_GEOM, g)!r} has condim=4 "
                                "(torsional friction), which lcpsim would give the pair's contacts too; "
                                "give the pair's geoms condim 1 or 3")
            b = int(m.geom_bodyid[g])
            if moving[b] and len(per_body[b]) > 1:
                raise MjcfError(
                    f"{what}: geom {_name(mujoco, m, mujoco.mjtObj.mjOBJ_GEOM, g)!r} is one of the "
                    f"{len(per_body[b])} colliding geoms of body {_name(mujoco, m, mujoco.mjtObj.mjOBJ_BODY, b)!r}, "
                    "which lcpsim makes one body: a pair must name a moving body's only colliding geom")


def _add_contact_pairs(
    world: Any, pairs: list[tuple[int, int, float, str]], of_geom: dict[int, int],
    joined: set[tuple[int, int]], body_index: dict[int, int],
) -> None:
    """Each pair as :meth:`lcpsim.World.add_contact_pair` of its geoms' bodies (past the bits,
    the exclusions and MuJoCo's body filter, as MuJoCo's explicit pairs are); a pair of two
    static geoms moves nothing and is left out; one across a joint is refused (lcpsim never
    collides bodies joined by a joint, MuJoCo's pair would)."""
    moving = set(body_index.values())
    for g1, g2, mu, what in pairs:
        a, b = of_geom[g1], of_geom[g2]
        if a not in moving and b not in moving:
            continue
        if a == b or (min(a, b), max(a, b)) in joined:
            raise MjcfError(f"{what} joins two geoms of bodies joined by a joint or welded: MuJoCo collides "
                            "them, lcpsim never collides bodies joined by a joint")
        world.add_contact_pair(a, b, mu)


@dataclass
class Actuator:
    """A ``<velocity>`` actuator as a joint motor: the control is the target
    rate of the actuator (``gear`` × the joint's), its force bounded by
    ``forcerange``; :meth:`lcpsim.World.set_control` drives it."""

    name: str
    joint: int  # lcpsim's joint index
    gear: float
    max_force: float
    ctrlrange: tuple[float, float] | None


def _actuators(mujoco: Any, m: Any, world: Any, joint_index: dict[int, int]) -> list[Actuator]:
    """``<velocity>`` actuators on hinge or slide joints with a symmetric
    ``forcerange``, each a motor held at speed 0 (MuJoCo's ``ctrl`` starts at
    0); every other actuator refused naming it."""
    OBJ = mujoco.mjtObj
    out: list[Actuator] = []
    used: set[int] = set()
    for u in range(m.nu):
        name = _name(mujoco, m, OBJ.mjOBJ_ACTUATOR, u)
        what = f"actuator {name!r}"
        kv = float(m.actuator_gainprm[u][0])
        velocity = (
            int(m.actuator_gaintype[u]) == 0
            and int(m.actuator_biastype[u]) == 1
            and int(m.actuator_dyntype[u]) == 0
            and kv > 0
            and float(m.actuator_biasprm[u][0]) == 0.0
            and float(m.actuator_biasprm[u][1]) == 0.0
            and float(m.actuator_biasprm[u][2]) == -kv
        )
        if not velocity:
            raise MjcfError(f"{what} is not supported (only <velocity> actuators on a hinge or slide joint)")
        if int(m.actuator_trntype[u]) != 0:
            raise MjcfError(f"{what} does not act on a joint (only joint transmissions are supported)")
        j = int(m.actuator_trnid[u][0])
        jt = int(m.jnt_type[j])
        if jt not in (2, 3):
            raise MjcfError(f"{what} drives the {_JOINT_TYPES.get(jt, jt)} joint {_name(mujoco, m, OBJ.mjOBJ_JOINT, j)!r} (only hinge or slide)")
        if j in used:
            raise MjcfError(f"{what} is a second actuator on joint {_name(mujoco, m, OBJ.mjOBJ_JOINT, j)!r} (one per joint)")
        used.add(j)
        lo, hi = (float(x) for x in m.actuator_forcerange[u])
        if not bool(m.actuator_forcelimited[u]) or lo != -hi or hi <= 0:
            raise MjcfError(f"{what} needs a symmetric forcerange (-f f), got limited={bool(m.actuator_forcelimited[u])} range=({lo:g}, {hi:g})")
        gear = float(m.actuator_gear[u][0])
        if gear == 0.0:
            raise MjcfError(f"{what} has gear 0")
        ctrl = None
        if bool(m.actuator_ctrllimited[u]):
            ctrl = (float(m.actuator_ctrlrange[u][0]), float(m.actuator_ctrlrange[u][1]))
        act = Actuator(name, joint_index[j], gear, abs(gear) * hi, ctrl)
        world.set_motor(act.joint, 0.0, act.max_force)
        out.append(act)
    return out


def _mesh(m: Any, g: int) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    k = int(m.geom_dataid[g])
    va, vn = int(m.mesh_vertadr[k]), int(m.mesh_vertnum[k])
    fa, fn = int(m.mesh_faceadr[k]), int(m.mesh_facenum[k])
    return np.array(m.mesh_vert[va : va + vn], dtype=np.float64), np.array(m.mesh_face[fa : fa + fn], dtype=np.int64)


def _off_centre(m: Any, d: Any, g: int, b: int) -> bool:
    """Whether body ``b``'s centre of mass is off the centre of its one geom ``g`` (a mesh's
    hull is placed at its own centre, which MuJoCo's compiled centre of mass is)."""
    if int(m.geom_type[g]) == 7:
        return False
    scale = max(1.0, float(np.max(np.abs(m.geom_size[g]))))
    return bool(np.linalg.norm(np.asarray(d.xipos[b]) - np.asarray(d.geom_xpos[g])) > 1e-6 * scale)


def _mu(m: Any, g: int) -> float:
    """Geom ``g``'s μ: ``friction[0]``, 0 for a frictionless geom (``condim`` 1)."""
    return 0.0 if int(m.geom_condim[g]) == 1 else float(m.geom_friction[g][0])


def _mu_torsion(m: Any, g: int) -> float:
    """Geom ``g``'s torsional friction: ``friction[1]`` with ``condim`` 4, else 0."""
    return float(m.geom_friction[g][1]) if int(m.geom_condim[g]) == 4 else 0.0


def _check_friction_model(mujoco: Any, m: Any, colliding: list[int]) -> None:
    """MuJoCo's friction of a pair as lcpsim's max of the two bodies' μ (:func:`_mu`). MuJoCo
    gives a pair the larger ``condim`` of its geoms and the larger ``friction[0]`` (both
    geoms' at equal ``priority``; the higher-priority geom's otherwise): exact when every
    colliding geom has one priority, ``condim`` is 1 (frictionless), 3 (sliding friction) or
    4 (and torsional, :func:`_mu_torsion`; 6 adds rolling friction, which lcpsim has not), no
    condim-1 geom has more friction than a condim-3 or 4 one (a pair of the two slides with
    the larger) and no condim-1 or 3 geom a larger ``friction[1]`` than a condim-4 one."""
    OBJ = mujoco.mjtObj
    name = lambda g: _name(mujoco, m, OBJ.mjOBJ_GEOM, g)  # noqa: E731
    for g in colliding:
        if float(m.geom_margin[g]) != 0.0:
            raise MjcfError(f"geom {name(g)!r} has margin={float(m.geom_margin[g]):g}, which is not supported: "
                            "MuJoCo's contacts then act that far apart (bodies rest apart), lcpsim's at touch")
        c = int(m.geom_condim[g])
        if c not in (1, 3, 4):
            raise MjcfError(f"geom {name(g)!r} has condim={c} (rolling friction), which is not "
                            "supported: lcpsim's friction is sliding and torsional only (condim 1, 3 or 4)")
    if colliding:
        first = colliding[0]
        for g in colliding:
            if int(m.geom_priority[g]) != int(m.geom_priority[first]):
                raise MjcfError(
                    f"geom {name(g)!r} has priority={int(m.geom_priority[g])} and geom {name(first)!r} "
                    f"priority={int(m.geom_priority[first])}: MuJoCo then takes the higher one's friction, "
                    "lcpsim combines by max; give every colliding geom one priority")
    frictionless = [g for g in colliding if int(m.geom_condim[g]) == 1]
    sliding = [g for g in colliding if int(m.geom_condim[g]) in (3, 4)]
    torsional = [g for g in colliding if int(m.geom_condim[g]) == 4]
    over = _exceeds(m, [g for g in colliding if g not in torsional], torsional, 1)
    if over:
        hi, lo, th, tl = over
        raise MjcfError(
            f"geom {name(hi)!r} (condim {int(m.geom_condim[hi])}, torsional friction {th:g}) and geom "
            f"{name(lo)!r} (condim 4, torsional friction {tl:g}): MuJoCo gives such a pair {th:g}, lcpsim "
            f"{tl:g}; give the other geoms a friction[1] <= {tl:g}")
    over = _exceeds(m, frictionless, sliding, 0)
    if over:
        hi, lo, fh, fl = over
        raise MjcfError(
            f"geom {name(hi)!r} (condim 1, friction {fh:g}) and geom {name(lo)!r} "
            f"(condim {int(m.geom_condim[lo])}, friction {fl:g}): MuJoCo slides such a pair with friction "
            f"{fh:g}, lcpsim's frictionless geom gives {fl:g}; give the condim-1 geoms a friction <= {fl:g}")


def _exceeds(m: Any, above: list[int], below: list[int], k: int) -> tuple[int, int, float, float] | None:
    """The geom of ``above`` with the largest ``friction[k]`` and the geom of ``below`` with
    the smallest, and the two values, when the first is larger (else None)."""
    if not above or not below:
        return None
    hi = max(above, key=lambda g: float(m.geom_friction[g][k]))
    lo = min(below, key=lambda g: float(m.geom_friction[g][k]))
    fh, fl = float(m.geom_friction[hi][k]), float(m.geom_friction[lo][k])
    return (hi, lo, fh, fl) if fh > fl else None


def _check_same_surface(mujoco: Any, m: Any, gs: list[int], bname: str) -> None:
    """The geoms of one moving body make one lcpsim body with one μ and one pair of
    collision bits: refuses geoms that differ in either, naming the body."""
    for field, values in (
        ("friction", [_mu(m, g) for g in gs]),
        ("torsional friction", [_mu_torsion(m, g) for g in gs]),
        ("contype", [int(m.geom_contype[g]) for g in gs]),
        ("conaffinity", [int(m.geom_conaffinity[g]) for g in gs]),
    ):
        if len(set(values)) > 1:
            raise MjcfError(
                f"body {bname!r} has colliding geoms of different {field} ({', '.join(map(str, values))}); "
                "the geoms of one moving body must share friction, contype and conaffinity"
            )


def _part(m: Any, g: int, pos: NDArray[np.float64], quat: NDArray[np.float64]) -> dict[str, Any]:
    """Geom ``g`` as a compound part at ``pos``, ``quat`` (a mesh as the hull of its vertices)."""
    t = int(m.geom_type[g])
    size = [float(x) for x in m.geom_size[g]]
    part: dict[str, Any] = {"position": pos, "orientation": quat}
    if t == 2:
        part.update(kind="sphere", radius=size[0])
    elif t == 3:
        part.update(kind="capsule", radius=size[0], half_length=size[1])
    elif t == 5:
        part.update(kind="cylinder", radius=size[0], half_length=size[1])
    elif t == 6:
        part.update(kind="box", half_extents=size[:3])
    elif t == 7:
        part.update(kind="convex", vertices=_mesh(m, g)[0])
    else:  # planes are never moving; the others were refused before
        raise ValueError(f"geom type {GEOM_TYPES.get(t, t)} cannot be part of a moving body")
    return part


def _add_compound(mujoco: Any, m: Any, d: Any, world: Any, gs: list[int], b: int, names: dict[str, int]) -> int:
    """Moving body ``b``'s geoms ``gs`` as one compound body at MuJoCo's compiled centre of
    mass and principal axes (``xipos``, ``ximat``), mass ``body_mass`` and inertia ``body_inertia``."""
    com = np.array(d.xipos[b], dtype=np.float64)
    ri = np.array(d.ximat[b], dtype=np.float64).reshape(3, 3)
    parts = []
    for g in gs:
        rot = ri.T @ np.array(d.geom_xmat[g], dtype=np.float64).reshape(3, 3)
        parts.append(_part(m, g, ri.T @ (np.array(d.geom_xpos[g], dtype=np.float64) - com), _quat_of(mujoco, rot)))
    idx = int(world.add_compound(
        parts, mass=float(m.body_mass[b]), position=com, orientation=_quat_of(mujoco, ri),
        mu=_mu(m, gs[0]), inertia=np.diag(np.array(m.body_inertia[b], dtype=np.float64)),
        com=(0.0, 0.0, 0.0), contype=int(m.geom_contype[gs[0]]), conaffinity=int(m.geom_conaffinity[gs[0]]),
    ))
    _finish(mujoco, m, world, idx, b, gs, True, names)
    return idx


def _hfield(m: Any, g: int) -> tuple[NDArray[np.float64], tuple[float, float]]:
    """Geom ``g``'s height field: (nrow, ncol) heights (``hfield_data``, normalized to
    [0, 1] by MuJoCo, times the elevation ``size[2]``; row 0 at −y) and its half sizes."""
    k = int(m.geom_dataid[g])
    nrow, ncol = int(m.hfield_nrow[k]), int(m.hfield_ncol[k])
    adr = int(m.hfield_adr[k])
    size = [float(x) for x in m.hfield_size[k]]
    data = np.array(m.hfield_data[adr : adr + nrow * ncol], dtype=np.float64).reshape(nrow, ncol)
    return data * size[2], (size[0], size[1])


def _add_geom(mujoco: Any, m: Any, d: Any, world: Any, g: int, b: int, moving: bool, names: dict[str, int]) -> int:
    """One colliding geom as an lcpsim body (static unless its body moves)."""
    t = int(m.geom_type[g])
    size = np.array(m.geom_size[g], dtype=np.float64)
    pos = np.array(d.geom_xpos[g], dtype=np.float64)
    rot = np.array(d.geom_xmat[g], dtype=np.float64).reshape(3, 3)
    # The body's pose times the geom's (not read back from geom_xmat): a free body's quat
    # from the file comes through unrounded.
    quat = np.zeros(4)
    mujoco.mju_mulQuat(quat, np.asarray(d.xquat[b], dtype=np.float64), np.asarray(m.geom_quat[g], dtype=np.float64))
    mu = _mu(m, g)
    bits = {"contype": int(m.geom_contype[g]), "conaffinity": int(m.geom_conaffinity[g])}
    kw: dict[str, Any] = {"position": pos, "orientation": quat, "mu": mu, **bits}
    if moving:
        ri = np.array(d.ximat[b], dtype=np.float64).reshape(3, 3)
        principal = np.diag(np.array(m.body_inertia[b], dtype=np.float64))
        i_geom = rot.T @ (ri @ principal @ ri.T) @ rot
        # Principal axes along the geom's (a box, a cylinder): the compiled diagonal as it is.
        kw["inertia"] = principal if np.array_equal(ri, rot) else 0.5 * (i_geom + i_geom.T)
        kw["mass"] = float(m.body_mass[b])
    else:
        kw["static"] = True
    if t == 0:  # plane: the geom's z is its normal
        n = rot[:, 2]
        idx = world.add_plane(tuple(n), float(n @ pos), mu, **bits)
    elif t == 1:
        heights, half = _hfield(m, g)
        idx = world.add_heightfield(heights, half, mu, position=pos, orientation=quat, **bits)
    elif t == 2:
        idx = world.add_sphere(float(size[0]), **kw)
    elif t == 3:
        idx = world.add_capsule(float(size[0]), float(size[1]), **kw)
    elif t == 5:
        idx = world.add_cylinder(float(size[0]), float(size[1]), **kw)
    elif t == 6:
        idx = world.add_box(half_extents=tuple(float(x) for x in size[:3]), **kw)
    elif t == 7:
        verts, _faces = _mesh(m, g)
        idx = world.add_convex(verts, **kw)
        off = world.body(idx).com_offset
        if off is not None and np.any(off != 0):
            # The hull's centre in the geom frame: move the body there.
            world._core.set_position(idx, tuple(pos + rot @ off))
    else:  # refused before
        raise ValueError(f"geom type {GEOM_TYPES.get(t, t)} is not supported")
    _finish(mujoco, m, world, int(idx), b, [g], moving, names)
    return int(idx)


def _finish(mujoco: Any, m: Any, world: Any, idx: int, b: int, gs: list[int], moving: bool, names: dict[str, int]) -> None:
    """The lcpsim body ``idx`` made of MuJoCo body ``b``'s geoms ``gs``: its torsional friction
    (the first geom's), and the names that find it — the body's when it moves, and each geom's
    unless a body of that name came first."""
    if _mu_torsion(m, gs[0]) > 0.0:
        world.set_torsional_friction(idx, _mu_torsion(m, gs[0]))
    bname = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b)
    if moving and bname:
        names[bname] = idx
    for g in gs:
        gname = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g)
        if gname:
            names.setdefault(gname, idx)
