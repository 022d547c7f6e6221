"""Type stubs for the private compiled module ``lcpsim._core``.

Use the public wrappers in :mod:`lcpsim` instead; these functions return plain
dicts and are documented here for the wrappers' sake.
"""

from typing import Any, TypedDict, final

import numpy as np
from numpy.typing import ArrayLike, NDArray

# Checked against the compiled module by tests/test_stubs.py (mypy.stubtest).
__all__ = [
    "__version__", "METHODS", "PIVOTINGS", "STATUSES", "METHOD_OPTIONS", "LEMKE_DEFAULTS", "solve_lcp",
    "solve_lcp_batch", "lcp_residual", "lcp_residuals", "World", "StepRecord", "build_scene", "SCENES", "MU_COMBINE",
    "SCENE_DEFAULTS", "WORLD_DEFAULTS", "BODY_DEFAULTS",
    "contact_lcp", "spd_lcp", "p_matrix_lcp", "hard_contact_lcp", "hard_corpus", "HARD_KINDS", "certify_lcp",
    "certify_lcp_batch", "solve_lcp_traced", "ContactLayout", "quat_from_axis_angle", "quat_mul", "quat_to_matrix",
    "quat_from_matrix",
]

__version__: str
#: ["lemke", "pgs", "newton_fb"]
METHODS: list[str]
#: ["lexicographic", "classic"]
PIVOTINGS: list[str]
#: ["solved", "ray_termination", "max_pivots", "max_iterations",
#:  "singular_basis", "cycling", "numerical", "regularized"]
STATUSES: list[str]
#: Option names accepted by each method.
METHOD_OPTIONS: dict[str, list[str]]
#: Lemke's default options by name (``LemkeOptions::default()``).
LEMKE_DEFAULTS: dict[str, Any]

#: Keyed by exactly the fields of ``lcpsim.LcpResult`` that a solve determines
#: (the wrapper makes it the result's ``__dict__``; tests/test_api.py checks the keys).
SolutionDict = dict[str, Any]

#: Keyed by the fields of ``lcpsim.LcpBatchResult`` (``status`` a list):
#: ``z``, ``w`` of shape (b, n), ``basis`` (b, n) or None, the rest (b,).
BatchDict = dict[str, Any]

class ResidualsDict(TypedDict):
    w: NDArray[np.float64]
    residual: float
    min_z: float
    min_w: float
    max_complementarity: float

def solve_lcp(m: ArrayLike, q: ArrayLike, method: str = "lemke", **options: Any) -> SolutionDict:
    """Solve one LCP. Raises ValueError on invalid input or options."""

def solve_lcp_batch(
    ms: ArrayLike, qs: ArrayLike, method: str, threads: int, **options: Any
) -> BatchDict:
    """Solve a (b, n, n) / (b, n) batch with the GIL released."""

def lcp_residual(m: ArrayLike, q: ArrayLike, z: ArrayLike) -> float:
    """‖min(z, M z + q)‖∞."""

def lcp_residuals(m: ArrayLike, q: ArrayLike, z: ArrayLike) -> ResidualsDict:
    """w = M z + q and every residual of z."""

# ----------------------------------------------------------------- simulator

#: Scene name → its parameter names (the Rust `sim::scenes` structs' fields).
SCENES: dict[str, list[str]]
#: Scene name → its optional parameters and their Rust defaults (the required
#: ones, such as a slope's angle and μ, have none).
SCENE_DEFAULTS: dict[str, dict[str, Any]]
#: ``sim::WorldParams::default()`` as ``World.params()`` gives it (stabilization's
#: fields ``erp``, ``slop``, ``speculative``, ``gap_floor`` included).
WORLD_DEFAULTS: dict[str, Any]
#: ``sim::BodyDesc``'s defaults: ``mass``, ``position``, ``orientation``,
#: ``velocity``, ``angular_velocity``, ``mu``, ``static``.
BODY_DEFAULTS: dict[str, Any]
#: ["min", "max", "product", "geometric_mean", "average"]
MU_COMBINE: list[str]

@final
class StepRecord:
    """One step's record as the core wrote it; ``lcpsim.world.StepRecord``
    reads each of its fields once, on first access (tests/test_world.py
    checks the names and types)."""

    def field(self, name: str) -> Any:
        """Field ``name`` of ``lcpsim.world.StepRecord``; AttributeError for any other name."""

class RunDict(TypedDict):
    time: NDArray[np.float64]  # (T,)
    position: NDArray[np.float64]  # (T, B, 3)
    orientation: NDArray[np.float64]  # (T, B, 4)
    velocity: NDArray[np.float64]  # (T, B, 3)
    angular_velocity: NDArray[np.float64]  # (T, B, 3)
    contacts: NDArray[np.int64]
    lcp_size: NDArray[np.int64]
    status: NDArray[np.int8]  # -1 no contact, else an index into STATUSES
    pivots: NDArray[np.int64]
    residual: NDArray[np.float64]
    solver_residual: NDArray[np.float64]
    normal_impulse: NDArray[np.float64]
    friction_impulse: NDArray[np.float64]  # (T, 3)
    max_lambda: NDArray[np.float64]
    islands: NDArray[np.int64]  # contact islands per step
    max_island_size: NDArray[np.int64]  # largest island LCP per step
    parts: NDArray[np.int64]  # parts each step was taken in
    stage_counts: NDArray[np.int64]  # (T, 4) islands answered per stage
    joint_force: NDArray[np.float64]  # (T, J, 3)
    joint_torque: NDArray[np.float64]  # (T, J, 3)
    joint_position: NDArray[np.float64]  # (T, J)
    joint_error: NDArray[np.float64]  # (T, J, 2)

class CaptureDict(TypedDict):
    M: NDArray[np.float64]  # row-major M of every LCP, concatenated
    q: NDArray[np.float64]  # concatenated
    z: NDArray[np.float64]
    w: NDArray[np.float64]
    n: NDArray[np.int64]
    step: NDArray[np.int64]
    island: NDArray[np.int64]  # island of the step the LCP belongs to
    time: NDArray[np.float64]
    contacts: NDArray[np.int64]
    friction_dirs: NDArray[np.int64]
    scale: NDArray[np.float64]
    status: NDArray[np.int8]  # index into STATUSES
    pivots: NDArray[np.int64]
    method: list[str]

class StateDict(TypedDict):
    position: NDArray[np.float64]  # (B, 3)
    orientation: NDArray[np.float64]  # (B, 4)
    velocity: NDArray[np.float64]  # (B, 3)
    angular_velocity: NDArray[np.float64]  # (B, 3)
    is_static: list[bool]

@final
class World:
    """`sim::World` (use `lcpsim.World`). Invalid input raises ValueError."""

    def __new__(cls, params: dict[str, Any] | None = None, **options: Any) -> World:
        """``params``: the keys of ``WORLD_DEFAULTS`` but ``scale`` and ``method_config``
        (missing or None: the default); ``options``: the solver's."""
    @property
    def time(self) -> float: ...
    @property
    def steps(self) -> int: ...
    @property
    def body_count(self) -> int: ...
    @property
    def capturing(self) -> bool: ...
    def params(self) -> dict[str, Any]: ...
    def set_method(self, method: str, **options: Any) -> None: ...
    def set_cone_scale(self, scale: float | str | None = None) -> None: ...
    def copy(self) -> World: ...
    def energy(self) -> float: ...
    def add_joint(
        self,
        kind: str,
        body_a: int | None,
        body_b: int,
        anchor: ArrayLike,
        axis: ArrayLike | None = None,
        limits: tuple[float, float] | None = None,
    ) -> int:
        """A joint ("ball", "hinge", "slider", "fixed") between ``body_a`` (None: the world) and ``body_b``."""
    def set_motor(self, joint: int, speed: float, max_force: float) -> None: ...
    def set_joint_damping(self, joint: int, damping: float) -> None: ...
    @property
    def joint_count(self) -> int: ...
    def joint_config(self, joint: int) -> dict[str, Any]: ...
    def joint_error(self, joint: int) -> tuple[float, float]: ...
    def joint_position(self, joint: int) -> float: ...
    def joint_reactions(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
    def joint_params(self) -> dict[str, Any]: ...
    def set_joint_params(
        self,
        drift: float | None = None,
        rank_tol: float | None = None,
        settle_passes: int | None = None,
        settle_tol: float | None = None,
    ) -> None: ...
    def add_body(
        self,
        shape: str,
        size: Any,
        mass: float | None = None,
        position: ArrayLike | None = None,
        orientation: ArrayLike | None = None,
        velocity: ArrayLike | None = None,
        angular_velocity: ArrayLike | None = None,
        mu: float | None = None,
        is_static: bool = False,
        inertia: ArrayLike | None = None,
    ) -> int:
        """shape "box" (size: half extents), "sphere" (size: radius), "capsule" or "cylinder" (size: (radius, half_length)),
        "convex" (size: the (N, 3) float64 points of the hull)."""
    def add_mesh(
        self,
        vertices: NDArray[np.float64],
        faces: NDArray[np.int64],
        mu: float | None = None,
        position: ArrayLike | None = None,
        orientation: ArrayLike | None = None,
    ) -> int: ...
    def add_heightfield(
        self,
        heights: NDArray[np.float64],
        half_x: float,
        half_y: float,
        mu: float | None = None,
        position: ArrayLike | None = None,
        orientation: ArrayLike | None = None,
    ) -> int:
        """A static height field: ``heights`` (nrow, ncol) over [−half_x, half_x] × [−half_y, half_y] of its frame."""
    def com_offset(self, index: int) -> NDArray[np.float64]: ...
    def add_plane(
        self, normal: ArrayLike, offset: float, mu: float | None = None, tangent: ArrayLike | None = None
    ) -> int: ...
    def add_slope(self, angle_deg: float, mu: float | None, downhill: str, offset: float, tangent_angle: float) -> int: ...
    def body(self, index: int) -> dict[str, Any]: ...
    def state(self) -> StateDict: ...
    def set_position(self, body: int, position: ArrayLike) -> None: ...
    def set_orientation(self, body: int, orientation: ArrayLike) -> None: ...
    def set_velocity(self, body: int, velocity: ArrayLike) -> None: ...
    def set_angular_velocity(self, body: int, angular_velocity: ArrayLike) -> None: ...
    def set_mu(self, body: int, mu: float) -> None: ...
    def set_torsional_friction(self, body: int, mu_torsion: float) -> None: ...
    def set_collision_filter(self, body: int, contype: int, conaffinity: int) -> None: ...
    def exclude_pair(self, body_a: int, body_b: int) -> None: ...
    def excluded_pairs(self) -> list[tuple[int, int]]: ...
    def add_contact_pair(self, body_a: int, body_b: int, mu: float) -> None: ...
    def contact_pairs(self) -> list[tuple[int, int, float]]: ...
    def apply_force(self, body: int, force: ArrayLike, point: ArrayLike | None = None) -> None: ...
    def apply_torque(self, body: int, torque: ArrayLike) -> None: ...
    def clear_forces(self) -> None: ...
    def step(self) -> StepRecord: ...
    def last_record(self) -> StepRecord: ...
    def run(self, steps: int, max_capture_bytes: int | None = None) -> RunDict:
        """Runs with the GIL released; stops early once the capture holds max_capture_bytes."""
    def start_capture(self) -> None: ...
    def stop_capture(self) -> None: ...
    def captured_count(self) -> int: ...
    def drain_capture(self) -> CaptureDict: ...

def build_scene(name: str, params: dict[str, Any] | None, template: World) -> tuple[World, dict[str, Any]]:
    """Scene `name` built with the template's parameters; ids in the dict: body, ground, bodies."""

# Rotations of sim::math (crates/py/src/math.rs); quaternions [w, x, y, z].

def quat_from_axis_angle(axis: ArrayLike, angle: float) -> list[float]:
    """Rotation by `angle` (rad) about `axis`."""

def quat_mul(p: ArrayLike, q: ArrayLike) -> list[float]:
    """Hamilton product p ⊗ q."""

def quat_to_matrix(q: ArrayLike) -> NDArray[np.float64]:
    """Rotation matrix (3, 3) of a unit quaternion."""

def quat_from_matrix(r: ArrayLike) -> list[float]:
    """Unit quaternion of a rotation matrix."""

# Where fn, fd, λ live in a contact LCP's z (crates/py/src/contact.rs → lcp::contact).

@final
class ContactLayout:
    """z = [fn (nc); fd (nc·k); λ (nc)], n = nc·(k + 2). Array arguments may have
    leading batch dimensions: z (..., n), M (..., n, n), q (..., n)."""

    #: Sign patterns (fn, Σfd, λ) in the source note's table order; `patterns` codes index it.
    PATTERNS: list[str]
    def __new__(cls, nc: int, k: int) -> ContactLayout: ...
    @property
    def nc(self) -> int: ...
    @property
    def k(self) -> int: ...
    @property
    def n(self) -> int:
        """nc·(k + 2)."""
    @property
    def impulses(self) -> int:
        """nc·(k + 1): the [fn; fd] part."""
    @property
    def fn(self) -> slice: ...
    @property
    def fd(self) -> slice:
        """Contact-major: z[fd].reshape(nc, k)."""
    @property
    def lam(self) -> slice: ...
    @property
    def force(self) -> slice:
        """The [fn; fd] part (rows and columns of A = J M_b⁻¹ Jᵀ)."""
    def fd_of(self, c: int) -> slice: ...
    def fd_index(self, c: int, j: int) -> int: ...
    def lambda_index(self, c: int) -> int: ...
    def cone_diagonal(self, s: float) -> NDArray[np.float64]:
        """Diagonal of D = diag(I, I, s·I)."""
    def scale_lcp(
        self, m: ArrayLike, q: ArrayLike, s: float
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(D M D, D q) of the unscaled problem."""
    def unscale_z(self, z: ArrayLike, s: float) -> NDArray[np.float64]:
        """Physical z of the scaled problem's answer: λ = s·λ_scaled."""
    def zero_levels(
        self, m: ArrayLike, q: ArrayLike, z: ArrayLike, rel: float
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(impulse, velocity) thresholds: rel·max(‖[fn; fd]‖∞, ‖q‖∞/max|A|), rel·‖q‖∞."""
    def patterns(
        self, z: ArrayLike, impulse_zero: ArrayLike | float | None = None, velocity_zero: ArrayLike | float | None = None
    ) -> NDArray[np.int8]:
        """Pattern codes 4·[fn > zero] + 2·[Σfd > zero] + [λ > zero], shape (..., nc)."""

# Seeded test-LCP generators (crates/py/src/generate.rs → lcp::generate).
# Contact generators return (M, q, label, nc, k); the others (M, q, label).

#: Hard-contact families: "many_contacts", "duplicate", "nearly_parallel",
#: "collinear", "mass_ratio", "thin_rod", "mixed".
HARD_KINDS: list[str]

def contact_lcp(
    nc: int, k: int, scale: float, seed: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], str, int, int]:
    """Contact LCP (z = [fn; fd; λ]) of a unit cube on a random slope."""

def spd_lcp(n: int, seed: int) -> tuple[NDArray[np.float64], NDArray[np.float64], str]:
    """Random LCP with M = A Aᵀ/n + 0.1 I."""

def p_matrix_lcp(n: int, seed: int) -> tuple[NDArray[np.float64], NDArray[np.float64], str]:
    """Random LCP with a nonsymmetric positive definite M."""

def hard_contact_lcp(
    kind: str, scale: float, seed: int, k: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], str, int, int]:
    """Hard contact LCP of one family."""

def hard_corpus(
    seed: int, count: int, scale: float
) -> list[tuple[NDArray[np.float64], NDArray[np.float64], str, int, int]]:
    """`count` hard contact LCPs cycling through the families."""

# Exact certification and failure forensics (crates/py/src/certify.rs).

class ViolationDict(TypedDict):
    index: int
    kind: str  # "negative_z" | "negative_w" | "complementarity"
    value: float

class CertificateDict(TypedDict):
    status: str  # "certified" | "violated" | "singular"
    basis: NDArray[np.bool_]
    z: NDArray[np.float64]  # exact basis solution, rounded; empty when singular
    w: NDArray[np.float64]
    violations: int
    violation: ViolationDict | None  # the first one
    det_bits: int
    natural_residual: float  # of the exact solution; inf when singular
    backward_error: float  # Oettli–Prager η; 0 when certified, inf when singular
    z_error: float | None  # max |z_exact − z| when z was given

class TraceDict(TypedDict):
    # One entry per pivot over every rung; variables: w_i → i, z_j → n + j, z0 → 2n.
    rung: NDArray[np.int64]
    entering: NDArray[np.int64]
    leaving: NDArray[np.int64]
    theta: NDArray[np.float64]
    pivot: NDArray[np.float64]
    column_max: NDArray[np.float64]

def certify_lcp(
    m: ArrayLike, q: ArrayLike, basis: NDArray[np.bool_] | None = None, z: ArrayLike | None = None
) -> CertificateDict:
    """Exact check of `basis` (compared with `z` if given), or of the support of `z`."""

def certify_lcp_batch(
    ms: ArrayLike, qs: ArrayLike, bases: NDArray[np.bool_], zs: ArrayLike | None, threads: int
) -> list[CertificateDict]:
    """`certify_lcp` over a (b, n, n) / (b, n) stack with the GIL released."""

def solve_lcp_traced(
    m: ArrayLike, q: ArrayLike, method: str = "lemke", warm: NDArray[np.bool_] | None = None, **options: Any
) -> tuple[SolutionDict, TraceDict]:
    """Lemke with its pivot trace (method must be "lemke")."""
