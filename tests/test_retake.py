"""A step whose LCP fails, taken again in halves (``World(max_halvings=)``),
through the Python layer: the parameter, the record, the trajectory and its file."""

import numpy as np
import pytest

from lcpsim import Trajectory, World

H = 1e-3


def resting_cube(**kw) -> World:
    w = World(**kw)
    w.add_ground(mu=0.5)
    w.add_box(size=1.0, mass=1.0, position=(0, 0, 0.5))
    return w


def test_a_step_whose_lcp_keeps_failing_is_halved_and_says_so():
    # One PGS sweep never reaches 1e-10 on a resting cube: every attempt fails.
    w = resting_cube(method="pgs", max_iterations=1, max_halvings=2)
    assert w.params["max_halvings"] == 2
    r = w.step()
    assert r.parts == 4 and r.dt == H / 4 and r.time == 3 * H / 4
    assert [(t["time"], t["h"]) for t in r.retakes] == [(0.0, H), (0.0, H / 2), (H / 2, H / 2)]
    assert all(t["status"] == ("max_iterations",) and t["lcp_size"] == (40,) for t in r.retakes)
    assert r.pivots == 7 and r.status == "max_iterations" and r.zeroed
    assert w.steps == 1 and w.time == H


def test_halvings_change_nothing_when_every_lcp_is_solved(tmp_path):
    plain, ready = resting_cube(), resting_cube(max_halvings=3)
    a, b = plain.run(50), ready.run(50)
    np.testing.assert_array_equal(a.positions, b.positions)
    assert (b.parts == 1).all() and b.lcp_stats().retaken == 0
    # The trajectory file keeps the parts (format version 2).
    failing = resting_cube(method="pgs", max_iterations=1, max_halvings=1).run(3)
    assert failing.parts.tolist() == [2, 2, 2] and failing.lcp_stats().retaken == 3
    again = Trajectory.load(failing.save(tmp_path / "t.h5"))
    assert again.parts.tolist() == [2, 2, 2]


def test_a_version_1_trajectory_file_reads_as_one_part_per_step(tmp_path):
    import h5py

    path = resting_cube().run(5).save(tmp_path / "v1.h5")
    with h5py.File(path, "r+") as f:
        del f["parts"]
        f.attrs["format_version"] = 1
    assert Trajectory.load(path).parts.tolist() == [1] * 5


@pytest.mark.parametrize("bad", [11, -1, 1.5, True, "2", 2**70])
def test_bad_max_halvings_is_refused_by_name(bad):
    with pytest.raises(ValueError, match="max_halvings"):
        World(max_halvings=bad)


def test_a_capture_holds_the_failed_attempts_and_the_parts(tmp_path):
    from lcpsim import open_capture

    w = resting_cube(method="pgs", max_iterations=1, max_halvings=1)
    w.run(2, capture=tmp_path / "c.h5")
    with open_capture(tmp_path / "c.h5") as c:
        assert c.step.tolist() == [0, 0, 0, 1, 1, 1]
        assert [rec.time for rec in c] == pytest.approx([0, 0, H / 2, H, H, 1.5 * H])

