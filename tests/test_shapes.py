"""Capsules, cylinders, convex hulls and static meshes from Python: the
analytic answers (rolling, sliding, resting), the hull of a cube against the
box, and bad input refused with a ValueError naming the field, nothing added."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lcpsim import World

G = 9.81


def _z_onto(n) -> tuple[float, float, float, float]:
    """The quaternion turning the body's z onto unit ``n``."""
    n = np.asarray(n, dtype=float)
    axis = np.cross([0.0, 0.0, 1.0], n)
    s = np.linalg.norm(axis)
    if s < 1e-15:
        return (1.0, 0.0, 0.0, 0.0)
    ang = math.acos(max(-1.0, min(1.0, n[2])))
    a = axis / s * math.sin(ang / 2)
    return (math.cos(ang / 2), *a)


def _slope(angle: float, mu: float) -> tuple[World, np.ndarray, np.ndarray]:
    w = World()
    w.add_slope(angle, mu)
    th = math.radians(angle)
    normal = np.array([math.sin(th), 0.0, math.cos(th)])
    downhill = np.array([math.cos(th), 0.0, -math.sin(th)])
    return w, normal, downhill


def _accel(w: World, body: int, downhill: np.ndarray, steps: int = 1000) -> float:
    traj = w.run(steps)
    assert traj.lcp_stats().failures == 0
    return float(traj.velocities[-1, body, :3] @ downhill) / (steps * w.dt)


def test_solid_cylinder_rolls_down_an_incline_at_two_thirds_g_sin_theta():
    w, n, down = _slope(20.0, 0.5)
    c = w.add_cylinder(0.4, 0.5, position=tuple(n * 0.4), orientation=_z_onto([0, 1, 0]), mu=0.5)
    a = _accel(w, c, down)
    expect = 2 / 3 * G * math.sin(math.radians(20))
    assert abs(a - expect) / expect < 1e-2


def test_cylinder_on_its_cap_slides_like_a_box():
    w, n, down = _slope(30.0, 0.3)
    c = w.add_cylinder(0.3, 0.1, position=tuple(n * 0.1), orientation=_z_onto(n), mu=0.3)
    th = math.radians(30)
    expect = G * (math.sin(th) - 0.3 * math.cos(th))
    assert abs(_accel(w, c, down) - expect) / expect < 1e-2


def test_capsule_on_its_side_stays_put():
    w = World()
    w.add_ground()
    c = w.add_capsule(0.2, 0.5, position=(0, 0, 0.2), orientation=_z_onto([1, 0, 0]))
    traj = w.run(1000)
    assert np.abs(traj.positions[-1, c] - [0, 0, 0.2]).max() < 1e-6
    assert w.body(c).kind == "capsule" and w.body(c).half_length == 0.5


def test_hull_of_cube_corners_moves_like_the_box():
    corners = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
    q = (math.cos(0.15), math.sin(0.15) * 0.8, math.sin(0.15) * 0.6, 0.0)
    out = []
    for hull in (False, True):
        w = World()
        w.add_ground()
        kw = dict(mass=2.0, position=(0, 0, 1.2), orientation=q, velocity=(1.0, 0, 0))
        b = w.add_convex(corners, **kw) if hull else w.add_box(size=1.0, **kw)
        out.append(w.run(1500).positions[:, b])
    assert np.abs(out[0] - out[1]).max() < 1e-6
    w = World()
    h = w.add_convex(corners + [1.0, 2.0, 3.0], mass=6.0)
    np.testing.assert_allclose(w.body(h).com_offset, [1, 2, 3], atol=1e-12)
    np.testing.assert_allclose(w.body(h).inertia, np.eye(3) * 6.0 / 6.0, atol=1e-12)
    assert w.config()["bodies"][0]["kind"] == "convex"


def test_box_rests_on_a_two_triangle_mesh_as_on_the_plane():
    v = [(-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0)]
    f = [(0, 1, 2), (0, 2, 3)]
    ends = []
    for mesh in (False, True):
        w = World()
        w.add_mesh(v, f) if mesh else w.add_ground()
        b = w.add_box(size=1.0, position=(0.3, -0.2, 0.5))
        ends.append(w.run(500).positions[-1, b])
    np.testing.assert_allclose(ends[0], ends[1], atol=1e-9)


@pytest.mark.parametrize(
    "call, field, value",
    [
        (lambda w: w.add_capsule(-1.0, 0.5), "radius", "-1"),
        (lambda w: w.add_capsule(0.2, 0.0), "half_length", "0"),
        (lambda w: w.add_cylinder(0.2, float("nan")), "half_length", "nan"),
        (lambda w: w.add_cylinder(0.2, 0.3, mass=0.0), "mass", "0"),
        (lambda w: w.add_convex([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), "vertices", "3 points"),
        (lambda w: w.add_convex([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]), "vertices", "not in one plane"),
        (lambda w: w.add_convex([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, np.nan]]), "vertices", "point 3"),
        (lambda w: w.add_convex([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, np.inf]]), "vertices", "inf"),
        (lambda w: w.add_convex(np.zeros((100_001, 3))), "vertices", "limit of 100000"),
        (lambda w: w.add_mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 3]]), "faces", "index 3"),
        (lambda w: w.add_mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, -1]]), "faces", "-1"),
        (lambda w: w.add_mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 1]]), "faces", "degenerate"),
        (lambda w: w.add_mesh([[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 1, 2]]), "faces", "degenerate"),
        (lambda w: w.add_mesh([[0, 0, 0], [1, 0, 0]], [[0, 1]]), "faces", "(M, 3)"),
        (lambda w: w.add_sphere(0.1, contype=-1), "contype", "-1"),
        (lambda w: w.add_box(size=1.0, conaffinity=2**32), "conaffinity", "4294967296"),
        (lambda w: w.add_plane(contype=1.5), "contype", "1.5"),
        (lambda w: w.add_mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], conaffinity="1"), "conaffinity", "'1'"),
    ],
)
def test_bad_shapes_raise_value_error_naming_field_and_value(call, field, value):
    w = World()
    with pytest.raises(ValueError) as e:
        call(w)
    assert field in str(e.value) and value.lower() in str(e.value).lower(), str(e.value)
    assert w.body_count == 0


def test_filtered_pair_passes_through_and_the_rest_still_collide():
    """MuJoCo's rule, (contype1 & conaffinity2) | (contype2 & conaffinity1): a capsule of type 2,
    affinity 2 falls through a static box (1, 1) as in free fall and lands on a mesh floor of
    affinity 3; a sphere of the defaults lands on the box."""
    w = World(dt=1e-3)
    w.add_mesh([(-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0)], [(0, 1, 2), (0, 2, 3)], conaffinity=3)
    w.add_box(half_extents=(1, 1, 0.1), position=(0, 0, 1.0), static=True)
    pill = w.add_capsule(0.1, 0.2, position=(0, 0, 1.5), orientation=_z_onto((1, 0, 0)), contype=2, conaffinity=2)
    ball = w.add_sphere(0.1, position=(0.5, 0.5, 1.5))
    assert w.collision_filter(pill) == (2, 2) and w.collision_filter(ball) == (1, 1)
    traj = w.run(300)
    n = np.arange(1, 301)
    free_fall = 1.5 - G * 1e-6 * n * (n + 1) / 2  # semi-implicit Euler, exactly
    np.testing.assert_allclose(traj.positions[:, pill, 2], free_fall, atol=1e-9)
    traj = w.run(1200)
    assert traj.lcp_stats().failures == 0
    np.testing.assert_allclose(traj.positions[-1, pill], [0, 0, 0.1], atol=1e-4)  # on the floor, on its side
    np.testing.assert_allclose(traj.positions[-1, ball], [0.5, 0.5, 1.2], atol=1e-4)  # on the box
    w.set_collision_filter(ball, 0, 0)  # now it touches nothing
    traj = w.run(200)
    assert traj.positions[-1, ball, 2] < 1.2 - 0.15


def test_an_excluded_pair_passes_through_whatever_its_bits_and_bad_pairs_are_named():
    """``exclude_pair``: a sphere of the default bits falls through a static box as in free
    fall and lands on the floor, which it still touches; bad pairs name the field and value."""
    w = World(dt=1e-3)
    floor = w.add_plane()
    shelf = w.add_box(half_extents=(1, 1, 0.1), position=(0, 0, 1.0), static=True)
    ball = w.add_sphere(0.1, position=(0.5, 0.5, 1.5))
    w.exclude_pair(ball, shelf)
    assert w.excluded_pairs() == [(shelf, ball)] and w.copy().excluded_pairs() == [(shelf, ball)]
    traj = w.run(300)
    n = np.arange(1, 301)
    np.testing.assert_allclose(traj.positions[:, ball, 2], 1.5 - G * 1e-6 * n * (n + 1) / 2, atol=1e-9)
    traj = w.run(1200)
    assert traj.lcp_stats().failures == 0
    np.testing.assert_allclose(traj.positions[-1, ball], [0.5, 0.5, 0.1], atol=1e-4)  # on the floor
    assert w.excluded_pairs() == [(shelf, ball)] and floor not in w.excluded_pairs()[0]
    with pytest.raises(ValueError, match="body_b must be in the bodies other than body_a, got 2"):
        w.exclude_pair(ball, ball)
    with pytest.raises(ValueError, match="body 9 does not exist"):
        w.exclude_pair(ball, 9)


def test_a_contact_pair_lands_a_ball_on_a_shelf_it_is_excluded_from_and_bad_pairs_are_named():
    """``add_contact_pair``: the same ball lands on the shelf again, past the exclusion and
    the shelf's bits of 0; bad pairs name the field and value and change nothing."""
    w = World(dt=1e-3)
    shelf = w.add_box(half_extents=(1, 1, 0.1), position=(0, 0, 1.0), static=True, contype=0, conaffinity=0)
    ball = w.add_sphere(0.1, position=(0.5, 0.5, 1.5))
    w.exclude_pair(ball, shelf)
    w.add_contact_pair(ball, shelf, 0.3)
    assert w.contact_pairs() == [(shelf, ball, 0.3)] and w.copy().contact_pairs() == [(shelf, ball, 0.3)]
    traj = w.run(1500)
    assert traj.lcp_stats().failures == 0
    np.testing.assert_allclose(traj.positions[-1, ball], [0.5, 0.5, 1.2], atol=1e-4)  # on the shelf
    assert set(w.last_record.mu) == {0.3}
    floor = w.add_plane()
    for args, words in [((ball, ball, 0.3), "body_b must be in the bodies other than body_a, got 1"),
                        ((ball, 9, 0.3), "body 9 does not exist"), ((ball, shelf, -1.0), "mu"),
                        ((ball, shelf, float("nan")), "mu must be finite"), ((floor, shelf, 0.3), "two static bodies")]:
        with pytest.raises(ValueError, match=words):
            w.add_contact_pair(*args)
    assert w.contact_pairs() == [(shelf, ball, 0.3)]


@pytest.mark.slow
def test_bin_of_50_mixed_shapes_pours_and_settles_without_a_failed_lcp():
    """Boxes, spheres, capsules, cylinders and hulls dropped into a mesh bin
    (floor and four walls, 10 triangles): 5 s, no failed LCP, every body in
    the bin, boxes and hulls at rest; with no rolling resistance a sphere, capsule
    or cylinder may still roll (at 5 s one sphere rolls at 0.12 m/s), on the pile."""
    half, height = 0.6, 0.8
    v = [(-half, -half, 0), (half, -half, 0), (half, half, 0), (-half, half, 0)]
    v += [(x, y, height) for x, y, _ in v]
    f = [(0, 1, 2), (0, 2, 3), (0, 4, 5), (0, 5, 1), (1, 5, 6), (1, 6, 2), (2, 6, 7), (2, 7, 3), (3, 7, 4), (3, 4, 0)]
    w = World(dt=2e-3, max_halvings=3)
    w.add_mesh(v, f, mu=0.5)
    rng = np.random.default_rng(7)
    tetra = np.array([[0, 0, 0], [0.16, 0, 0], [0, 0.16, 0], [0, 0, 0.16]])
    for k in range(50):
        p = (-0.3 + 0.3 * (k % 3), -0.3 + 0.3 * ((k // 3) % 3), 0.15 + 0.25 * (k // 9))
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        [
            lambda: w.add_box(half_extents=(0.07, 0.06, 0.05), position=p, orientation=q),
            lambda: w.add_sphere(0.07, position=p),
            lambda: w.add_capsule(0.05, 0.06, position=p, orientation=q),
            lambda: w.add_cylinder(0.06, 0.05, position=p, orientation=q),
            lambda: w.add_convex(tetra, position=p, orientation=q),
        ][k % 5]()
    traj = w.run(2500)
    assert traj.lcp_stats().failures == 0
    end = traj.positions[-1, 1:]
    assert np.abs(end[:, :2]).max() < half and end[:, 2].min() > 0 and end[:, 2].max() < 0.3
    v = traj.velocities[-1, 1:, :3]
    flat = [k for k in range(50) if k % 5 in (0, 4)]  # boxes and hulls cannot roll
    assert np.linalg.norm(v[flat], axis=1).max() < 0.05 and np.abs(v[:, 2]).max() < 0.05


def test_viewer_page_carries_the_new_shapes(tmp_path):
    w = World()
    w.add_ground()
    w.add_capsule(0.1, 0.3, position=(0, 0, 0.1))
    w.add_cylinder(0.1, 0.1, position=(1, 0, 0.1))
    w.add_convex([[0, 0, 0], [0.2, 0, 0], [0, 0.2, 0], [0, 0, 0.2]], position=(2, 0, 0.1))
    page = w.run(5, record_contacts=True).to_html(tmp_path / "shapes.html")
    html = open(page, encoding="utf-8").read()
    for word in ('"capsule"', '"cylinder"', '"convex"', '"half_length"', '"vertices"', '"faces"', "CapsuleGeometry"):
        assert word in html, word
