"""lcpsim.World: construction, bodies, forces, step records, trajectories,
validation errors (ValueError naming the field and value), GIL release."""

from __future__ import annotations

import math
import threading
import time

import numpy as np
import pytest

import lcpsim
from lcpsim import NO_CONTACT, Stabilization, StepRecord, Trajectory, World

from conftest import raises_naming

G = 9.81
H = 1e-3


def resting_cube(**kw) -> tuple[World, int]:
    w = World(**kw)
    w.add_ground(mu=0.5)
    cube = w.add_box(size=1.0, mass=1.0, position=(0, 0, 0.5))
    return w, cube


# ----------------------------------------------------------------- construction


def test_defaults_and_params():
    w = World()
    p = w.params
    assert p["dt"] == 1e-3 and p["gravity"] == [0.0, 0.0, -9.81] and p["friction_dirs"] == 8
    assert p["cone_scale"] == "none" and p["scale"] == 1.0
    assert p["method"] == "lemke" and p["solver_options"] == {}
    assert w.body_count == 0 and w.steps == 0 and w.time == 0.0
    assert World(cone_scale="dt", dt=2e-3).params["scale"] == 2e-3
    assert World(cone_scale=1e-4).params["cone_scale"] == 1e-4
    w = World(method="lemke", pivoting="classic", zero_tol=1e-6)
    assert w.solver_options == {"pivoting": "classic", "zero_tol": 1e-6}
    assert "Classic" in w.params["method_config"]


@pytest.mark.parametrize(
    "kwargs, words",
    [
        (dict(dt=0.0), ["dt", "0"]),
        (dict(dt=-1e-3), ["dt", "-0.001"]),
        (dict(dt=float("nan")), ["dt", "nan"]),
        (dict(dt="fast"), ["dt", "fast"]),
        (dict(friction_dirs=3), ["friction_dirs", "3"]),
        (dict(friction_dirs=0), ["friction_dirs", "0"]),
        (dict(friction_dirs=2.0), ["friction_dirs", "2.0"]),
        (dict(cone_scale=0.0), ["cone_scale", "0.0"]),
        (dict(cone_scale=-1e-3), ["cone_scale", "-0.001"]),
        (dict(cone_scale="huge"), ["cone_scale", "huge"]),
        (dict(cone_scale=float("inf")), ["cone_scale", "inf"]),
        (dict(method="simplex"), ["method", "simplex"]),
        (dict(pivoting="bland"), ["pivoting", "bland"]),
        (dict(warp=9), ["warp"]),
        (dict(zero_tol=-1.0), ["zero_tol", "-1"]),
        (dict(method="pgs", pivoting="classic"), ["pivoting"]),
        (dict(gravity=(0, -9.81)), ["gravity"]),
        (dict(gravity=(0, 0, float("nan"))), ["gravity"]),
        (dict(margin=-1e-3), ["margin", "-0.001"]),
        (dict(restitution=1.5), ["restitution", "1.5"]),
        (dict(stabilization={"erp": 2.0}), ["erp", "2"]),
        (dict(stabilization={"gain": 1.0}), ["gain"]),
        (dict(mu_combine="median"), ["mu_combine", "median"]),
        (dict(mu_override=-0.5), ["mu_override", "-0.5"]),
    ],
)
def test_bad_world_parameters(kwargs, words):
    raises_naming(ValueError, lambda: World(**kwargs), words, any_case=True)


@pytest.mark.parametrize(
    "call, words",
    [
        (lambda w: w.add_box(size=1.0, mass=-1.0), ["mass", "-1"]),
        (lambda w: w.add_box(size=1.0, mass=0.0), ["mass", "0"]),
        (lambda w: w.add_box(size=1.0, mass=float("nan")), ["mass", "nan"]),
        (lambda w: w.add_box(size=1.0, mu=-0.1), ["mu", "-0.1"]),
        (lambda w: w.add_box((0.0, 0.5, 0.5)), ["half_extents.x", "0"]),
        (lambda w: w.add_box((0.5, -0.5, 0.5)), ["half_extents.y", "-0.5"]),
        (lambda w: w.add_box(size=0.0), ["size", "0"]),
        (lambda w: w.add_box(), ["half_extents", "size"]),
        (lambda w: w.add_box((0.5, 0.5, 0.5), size=1.0), ["half_extents", "size"]),
        (lambda w: w.add_box(size=1.0, orientation=(0, 0, 0, 0)), ["orientation", "zero"]),
        (lambda w: w.add_box(size=1.0, orientation=(1, 0, 0)), ["orientation"]),
        (lambda w: w.add_box(size=1.0, orientation=(1, 0, float("nan"), 0)), ["orientation", "nan"]),
        (lambda w: w.add_box(size=1.0, position=(0, 0)), ["position"]),
        (lambda w: w.add_box(size=1.0, position=(0, 0, float("inf"))), ["position", "inf"]),
        (lambda w: w.add_box(size=1.0, velocity=(0, float("nan"), 0)), ["velocity", "nan"]),
        (lambda w: w.add_box(size=1.0, inertia=np.eye(2)), ["inertia"]),
        (lambda w: w.add_box(size=1.0, inertia=-np.eye(3)), ["inertia", "positive definite"]),
        (lambda w: w.add_sphere(0.0), ["radius", "0"]),
        (lambda w: w.add_sphere(-1.0), ["radius", "-1"]),
        (lambda w: w.add_sphere(0.5, mass=-2.0), ["mass", "-2"]),
        (lambda w: w.add_plane((0, 0, 0)), ["normal", "zero"]),
        (lambda w: w.add_plane((0, 0, 1), mu=-1.0), ["mu", "-1"]),
        (lambda w: w.add_slope(90.0), ["angle_deg", "90"]),
        (lambda w: w.add_slope(-5.0), ["angle_deg", "-5"]),
        (lambda w: w.add_slope(30.0, downhill="up"), ["downhill", "up"]),
    ],
)
def test_bad_bodies(call, words):
    w = World()
    raises_naming(ValueError, lambda: call(w), words, any_case=True)
    assert w.body_count == 0  # nothing was added


def test_bad_forces_and_indices():
    w, cube = resting_cube()
    with pytest.raises(ValueError, match="force"):
        w.apply_force(cube, (1.0, float("nan"), 0.0))
    with pytest.raises(ValueError, match="point"):
        w.apply_force(cube, (1.0, 0.0, 0.0), point=(0, 0))
    with pytest.raises(ValueError, match="static"):
        w.apply_force(0, (1.0, 0.0, 0.0))  # the ground
    with pytest.raises(ValueError, match="body 7 does not exist"):
        w.apply_torque(7, (0, 0, 1))
    with pytest.raises(ValueError, match="body"):
        w.apply_force(-1, (1, 0, 0))
    with pytest.raises(ValueError, match="body 5 does not exist"):
        w.body(5)
    with pytest.raises(ValueError, match="orientation"):
        w.set_orientation(cube, (0, 0, 0, 0))
    with pytest.raises(ValueError, match="mu"):
        w.set_mu(cube, -1.0)
    with pytest.raises(ValueError, match="steps"):
        w.run(-1)
    with pytest.raises(ValueError, match="cone_scale"):
        w.set_cone_scale(0.0)
    with pytest.raises(ValueError, match="method"):
        w.set_method("magic")


def test_bodies_and_state():
    w = World()
    ground = w.add_ground(mu=0.8)
    box = w.add_box((0.5, 0.25, 0.1), mass=2.0, position=(1, 2, 3), orientation=(2, 0, 0, 0), velocity=(1, 0, 0, 0, 0, 1))
    ball = w.add_sphere(0.3, mass=3.0, position=(5, 0, 0.3), mu=0.2)
    slope = w.add_slope(30.0, mu=0.4, offset=-10.0)
    assert (ground, box, ball, slope) == (0, 1, 2, 3) and len(w) == 4
    b = w.body(box)
    assert b.kind == "box" and not b.is_static and b.mass == 2.0
    np.testing.assert_array_equal(b.orientation, [1, 0, 0, 0])  # normalized
    np.testing.assert_array_equal(b.half_extents, [0.5, 0.25, 0.1])
    np.testing.assert_array_equal(b.velocity, [1, 0, 0, 0, 0, 1])
    # Solid box inertia m/3 (b² + c²) etc.
    np.testing.assert_allclose(np.diag(b.inertia), 2.0 / 3.0 * np.array([0.0725, 0.26, 0.3125]))
    s = w.body(ball)
    assert s.kind == "sphere" and s.radius == 0.3
    np.testing.assert_allclose(np.diag(s.inertia), 0.4 * 3.0 * 0.09)
    g = w.body(slope)
    assert g.kind == "plane" and g.is_static and math.isinf(g.mass)
    th = math.radians(30)
    np.testing.assert_allclose(g.normal, [math.sin(th), 0, math.cos(th)])
    np.testing.assert_allclose(g.downhill, [math.cos(th), 0, -math.sin(th)])
    assert g.offset == -10.0 and w.body(ground).downhill is None
    assert w.positions.shape == (4, 3) and w.orientations.shape == (4, 4) and w.velocities.shape == (4, 6)
    w.set_position(box, (0, 0, 9))
    w.set_velocity(box, (0, 1, 0))
    w.set_angular_velocity(box, (0, 0, 0))
    np.testing.assert_array_equal(w.positions[box], [0, 0, 9])
    np.testing.assert_array_equal(w.velocities[box], [0, 1, 0, 0, 0, 0])
    w.set_velocity(box, (1, 2, 3, 4, 5, 6))
    np.testing.assert_array_equal(w.velocities[box], [1, 2, 3, 4, 5, 6])
    cfg = w.config()
    assert cfg["bodies"][1]["kind"] == "box" and cfg["params"]["dt"] == 1e-3
    assert cfg["lcpsim_version"] == lcpsim.__version__


# ----------------------------------------------------------------- stepping


def test_step_record_of_a_resting_cube():
    w, cube = resting_cube()
    r = w.step()
    assert isinstance(r, StepRecord)
    assert r.step == 0 and r.time == 0.0 and r.dt == H
    assert r.contacts == 4 and r.friction_dirs == 8 and r.lcp_size == 40 and r.scale == 1.0
    assert r.status == "solved" and r.ok and r.pivots > 0 and not r.zeroed
    assert r.residual < 1e-12
    assert r.fn.shape == (4,) and r.fd.shape == (4, 8) and r.lam.shape == (4,)
    np.testing.assert_array_equal(r.z, np.concatenate([r.fn, r.fd.ravel(), r.lam]))
    assert r.w.shape == (40,)
    assert r.total_normal_impulse == pytest.approx(G * H, rel=1e-12)
    np.testing.assert_allclose(r.total_impulse, [0, 0, G * H], atol=1e-15)
    np.testing.assert_allclose(r.points[:, 2], 0.0, atol=1e-12)
    np.testing.assert_allclose(np.abs(r.points[:, :2]), 0.5)
    np.testing.assert_array_equal(r.normals, np.tile([0.0, 0.0, 1.0], (4, 1)))
    assert r.directions.shape == (4, 8, 3) and r.friction.shape == (4, 3)
    np.testing.assert_allclose(r.directions[0, 0], [1, 0, 0])
    np.testing.assert_allclose(r.directions[0, 2], [0, 1, 0], atol=1e-15)
    assert set(r.body_a.tolist()) == {cube} and set(r.body_b.tolist()) == {0}
    np.testing.assert_array_equal(r.mu, 0.5)
    assert r.patterns().shape == (4, 3) and r.between(0, cube).all()
    assert w.last_record.step == 0 and w.steps == 1 and w.time == pytest.approx(H)


def test_entered_counts_what_had_to_enter_the_basis():
    """Two stacked boxes sliding at different speeds until friction stops
    them. The first contact step starts cold (every w basic): every positive
    z had to enter, at least the loaded normals, and Lemke took at least one
    pivot each. Later steps start from the previous basis: what entered is
    the positive z it had nonbasic, and the stops bring some in."""
    w = World()
    w.add_ground(mu=0.5)
    for i in range(2):
        w.add_box(size=1.0, mass=1.0, position=(0, 0, 0.5 + i), velocity=(0.2 + 0.3 * i, 0, 0))

    def positive(r: StepRecord) -> np.ndarray:
        return np.concatenate([r.fn, r.fd.ravel(), r.lam]) > 0

    first = w.step()
    assert first.islands == 1 and first.basis is not None
    e = int(first.island_entered[0])
    assert e == int(positive(first).sum()) and e >= int((first.fn > 0).sum()) >= 2
    assert first.pivots >= e
    prev, moved = first, 0
    for _ in range(120):
        r = w.step()
        assert r.islands == 1 and r.basis is not None and r.contacts == prev.contacts
        assert not (positive(r) & ~r.basis).any()
        assert int(r.island_entered[0]) == int((positive(r) & ~prev.basis).sum())
        moved += int(r.island_entered[0] > 0)
        prev = r
    assert moved >= 2 and int(prev.island_entered[0]) == 0 and np.abs(w.velocities).max() < 1e-9


def test_step_record_holds_exactly_its_fields_with_their_types():
    """Every dataclass field of a step record reads from the compiled record
    (converted on first access), each of the declared type; a record survives
    pickling with every field."""
    import dataclasses
    import pickle

    w, _ = resting_cube()
    records = [w.step()]
    free = World()
    free.add_sphere(0.1, position=(0, 0, 10))
    records.append(free.step())
    names = [f.name for f in dataclasses.fields(StepRecord)]
    scalars = {"step": int, "time": float, "dt": float, "contacts": int, "friction_dirs": int, "lcp_size": int,
               "scale": float, "status": str, "pivots": int, "residual": float, "solver_residual": float,
               "min_z": float, "min_w": float, "max_complementarity": float, "zeroed": bool, "islands": int,
               "energy_before": float, "energy_after": float, "external_work": float, "stabilization_work": float,
               "motor_work": float, "joint_drift_work": float, "joint_projection_energy": float, "parts": int}
    dtypes = {"body_a": np.int64, "body_b": np.int64, "island_of_contact": np.int64, "island_lcp_size": np.int64,
              "island_pivots": np.int64, "island_entered": np.int64}
    for r in records:
        assert not set(vars(r)) & set(names), "nothing converted before it is read"
        assert set(names) <= set(dir(r)), "dir() lists the fields not yet read"
        for name in names:
            v = getattr(r, name)
            if name in scalars:
                assert type(v) is scalars[name], (name, type(v))
            elif name == "basis":
                assert v is None or (isinstance(v, np.ndarray) and v.dtype == np.bool_ and v.shape == (r.lcp_size,))
            elif name == "retakes":
                assert v == ()
            elif name in ("island_status", "island_stage"):
                assert type(v) is tuple and len(v) == r.islands and all(type(x) is str for x in v)
            elif name == "island_bodies":
                assert type(v) is tuple and len(v) == r.islands
                assert all(isinstance(b, np.ndarray) and b.dtype == np.int64 for b in v)
            else:
                assert isinstance(v, np.ndarray) and v.dtype == dtypes.get(name, np.float64), name
                assert v.flags.c_contiguous and v.flags.owndata, name
        assert repr(r).startswith(f"StepRecord(step={r.step}, ") and dataclasses.asdict(r).keys() == set(names)
        again = pickle.loads(pickle.dumps(r))
        assert set(vars(again)) == set(names) and again.step == r.step and np.array_equal(again.z, r.z)
        with pytest.raises(AttributeError, match="no_such_field"):
            r.no_such_field  # type: ignore[attr-defined]  # noqa: B018
        with pytest.raises(dataclasses.FrozenInstanceError):
            r.step = 3  # type: ignore[misc]
    assert records[0].status == "solved" and records[1].status == NO_CONTACT


def test_free_fall_has_no_contact():
    w = World()
    ball = w.add_sphere(0.1, position=(0, 0, 10))
    r = w.step()
    assert r.status == NO_CONTACT and r.ok and r.contacts == 0 and r.lcp_size == 0
    assert r.fn.shape == (0,) and r.fd.shape == (0, 8) and r.points.shape == (0, 3)
    traj = w.run(99)
    n = np.arange(1, 101)
    # Semi-implicit Euler: z_n = z_0 − g h² n(n+1)/2.
    np.testing.assert_allclose(traj.positions[:, ball, 2], 10 - G * H * H * n[1:] * (n[1:] + 1) / 2, rtol=1e-12)
    assert (traj.status == NO_CONTACT).all() and traj.failures == 0
    assert traj.lcp_stats().lcps == 0


def test_trajectory_arrays():
    w, cube = resting_cube()
    traj = w.run(250)
    assert isinstance(traj, Trajectory) and len(traj) == 250 and traj.bodies == 2
    assert traj.positions.shape == (250, 2, 3) and traj.orientations.shape == (250, 2, 4)
    assert traj.velocities.shape == (250, 2, 6)
    assert traj.linear_velocities.shape == (250, 2, 3) and traj.angular_velocities.shape == (250, 2, 3)
    np.testing.assert_allclose(traj.time, H * np.arange(1, 251), rtol=1e-12)
    for a in (traj.status, traj.pivots, traj.residual, traj.lcp_size, traj.contacts, traj.normal_impulse, traj.max_lambda):
        assert a.shape == (250,)
    assert traj.friction_impulse.shape == (250, 3)
    assert traj.status.dtype.kind == "U" and (traj.status == "solved").all()
    assert (traj.lcp_size == 40).all() and (traj.contacts == 4).all()
    stats = traj.lcp_stats()
    assert stats.lcps == 250 and stats.failures == 0 and stats.by_status == {"solved": 250}
    # Warm-started from the previous step, most steps need no pivot at all.
    assert stats.max_lcp_size == 40 and stats.pivots_max >= stats.pivots_median >= 0 and stats.pivots_max > 0
    np.testing.assert_array_equal(traj.initial_positions[cube], [0, 0, 0.5])
    # A second run continues in time.
    t2 = w.run(10)
    assert t2.time[0] == pytest.approx(251 * H) and w.steps == 260
    empty = w.run(0)
    assert len(empty) == 0 and empty.positions.shape == (0, 2, 3) and empty.lcp_stats().lcps == 0


def test_run_equals_repeated_step():
    a, _ = resting_cube(cone_scale="dt")
    b = a.copy()
    a.set_velocity(1, (0.3, 0.1, 0.0))
    b.set_velocity(1, (0.3, 0.1, 0.0))
    traj = a.run(50)
    recs = [b.step() for _ in range(50)]
    np.testing.assert_array_equal(traj.positions[-1], b.positions)
    np.testing.assert_array_equal(traj.pivots, [r.pivots for r in recs])
    np.testing.assert_array_equal(traj.normal_impulse, [r.fn.sum() for r in recs])


def test_copy_is_independent():
    w, cube = resting_cube()
    w.scene = "mine"
    c = w.copy()
    c.apply_force(cube, (100.0, 0, 0))
    c.run(100)
    w.run(100)
    assert c.positions[cube, 0] > 0.1 and abs(w.positions[cube, 0]) < 1e-9 and c.scene == "mine"


def test_force_at_a_point_and_torque_turn_the_body():
    w = World(gravity=(0, 0, 0))
    b = w.add_box(size=1.0, mass=1.0)
    w.apply_torque(b, (0, 0, 1.0))
    w.run(1000)
    # I_zz = m (a² + b²)/12 = 1/6 for a unit cube: ω = τ t / I.
    assert w.velocities[b, 5] == pytest.approx(6.0, rel=1e-9)
    w = World(gravity=(0, 0, 0))
    b = w.add_box(size=1.0, mass=1.0)
    w.apply_force(b, (1.0, 0, 0), point=(0, 0.5, 0))  # torque r × F = (0, 0, −0.5)
    w.step()
    assert w.velocities[b, 0] == pytest.approx(1e-3) and w.velocities[b, 5] == pytest.approx(-3e-3)
    w.clear_forces()
    v = w.velocities[b].copy()
    w.step()
    np.testing.assert_allclose(w.velocities[b], v, atol=1e-15)


def test_energy_does_not_grow_while_sliding():
    w = World()
    w.add_ground(mu=0.3)
    b = w.add_box(size=1.0, position=(0, 0, 0.5), velocity=(2.0, 0.5, 0.0))
    e = [w.energy()]
    for _ in range(20):
        w.run(50)
        e.append(w.energy())
    assert all(e1 <= e0 + 1e-12 for e0, e1 in zip(e, e[1:])), e
    assert np.linalg.norm(w.velocities[b]) < 1e-9  # came to rest


def test_stabilization_and_restitution_options():
    w = World(stabilization="none", restitution=0.5, restitution_threshold=0.05, mu_combine="max", mu_override=0.9)
    p = w.params
    assert (p["erp"], p["slop"], p["speculative"]) == (0.0, 0.0, False)
    assert p["restitution"] == 0.5 and p["restitution_threshold"] == 0.05
    assert p["mu_combine"] == "max" and p["mu_override"] == 0.9
    assert World(stabilization=Stabilization(erp=0.1, slop=1e-4)).params["slop"] == 1e-4


def test_set_method_and_scale():
    w, _ = resting_cube()
    w.set_method("pgs", max_iterations=500)
    assert w.method == "pgs" and w.params["method"] == "pgs"
    r = w.step()
    assert r.status in lcpsim.STATUSES
    w.set_method("lemke", pivoting="classic")
    w.set_cone_scale("dt")
    r = w.step()
    assert r.scale == 1e-3 and r.status == "solved"


def test_run_releases_the_gil():
    w = World()
    w.add_ground()
    w.add_box(size=1.0, position=(0, 0, 0.5))
    t0 = time.perf_counter()
    w.copy().run(3000)
    single = time.perf_counter() - t0
    ticks = 0
    done = threading.Event()

    def work() -> None:
        w.run(int(3000 * max(1.0, 0.3 / max(single, 1e-6))))
        done.set()

    th = threading.Thread(target=work)
    th.start()
    time.sleep(0.01)
    while not done.is_set():
        ticks += 1
        time.sleep(0)
    th.join()
    # With the GIL held for the whole run this loop could not advance.
    assert ticks > 100, ticks
