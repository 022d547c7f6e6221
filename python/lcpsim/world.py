"""The simulator: a :class:`World` of rigid bodies stepped with the
Stewart–Trinkle / Anitescu–Potra contact LCP.

::

    from lcpsim import World
    w = World(dt=1e-3, cone_scale=None, method="lemke")
    w.add_ground(mu=0.5)
    cube = w.add_box(size=1.0, mass=1.0, position=(0, 0, 0.5))
    rec = w.step()                  # StepRecord: contacts, lcp_size, status, fn, fd, lam, ...
    traj = w.run(1000)              # Trajectory of numpy arrays
    traj.positions[-1, cube]

Conventions: SI units, gravity (0, 0, −9.81), quaternions
(w, x, y, z) rotating body → world, velocities ``[v; ω]`` in the world frame,
LCP unknowns ``z = [fn; fd; λ]`` (impulses in N·s, λ ≈ sliding speed in m/s).

The stepping loop runs in Rust (``run`` releases the GIL); this module only
converts. Invalid parameters — negative mass or μ, dt ≤ 0, a zero-size box, a
zero quaternion, NaN anywhere — raise :class:`ValueError` naming the field and
the value. A solver that fails is not an error: its status is in the record.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, fields
from typing import TYPE_CHECKING, Any, Mapping, Sequence, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core
from ._json import jsonable
from ._validate import real as _real, vec as _vec, velocities as _velocities
from .lcp import _new_object
from .scale import parse_cone_scale
from .stabilization import FIELDS as STABILIZATION_FIELDS, Stabilization, as_stabilization
from .joints import JointsMixin
from ._shapes import ShapesMixin
from .trajectory import NO_CONTACT, ContactLog, LcpStats, Trajectory, quat_angle

if TYPE_CHECKING:
    from .io.capture import CaptureWriter

__all__ = [
    "World",
    "StepRecord",
    "Trajectory",
    "BodyState",
    "Stabilization",
    "LcpStats",
    "NO_CONTACT",
    "ContactLog",
    "MU_COMBINE",
    "quat_angle",
]

#: Rules for combining two bodies' μ into the contact's μ.
MU_COMBINE: tuple[str, ...] = tuple(_core.MU_COMBINE)

# The defaults are the Rust ones (sim::WorldParams, sim::BodyDesc), read from the
# compiled module: this module declares none of its own.
_WORLD = _core.WORLD_DEFAULTS
_BODY = _core.BODY_DEFAULTS

Vec = Union[Sequence[float], NDArray[np.float64]]
CaptureTarget = Union[str, "os.PathLike[str]", "CaptureWriter", None]


@dataclass(frozen=True)
class BodyState:
    """One body: its shape, mass properties and current state."""

    index: int
    kind: str  # "box", "sphere", "plane", "capsule", "cylinder", "convex", "mesh", "compound" or "hfield"
    is_static: bool
    mass: float  # inf for static bodies
    mu: float
    position: NDArray[np.float64]
    orientation: NDArray[np.float64]  # (w, x, y, z)
    velocity: NDArray[np.float64]  # (6,): [v; ω]
    inertia: NDArray[np.float64]  # (3, 3), body frame
    half_extents: NDArray[np.float64] | None = None
    radius: float | None = None
    normal: NDArray[np.float64] | None = None
    offset: float | None = None
    tangent: NDArray[np.float64] | None = None
    downhill: NDArray[np.float64] | None = None
    half_length: float | None = None  # capsule, cylinder: half the axis length (body z)
    vertices: NDArray[np.float64] | None = None  # convex (body frame, centred), mesh (body frame)
    faces: NDArray[np.int64] | None = None  # convex, mesh: (M, 3) vertex indices
    com_offset: NDArray[np.float64] | None = None  # convex, compound: its centre of mass in the frame given
    parts: list[dict[str, Any]] | None = None  # compound: each part's kind, size, position, orientation (body frame)
    heights: NDArray[np.float64] | None = None  # hfield: (nrow, ncol) heights; half_extents its (x, y) half sizes


@dataclass(frozen=True)
class StepRecord:
    """What one step did.

    ``status`` is the LCP's status, or ``"no_contact"`` when there was no
    contact (nothing solved). ``residual`` is ``‖min(z, w)‖∞`` of the physical
    ``z`` on the unscaled LCP (N·s and m/s); ``solver_residual`` is what the
    solver saw (the scaled LCP). Per contact (``nc`` of them, ``k`` friction
    directions): ``fn`` (nc,), ``fd`` (nc, k), ``lam`` (nc,) in physical units
    (``λ = s·λ_scaled``), ``points``/``normals``/``tangents`` (nc, 3),
    ``directions`` (nc, k, 3) the friction directions ``d_j``, ``friction``
    (nc, 3) the friction impulse vector ``Σ_j fd_j d_j`` on body A, ``gaps``,
    ``mu``, ``body_a``/``body_b`` (the normal points from B to A). Contact ``islands``
    (one LCP each): ``island_of_contact`` (nc,), per island ``island_bodies``,
    ``island_lcp_size``/``pivots``/``residual``/``status``; ``status`` is "solved" iff every island
    was, else the first unsolved one's; ``pivots`` total, ``residual`` max.
    ``island_stage``: the stage of the solve chain that answered each island
    (``"previous_basis"``, ``"guessed_basis"``, ``"structured_lemke"``,
    ``"dense"``: see ``docs/architecture.md``; ``"none"`` when nothing was solved).
    ``island_entered``: how many ``z`` of the island's answer are positive that
    the basis its step started from (the previous step's, or every ``w``
    basic when cold) had nonbasic; each had to enter, one per pivot, so any
    pivoting run from that start takes at least that many pivots: beside
    ``island_pivots`` it shows how straight the solve went (−1 when not
    solved).
    ``island_body_eta``: each island's body-space backward error (every contact
    row judged on the scale of the velocities it relates; an answer passes
    when it is ≤ the solver's ``accept_tol``, 1e-9 by default). Only islands
    where a contact joins two bodies whose mobilities differ 100-fold or more
    (a heavy body on a light one) are checked, and only with the robust Lemke
    with warm starts (the default); 0 for the others and for a failed solve.
    ``parts``: 1, or the parts the step was taken in when a failed LCP had
    (a part of) it taken again as two halves (``World(max_halvings=)``); the
    contact fields, ``time``, ``dt`` and islands are then the last part's,
    ``pivots`` counts every attempt and the energy audit spans the step.
    ``joint_force``/``joint_torque`` (J, 3): what each joint's side A exerted
    on side B at the anchor over the step (N, N·m; mean over the step; limits
    and motors are in the contact fields). ``retakes``: the failed attempts, each a dict of ``time``, ``h``,
    ``pivots`` and its islands' ``lcp_size`` and ``status`` (tuples).
    ``zeroed``: the solve failed and its answer was not applied as it stood:
    the island applied its admissible part (impulses clipped at 0, friction
    scaled into the cone) times the factor in [0, 1] that minimizes the energy
    after the step, so a failed step adds no energy. Energy audit (J):
    ``energy_before``/``energy_after`` (kinetic + gravitational potential of
    the dynamic bodies), ``external_work`` (applied forces and torques;
    gravity is in the energies), ``stabilization_work`` (what the penetration
    correction put in: ``Σ fn·erp·|φ|/h`` over the penetrating contacts,
    Baumgarte's known energy gain), the joints' terms (``docs/joints.md``):
    ``motor_work`` (each motor's impulse times its joint's rate),
    ``joint_drift_work`` (the joints' drift correction, ``−λ·βC/h``, 0 for
    ideal joints) and ``joint_projection_energy`` (what the position
    projections after the step changed), and ``energy_created = after −
    before −`` all of those.
    """

    step: int
    time: float
    dt: float
    contacts: int
    friction_dirs: int
    lcp_size: int
    scale: float
    status: str
    pivots: int
    residual: float
    solver_residual: float
    min_z: float
    min_w: float
    max_complementarity: float
    zeroed: bool
    parts: int
    retakes: tuple[dict[str, Any], ...]
    energy_before: float
    energy_after: float
    external_work: float
    stabilization_work: float
    motor_work: float
    joint_drift_work: float
    joint_projection_energy: float
    fn: NDArray[np.float64]
    fd: NDArray[np.float64]
    lam: NDArray[np.float64]
    z: NDArray[np.float64]
    w: NDArray[np.float64]
    points: NDArray[np.float64]
    normals: NDArray[np.float64]
    tangents: NDArray[np.float64]
    directions: NDArray[np.float64]
    friction: NDArray[np.float64]
    gaps: NDArray[np.float64]
    mu: NDArray[np.float64]
    body_a: NDArray[np.int64]
    body_b: NDArray[np.int64]
    islands: int
    island_of_contact: NDArray[np.int64]
    island_bodies: tuple[NDArray[np.int64], ...]
    island_lcp_size: NDArray[np.int64]
    island_pivots: NDArray[np.int64]
    island_entered: NDArray[np.int64]
    island_residual: NDArray[np.float64]
    island_body_eta: NDArray[np.float64]
    island_status: tuple[str, ...]
    island_stage: tuple[str, ...]
    basis: NDArray[np.bool_] | None  # None when some island reported no basis
    joint_force: NDArray[np.float64]
    joint_torque: NDArray[np.float64]

    @property
    def ok(self) -> bool:
        """True when there was no LCP or it was solved."""
        return self.status in ("solved", NO_CONTACT)

    @property
    def energy_created(self) -> float:
        """Energy the step added (J): ``energy_after − energy_before − external_work − stabilization_work
        − motor_work − joint_drift_work − joint_projection_energy``."""
        created = self.energy_after - self.energy_before - self.external_work - self.stabilization_work
        return created - self.motor_work - self.joint_drift_work - self.joint_projection_energy

    @property
    def total_normal_impulse(self) -> float:
        """Σ fn (N·s)."""
        return float(self.fn.sum())

    @property
    def total_impulse(self) -> NDArray[np.float64]:
        """Σ over contacts of ``n·fn + Σ_j d_j fd_j``: the contact impulse on the A bodies (N·s)."""
        if self.contacts == 0:
            return np.zeros(3)
        return np.asarray((self.normals * self.fn[:, None]).sum(axis=0) + self.friction.sum(axis=0))

    def patterns(self, zero: float = 1e-12) -> NDArray[np.bool_]:
        """Per contact (nc, 3): whether fn, Σfd, λ exceed ``zero`` (``ContactLayout.patterns``)."""
        if self.contacts == 0:
            return np.zeros((0, 3), dtype=bool)
        codes = _core.ContactLayout(self.contacts, self.friction_dirs).patterns(self.z, zero)
        return np.asarray((codes[:, None] & np.array([4, 2, 1])) != 0)

    def between(self, a: int, b: int) -> NDArray[np.bool_]:
        """Mask of the contacts between bodies ``a`` and ``b`` (either order)."""
        return np.asarray(((self.body_a == a) & (self.body_b == b)) | ((self.body_a == b) & (self.body_b == a)))

    @classmethod
    def _from_core(cls, core: Any) -> "StepRecord":
        # The compiled record (``_core.StepRecord``) is kept as it is; each
        # field is converted on its first access (``__getattr__``): a step from
        # Python would otherwise cost the conversion of ~25 arrays, many times
        # the step itself, whether they are read or not.
        # (Written into the instance's own dict, not set as a new one: one
        # dict and no frozen-dataclass ``__setattr__`` call.)
        rec = _new_object(cls)
        rec.__dict__["_core"] = core
        return rec

    def __getattr__(self, name: str) -> Any:
        # Only reached for a field not yet read (or a name that is no field).
        core = self.__dict__.get("_core")
        if core is None or name not in _STEP_FIELDS:
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        value = self.__dict__[name] = core.field(name)
        return value

    def __dir__(self) -> list[str]:
        # The fields not yet read are listed too (completion, help()).
        return sorted(set(super().__dir__()) | _STEP_FIELDS)

    def __getstate__(self) -> dict[str, Any]:
        # Every field converted (pickle, copy): the compiled record is not picklable.
        return {name: getattr(self, name) for name in _STEP_FIELDS}


#: The fields of ``StepRecord``, read from its compiled record on first access.
_STEP_FIELDS = frozenset(f.name for f in fields(StepRecord))


class World(JointsMixin, ShapesMixin):
    """A rigid-body world stepped with the Stewart–Trinkle contact LCP.

    Parameters
    ----------
    dt:
        Time step h (s), > 0.
    gravity:
        (m/s²).
    friction_dirs:
        Friction directions per contact k (even, 2 ≤ k ≤ 1024); LCP size is
        (k + 2) per contact.
    cone_scale:
        The friction-cone scale s: None (unscaled, s = 1), ``"dt"`` (s = h,
        the source note's choice) or a number > 0.
    method:
        LCP solver: ``"lemke"`` (default), ``"pgs"`` or ``"newton_fb"``;
        ``**solver_options`` as for :func:`lcpsim.solve_lcp` (e.g.
        ``pivoting="classic"``, ``zero_tol=1e-6``).
    margin:
        Contacts with gap φ ≤ margin enter the LCP (m).
    velocity_margin:
        Widen each pair's margin by how far it can close in one step.
    stabilization:
        :class:`Stabilization` (default ERP 0.2, no slop, speculative gaps,
        gaps within ±1e-12 m taken as touching), a mapping of its fields, or
        ``"none"``; its fields (``erp``, ``slop``, ``speculative``,
        ``gap_floor``) may also be given as keywords.
    restitution, restitution_threshold:
        Newton restitution coefficient e in [0, 1] (default 0) and the
        approach speed below which there is no bounce (m/s).
    mu_combine:
        How two bodies' μ combine: one of :data:`MU_COMBINE` (default "min").
    mu_override:
        If set, every contact uses this μ.
    threads:
        Threads for the islands' LCPs (0: one per core); results do not depend on it.
    max_halvings:
        A step whose contact LCP fails is taken again from its start as two
        steps of h/2, each of which may be halved again, at most this many
        halvings deep (0 to 10; default 0: a failure is recorded as it
        happened). Every part solves its own exact LCP; the step record's
        ``parts`` and ``retakes`` and the trajectory's ``parts`` say where it
        happened.
    """

    def __init__(
        self,
        dt: float = _WORLD["dt"],
        gravity: Vec = tuple(_WORLD["gravity"]),
        friction_dirs: int = _WORLD["friction_dirs"],
        cone_scale: float | str | None = None,
        method: str = _WORLD["method"],
        *,
        margin: float = _WORLD["margin"],
        velocity_margin: bool = _WORLD["velocity_margin"],
        stabilization: Stabilization | Mapping[str, Any] | str | None = None,
        restitution: float = _WORLD["restitution"],
        restitution_threshold: float = _WORLD["restitution_threshold"],
        mu_combine: str = _WORLD["mu_combine"],
        mu_override: float | None = _WORLD["mu_override"],
        threads: int = _WORLD["threads"],
        max_halvings: int = _WORLD["max_halvings"],
        **solver_options: Any,
    ) -> None:
        # The compiled World validates every parameter (messages name the field and
        # the value); here only what is Python's own: the Stabilization forms and
        # the cone scale's spellings (the one parser of lcpsim.scale).
        stab = as_stabilization(stabilization)
        direct: dict[str, Any] = {
            k: solver_options.pop(k) for k in STABILIZATION_FIELDS if k in solver_options
        }
        if direct:
            stab = Stabilization(**{**stab.__dict__, **direct})
        params = {
            "dt": dt,
            "gravity": gravity,
            "friction_dirs": friction_dirs,
            "cone_scale": parse_cone_scale(cone_scale, "cone_scale"),
            "method": method,
            "margin": margin,
            "velocity_margin": bool(velocity_margin),
            **{k: getattr(stab, k) for k in STABILIZATION_FIELDS},
            "speculative": bool(stab.speculative),
            "restitution": restitution,
            "restitution_threshold": restitution_threshold,
            "mu_combine": mu_combine,
            "mu_override": mu_override,
            "threads": threads,
            "max_halvings": max_halvings,
        }
        self._core = _core.World(params, **solver_options)
        self._method = method
        self._solver_options = {k: v for k, v in solver_options.items() if v is not None}
        self._body_names: dict[str, int] = {}
        #: Name and parameters of the scene that built this world (see :mod:`lcpsim.scenes`).
        self.scene: str | None = None
        self.scene_params: dict[str, Any] = {}

    @classmethod
    def _wrap(cls, core: Any, method: str, solver_options: Mapping[str, Any]) -> "World":
        w = cls.__new__(cls)
        w._core = core
        w._method = method
        w._solver_options = dict(solver_options)
        w.scene = None
        w.scene_params = {}
        w._body_names = {}
        return w

    @classmethod
    def from_mjcf(cls, source: "str | os.PathLike[str]", **kwargs: Any) -> "World":
        """A world from MJCF (a path, or XML starting with ``<``) compiled by MuJoCo; what
        is supported and refused (:class:`lcpsim.mjcf.MjcfError`): :mod:`lcpsim.mjcf`."""
        from .mjcf import load_mjcf

        return load_mjcf(source, cls, **kwargs).world

    def body_id(self, name: str) -> int:
        """The index of the body (or geom) called ``name`` in the model it was loaded from."""
        try:
            return self._body_names[name]
        except KeyError:
            known = ", ".join(sorted(self._body_names)) or "none"
            raise KeyError(f"no body named {name!r} (names: {known})") from None

    # ----- parameters -----

    @property
    def dt(self) -> float:
        return float(self._core.params()["dt"])

    @property
    def params(self) -> dict[str, Any]:
        """Every parameter in force (``cone_scale``: "none", "dt" or the number; ``scale``: the numeric s)."""
        p = dict(self._core.params())
        p["solver_options"] = dict(self._solver_options)
        return p

    @property
    def method(self) -> str:
        return self._method

    @property
    def solver_options(self) -> dict[str, Any]:
        return dict(self._solver_options)

    def set_method(self, method: str = "lemke", **options: Any) -> None:
        """Replaces the LCP solver (options as for :func:`lcpsim.solve_lcp`)."""
        self._core.set_method(method, **options)
        self._method = method
        self._solver_options = {k: v for k, v in options.items() if v is not None}

    def set_cone_scale(self, cone_scale: float | str | None) -> None:
        """Replaces the friction-cone scale (None, "dt" or a number > 0)."""
        self._core.set_cone_scale(parse_cone_scale(cone_scale, "cone_scale"))

    def config(self) -> dict[str, Any]:
        """A JSON-ready description: parameters, solver, scene, bodies and joints (for result files)."""
        from . import __version__

        bodies = []
        for i in range(self.body_count):
            b = self.body(i)
            d: dict[str, Any] = {"kind": b.kind, "static": b.is_static, "mu": b.mu}
            if not b.is_static:
                d["mass"] = b.mass
            for key in ("half_extents", "radius", "normal", "offset", "half_length", "vertices", "faces", "com_offset",
                        "heights"):
                v = getattr(b, key)
                if v is not None:
                    d[key] = v.tolist() if isinstance(v, np.ndarray) else v
            if b.parts is not None:
                d["parts"] = jsonable(b.parts)
            bodies.append(d)
        config = {
            "lcpsim_version": __version__,
            "scene": self.scene,
            "scene_params": jsonable(self.scene_params),
            "params": jsonable(self.params),
            "method": self._method,
            "solver_options": jsonable(self._solver_options),
            "bodies": bodies,
        }
        if self.joint_count:  # kind, bodies, anchor and axis in each side's frame, limits, motor
            config["joints"] = [jsonable(self._core.joint_config(j)) for j in range(self.joint_count)]
        return config

    # ----- bodies -----

    def add_box(
        self,
        half_extents: Vec | None = None,
        mass: float = _BODY["mass"],
        position: Vec = tuple(_BODY["position"]),
        orientation: Vec = tuple(_BODY["orientation"]),
        velocity: Vec = tuple(_BODY["velocity"]),
        angular_velocity: Vec = tuple(_BODY["angular_velocity"]),
        mu: float = _BODY["mu"],
        *,
        size: float | Vec | None = None,
        static: bool = _BODY["static"],
        inertia: ArrayLike | None = None,
        contype: int = _BODY["contype"],
        conaffinity: int = _BODY["conaffinity"],
    ) -> int:
        """Adds a box and returns its index.

        Give either ``half_extents`` (3 values, m) or ``size`` (a cube's edge,
        or the 3 full extents). ``velocity`` may hold 6 values ``[v; ω]``.
        ``inertia`` (3×3, body frame) defaults to the solid box's.
        A ``static`` box never moves."""
        if (half_extents is None) == (size is None):
            raise ValueError("give exactly one of half_extents and size")
        if size is not None:
            sz = (_real(size, "size"),) * 3 if np.ndim(size) == 0 else _vec(size, "size")
            for v in sz:
                if not (math.isfinite(v) and v > 0):
                    raise ValueError(f"size must be > 0 and finite, got {size!r}")
            he: Any = tuple(0.5 * v for v in sz)
        else:
            he = half_extents
        v, wv = _velocities(velocity, angular_velocity)
        return self._filtered(contype, conaffinity, lambda: self._core.add_body(
            "box", he, mass, position, orientation, v, wv, mu, bool(static), inertia))

    def add_sphere(
        self,
        radius: float,
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
        """Adds a solid sphere and returns its index (``velocity`` may hold ``[v; ω]``)."""
        v, wv = _velocities(velocity, angular_velocity)
        return self._filtered(contype, conaffinity, lambda: self._core.add_body(
            "sphere", radius, mass, position, orientation, v, wv, mu, bool(static), inertia))

    def add_plane(
        self, normal: Vec = (0.0, 0.0, 1.0), offset: float = 0.0, mu: float = _BODY["mu"], *, tangent: Vec | None = None,
        contype: int = _BODY["contype"], conaffinity: int = _BODY["conaffinity"],
    ) -> int:
        """Adds a static plane ``normal·x = offset`` (solid below it) and returns
        its index. ``tangent`` sets its contacts' first friction direction
        (default: downhill on a tilted plane, else x projected into the plane)."""
        return self._filtered(contype, conaffinity, lambda: self._core.add_plane(normal, offset, mu, tangent))

    def add_ground(self, mu: float = _BODY["mu"], height: float = 0.0) -> int:
        """Adds the level ground ``z = height``."""
        return self.add_plane((0.0, 0.0, 1.0), height, mu)

    def add_slope(
        self,
        angle_deg: float,
        mu: float = _BODY["mu"],
        *,
        downhill: str = "+x",
        offset: float = 0.0,
        tangent_angle: float = 0.0,
    ) -> int:
        """Adds a static slope through the origin at ``angle_deg`` in [0, 90),
        descending towards ``downhill`` ("+x" or "-x"), shifted along its normal
        by ``offset``. The first friction direction is the downhill direction,
        turned by ``tangent_angle`` (rad) about the normal (π/k puts the slope
        on a bisector of two friction directions)."""
        return int(self._core.add_slope(angle_deg, mu, downhill, offset, tangent_angle))

    @property
    def body_count(self) -> int:
        return int(self._core.body_count)

    def __len__(self) -> int:
        return self.body_count

    def body(self, index: int) -> BodyState:
        """A body's shape, mass properties and state."""
        d = self._core.body(index)
        return BodyState(
            index=int(d["index"]),
            kind=d["kind"],
            is_static=bool(d["is_static"]),
            mass=float(d["mass"]),
            mu=float(d["mu"]),
            position=d["position"],
            orientation=d["orientation"],
            velocity=np.concatenate([d["velocity"], d["angular_velocity"]]),
            inertia=d["inertia"],
            half_extents=d.get("half_extents"),
            radius=d.get("radius"),
            normal=d.get("normal"),
            offset=d.get("offset"),
            tangent=d.get("tangent"),
            downhill=d.get("downhill"),
            half_length=d.get("half_length"),
            vertices=d.get("vertices"),
            faces=d.get("faces"),
            com_offset=d.get("com_offset"),
            parts=d.get("parts"),
            heights=d.get("heights"),
        )

    @property
    def positions(self) -> NDArray[np.float64]:
        """(B, 3) centres of mass."""
        return np.asarray(self._core.state()["position"])

    @property
    def orientations(self) -> NDArray[np.float64]:
        """(B, 4) unit quaternions (w, x, y, z)."""
        return np.asarray(self._core.state()["orientation"])

    @property
    def velocities(self) -> NDArray[np.float64]:
        """(B, 6) velocities ``[v; ω]`` (world frame)."""
        s = self._core.state()
        return np.concatenate([s["velocity"], s["angular_velocity"]], axis=1)

    def set_position(self, body: int, position: Vec) -> None:
        self._core.set_position(body, position)

    def set_orientation(self, body: int, orientation: Vec) -> None:
        """Sets the orientation (normalized; a zero quaternion is an error)."""
        self._core.set_orientation(body, orientation)

    def set_velocity(self, body: int, velocity: Vec) -> None:
        """Sets the linear velocity (3 values) or ``[v; ω]`` (6 values) of a dynamic body."""
        if np.ndim(velocity) == 1 and np.size(velocity) == 6:
            v6 = _vec(velocity, "velocity", 6)
            self._core.set_velocity(body, v6[:3])
            self._core.set_angular_velocity(body, v6[3:])
        else:
            self._core.set_velocity(body, velocity)

    def set_angular_velocity(self, body: int, angular_velocity: Vec) -> None:
        self._core.set_angular_velocity(body, angular_velocity)

    def set_mu(self, body: int, mu: float) -> None:
        self._core.set_mu(body, mu)

    def set_torsional_friction(self, body: int, mu_torsion: float) -> None:
        """Torsional friction ``mu_torsion`` (m, >= 0; MuJoCo's ``friction[1]`` with
        condim 4): each contact patch of two or more points this body makes gets
        friction about its normal of at most ``mu_torsion`` (the larger of the
        pair's) times the patch's normal force. 0 (the default) turns it off."""
        self._core.set_torsional_friction(body, mu_torsion)

    # ----- forces -----

    def apply_force(self, body: int, force: Vec, point: Vec | None = None) -> None:
        """A constant force (world frame, N) on ``body`` every step until
        :meth:`clear_forces`. ``point`` is where it acts, relative to the
        centre of mass in the body frame (it moves with the body); None means
        the centre of mass (no torque). Gravity is separate."""
        self._core.apply_force(body, force, point)

    def apply_torque(self, body: int, torque: Vec) -> None:
        """A constant torque (world frame, N·m) every step until cleared."""
        self._core.apply_torque(body, torque)

    def clear_forces(self) -> None:
        """Removes all applied forces and torques."""
        self._core.clear_forces()

    # ----- stepping -----

    @property
    def time(self) -> float:
        """Time at the start of the next step (s)."""
        return float(self._core.time)

    @property
    def steps(self) -> int:
        """Steps taken so far."""
        return int(self._core.steps)

    def energy(self) -> float:
        """Kinetic + gravitational potential energy (J)."""
        return float(self._core.energy())

    def step(self) -> StepRecord:
        """One time step: forces → detect → assemble → solve → integrate."""
        return StepRecord._from_core(self._core.step())

    @property
    def last_record(self) -> StepRecord:
        """The record of the last step."""
        return StepRecord._from_core(self._core.last_record())

    def run(
        self,
        steps: int,
        capture: CaptureTarget = None,
        *,
        fclib: "str | os.PathLike[str] | None" = None,
        chunk_steps: int = 10_000,
        chunk_bytes: int = 64 << 20,
        record_contacts: bool = False,
        overwrite: bool = False,
    ) -> Trajectory:
        """Runs ``steps`` steps (the loop in Rust, GIL released) and returns the :class:`Trajectory`.

        ``capture``: a path or a :class:`lcpsim.io.capture.CaptureWriter`; every
        LCP solved is streamed to it (HDF5, see ``docs/capture.md``), drained
        from Rust every ``chunk_steps`` steps or ``chunk_bytes`` of captured
        data and flushed, so memory stays bounded. A path is refused if it
        exists (unless ``overwrite``), written as ``PATH.partial`` with this
        world's :meth:`config` as metadata and renamed onto ``PATH`` at the end;
        an interrupted run leaves the readable ``PATH.partial``.
        ``fclib``: a directory receiving each LCP as an FCLib local problem
        (:mod:`lcpsim.faceting`).

        ``record_contacts=True`` also records every step's contacts (points, normals,
        impulses: :class:`ContactLog`, ``Trajectory.contact_log``) for the viewer
        and ``Trajectory.save``; the steps are then taken one at a time (same
        results, a few µs more per step) and ``capture`` is not available."""
        if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 0:
            raise ValueError(f"steps must be a non-negative integer, got {steps!r}")
        if isinstance(chunk_steps, bool) or not isinstance(chunk_steps, (int, np.integer)) or chunk_steps < 1:
            raise ValueError(f"chunk_steps must be a positive integer, got {chunk_steps!r}")
        initial: Mapping[str, Any] = self._core.state()
        config = self.config()
        if record_contacts:
            if capture is not None or fclib is not None:
                raise ValueError("run: record_contacts=True steps one at a time and cannot capture; give one of the two")
            parts, records = [self._core.run(0)], []
            for _ in range(int(steps)):
                parts.append(self._core.run(1))
                records.append(StepRecord._from_core(self._core.last_record()))
            return Trajectory._from_parts(self.dt, parts, initial, config, ContactLog.from_records(records))
        if capture is None and fclib is None:
            parts = []
            done = 0
            while True:
                part = self._core.run(min(int(steps) - done, 100_000))
                parts.append(part)
                done += len(part["time"])
                if done >= steps:
                    break
            return Trajectory._from_parts(self.dt, parts, initial, config)
        from .io.sinks import RunSinks

        writer = RunSinks(capture, fclib, config, overwrite=overwrite)
        complete = False
        try:
            writer.begin_run(config)
            self._core.start_capture()
            parts = []
            done = 0
            try:
                while True:
                    part = self._core.run(min(int(steps) - done, chunk_steps), max_capture_bytes=int(chunk_bytes))
                    parts.append(part)
                    done += len(part["time"])
                    writer.append(self._core.drain_capture())
                    writer.flush()
                    if done >= steps:
                        break
            finally:
                self._core.stop_capture()
                writer.append(self._core.drain_capture())
                writer.flush()
            complete = True
        finally:
            writer.close(complete=complete)
        return Trajectory._from_parts(self.dt, parts, initial, config)

    def copy(self) -> "World":
        """An independent copy of the state, parameters and forces (no capture)."""
        w = World._wrap(self._core.copy(), self._method, self._solver_options)
        w.scene = self.scene
        w.scene_params = dict(self.scene_params)
        w._body_names = dict(self._body_names)
        w._actuators = list(getattr(self, "_actuators", []))  # type: ignore[attr-defined]
        return w

    def __repr__(self) -> str:
        scene = f", scene={self.scene!r}" if self.scene else ""
        return f"World(bodies={self.body_count}, steps={self.steps}, time={self.time:g}{scene})"
