//! A step whose LCP fails, taken again in halves (`WorldParams::max_halvings`):
//! the halves are exactly two steps of `h/2`, the step still advances `dt`,
//! and the record says what happened.

use sim::lcp::{self, Lcp, Solution, Status};
use sim::scenes::BoxStack;
use sim::{World, WorldParams};

const DT: f64 = 1e-3;

/// A resting stack of three boxes (contacts on every step, one island).
fn stack(params: WorldParams) -> World {
    BoxStack::new(3).build(params).unwrap().world
}

/// A solver whose first `fails` calls end `Numerical` after 5 pivots and whose
/// later ones are the robust Lemke's; `calls` counts them.
fn failing_first(fails: usize, calls: &mut usize) -> impl FnMut(&Lcp) -> Solution + '_ {
    move |l: &Lcp| {
        *calls += 1;
        if *calls <= fails {
            Solution::from_z(l, vec![0.0; l.n()], Status::Numerical, 5)
        } else {
            lcp::solve(l, &lcp::Method::default())
        }
    }
}

#[test]
fn a_failed_step_is_taken_again_as_two_steps_of_half_the_length() {
    let mut retaken = stack(WorldParams { max_halvings: 1, ..WorldParams::default() });
    let mut halves = stack(WorldParams { dt: DT / 2.0, ..WorldParams::default() });
    let energy = retaken.energy();
    // The first solve fails, every later one is the robust Lemke's.
    let mut calls = 0;
    let r = retaken.step_with(&mut failing_first(1, &mut calls)).unwrap().clone();
    assert_eq!(calls, 3, "the failed attempt, then one solve per half");
    let mut solve = |l: &Lcp| lcp::solve(l, &lcp::Method::default());
    let first = halves.step_with(&mut solve).unwrap().pivots;
    let second = halves.step_with(&mut solve).unwrap().clone();
    // Nothing of the failed attempt reached the bodies: the same state, bit for bit.
    assert_eq!(retaken.bodies(), halves.bodies());
    // One step of dt, recorded as its last part plus what came before it.
    assert_eq!((retaken.steps(), retaken.time()), (1, DT));
    assert_eq!((r.step, r.parts, r.time, r.dt), (0, 2, DT / 2.0, DT / 2.0));
    assert_eq!((r.status, r.z.clone(), r.contacts.clone()), (second.status, second.z, second.contacts));
    assert_eq!(r.retakes.len(), 1);
    let t = &r.retakes[0];
    assert_eq!((t.time, t.h, t.pivots), (0.0, DT, 5));
    assert_eq!(t.islands.iter().map(|i| i.status).collect::<Vec<_>>(), [Status::Numerical]);
    assert_eq!(r.pivots, 5 + first + second.pivots, "every attempt's pivots");
    // The energy audit spans the whole step.
    assert_eq!((r.energy.before, r.energy.after), (energy, retaken.energy()));
    assert!(r.ok());
}

#[test]
fn a_step_that_keeps_failing_is_halved_as_deep_as_allowed_then_left_to_the_failed_solve_policy() {
    let mut w = stack(WorldParams { max_halvings: 2, ..WorldParams::default() });
    let mut calls = 0;
    let r = w.step_with(&mut failing_first(usize::MAX, &mut calls)).unwrap().clone();
    // 1 attempt at h, 2 at h/2, then 4 parts of h/4 that keep their failure.
    assert_eq!(calls, 7);
    assert_eq!((r.parts, r.dt, r.time), (4, DT / 4.0, 3.0 * DT / 4.0));
    let tried: Vec<_> = r.retakes.iter().map(|t| (t.time, t.h)).collect();
    assert_eq!(tried, [(0.0, DT), (0.0, DT / 2.0), (DT / 2.0, DT / 2.0)]);
    assert_eq!(r.pivots, 7 * 5);
    assert!(!r.ok() && r.zeroed);
    assert_eq!((w.steps(), w.time()), (1, DT));
    // The next step is a step of dt again.
    let next = w.step().unwrap();
    assert_eq!((next.step, next.parts, next.dt, next.time), (1, 1, DT, DT));
    assert!(next.retakes.is_empty());
}

#[test]
fn a_part_left_failed_makes_the_step_failed_though_the_last_part_solved() {
    let mut w = stack(WorldParams { max_halvings: 1, ..WorldParams::default() });
    // The attempt at h and the first half fail, the second half is solved.
    let mut calls = 0;
    let r = w.step_with(&mut failing_first(2, &mut calls)).unwrap().clone();
    assert_eq!((calls, r.parts, r.retakes.len()), (3, 2, 1));
    assert!(r.islands.iter().all(|i| i.status == Status::Solved), "the last part's islands");
    assert_eq!(r.status, Some(Status::Numerical));
    assert!(!r.ok() && r.zeroed);
}

#[test]
fn without_halvings_a_failure_is_recorded_as_it_happened() {
    let mut w = stack(WorldParams::default());
    let mut calls = 0;
    let r = w.step_with(&mut failing_first(usize::MAX, &mut calls)).unwrap().clone();
    assert_eq!((calls, r.parts, r.dt, r.status), (1, 1, DT, Some(Status::Numerical)));
    assert!(r.retakes.is_empty() && r.zeroed);
}

#[test]
fn halvings_change_nothing_when_every_lcp_is_solved() {
    let mut plain = stack(WorldParams::default());
    let mut ready = stack(WorldParams { max_halvings: 3, ..WorldParams::default() });
    for _ in 0..200 {
        let (a, b) = (plain.step().unwrap().clone(), ready.step().unwrap().clone());
        assert_eq!(a, b);
        assert_eq!(b.parts, 1);
    }
    assert_eq!(plain.bodies(), ready.bodies());
}

#[test]
fn too_many_halvings_are_refused_by_name() {
    let most = sim::limits::MAX_HALVINGS;
    assert!(World::new(WorldParams { max_halvings: most, ..WorldParams::default() }).is_ok());
    let e = World::new(WorldParams { max_halvings: most + 1, ..WorldParams::default() }).unwrap_err().to_string();
    assert!(e.contains("max_halvings") && e.contains("11") && e.contains(&format!("[0, {most}]")), "{e}");
}

#[test]
fn an_error_in_a_later_part_leaves_the_bodies_where_the_step_began() {
    use sim::math::Vec3;
    let mut w = stack(WorldParams { max_halvings: 1, ..WorldParams::default() });
    // A free box near the largest f64, flying on: the first half moves it
    // past f64::MAX, so the second half's free velocities see a position
    // that is no longer finite.
    let far = w.add_box(Vec3::new(0.5, 0.5, 0.5), 1.0, Vec3::new(1.7976e308, 0.0, 10.0), 0.5).unwrap();
    w.set_velocity(far, Vec3::new(1e308, 0.0, 0.0)).unwrap();
    let before = (w.bodies().to_vec(), w.steps(), w.time());
    let mut first = true;
    let mut solver = |l: &Lcp| {
        let fail = std::mem::take(&mut first);
        if fail {
            Solution::from_z(l, vec![0.0; l.n()], Status::Numerical, 5)
        } else {
            lcp::solve(l, &lcp::Method::default())
        }
    };
    let e = w.step_with(&mut solver).map(|_| ()).unwrap_err().to_string();
    assert!(e.contains("non-finite"), "{e}");
    // The first half had moved every body (the stack by h/2, the far box to
    // infinity) and the clock: all put back.
    assert_eq!((w.bodies().to_vec(), w.steps(), w.time()), before);
}
