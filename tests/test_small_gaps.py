"""The smaller gaps — a ValueError naming the field where an
OverflowError or a late TypeError came out, inertia tensors no rigid body has,
a message about the mass when the mass is what is wrong, and a pivot count
that respects max_pivots = 0."""

from __future__ import annotations

import numpy as np
import pytest

import lcpsim
import lcpsim.certification
from lcpsim import World, generate, solve_lcp, solve_lcp_batch

M = np.array([[2.0, 1.0], [1.0, 2.0]])
Q = np.array([-1.0, -1.0])


@pytest.mark.parametrize("threads", [2**64, -1, 1.5, True])
def test_batch_threads_are_value_errors(threads):
    with pytest.raises(ValueError, match="threads"):
        solve_lcp_batch(M[None], Q[None], threads=threads)
    with pytest.raises(ValueError, match="threads"):
        lcpsim.certification.certify_batch(M[None], Q[None], np.ones((1, 2), dtype=bool), threads=threads)


def test_world_threads_2_64_is_a_value_error():
    with pytest.raises(ValueError, match="threads"):
        World(threads=2**64)


def test_body_index_2_64_is_a_value_error():
    w = World()
    w.add_box(size=1.0)
    for call in (lambda: w.apply_force(2**64, (1.0, 0.0, 0.0)), lambda: w.set_velocity(2**64, (0, 0, 0))):
        with pytest.raises(ValueError, match="body"):
            call()


@pytest.mark.parametrize(
    "call",
    [
        lambda: generate.spd_lcp(3, seed=-1),
        lambda: generate.p_matrix_lcp(3, seed=2**64),
        lambda: generate.contact_lcp(2, seed=-5),
        lambda: generate.hard_contact_lcp("many_contacts", seed=-1),
        lambda: generate.hard_corpus(-1, 2),
        lambda: generate.spd_lcp(3.0),
    ],
)
def test_generator_integers_are_value_errors(call):
    with pytest.raises(ValueError, match="must be an integer"):
        call()


def test_dump_argument_checked_up_front_even_when_solved():
    # Solved, so no dump would be written: the bad argument is still refused.
    with pytest.raises(ValueError, match="dump must be a directory path"):
        solve_lcp(M, Q, dump=123)


def test_inertia_must_obey_the_triangle_inequality():
    w = World()
    with pytest.raises(ValueError, match="triangle inequality"):
        w.add_box(size=1.0, inertia=np.diag([1.0, 1.0, 10.0]))
    # Rotated, the same tensor is refused too (principal moments, not the diagonal).
    c, s = np.cos(0.3), np.sin(0.3)
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]]) @ np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    with pytest.raises(ValueError, match="triangle inequality"):
        w.add_box(size=1.0, inertia=R @ np.diag([1.0, 10.0, 1.0]) @ R.T)
    # A flat plate sits on the boundary (I₁ + I₂ = I₃) and is a rigid body.
    w.add_box(size=1.0, inertia=np.diag([1.0, 1.0, 2.0]))
    w.add_sphere(radius=0.5, inertia=R @ np.diag([1.0, 2.0, 2.5]) @ R.T)


def test_a_tiny_mass_is_named_as_the_problem():
    with pytest.raises(ValueError, match=r"^mass must be .*got 1e-300$"):
        World().add_box(size=1.0, mass=1e-300)
    # Small but sound masses work.
    World().add_box(size=1.0, mass=1e-12)


@pytest.mark.parametrize("pivoting", ["lexicographic", "classic"])
def test_max_pivots_zero_does_no_pivot(pivoting):
    r = solve_lcp(M, Q, max_pivots=0, pivoting=pivoting)
    assert (r.status, r.pivots) == ("max_pivots", 0)
    r = solve_lcp(M, Q, max_pivots=1, pivoting=pivoting)
    assert r.pivots <= 1
    # z = 0 solves an LCP with q ≥ 0 without any pivot, whatever the budget.
    r = solve_lcp(M, -Q, max_pivots=0, pivoting=pivoting)
    assert (r.status, r.pivots) == ("solved", 0)
