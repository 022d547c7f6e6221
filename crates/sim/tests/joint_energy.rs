//! The energy audit with joints (`pipeline::energy`): ideal joints do no
//! work, a motor does its torque times the angle it turns, and a failed
//! solve in an island with joints applies no impulse that adds energy.

use lcp::{Lcp, Solution, Status};
use sim::math::Vec3;
use sim::{JointDesc, JointKind, World, WorldParams};

/// A ball of 2 kg and radius 0.1 m on an arm of 1 m hinged to the world
/// (axis y), swinging down at 1 m/s onto the ground, 0.5 mm above it.
fn hinged_ball_hitting_the_ground() -> (World, usize) {
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_ground(0.5).unwrap();
    let r = 0.1;
    let ball = w.add_sphere(r, 2.0, Vec3::new(1.0, 0.0, r + 5e-4), 0.5).unwrap().0;
    w.set_velocity(sim::BodyId(ball), Vec3::new(0.0, 0.0, -1.0)).unwrap();
    w.set_angular_velocity(sim::BodyId(ball), Vec3::Y).unwrap();
    let hinge = JointDesc {
        kind: JointKind::Hinge,
        body_a: None,
        body_b: ball,
        anchor: Vec3::new(0.0, 0.0, r + 5e-4),
        axis: Vec3::Y,
        limits: None,
    };
    w.add_joint(hinge).unwrap();
    (w, ball)
}

#[test]
fn a_failed_solve_with_joints_applies_the_impulse_best_for_the_jointed_motion() {
    // The step solved, then failed with answers 1 to 50 times too large. A
    // failed answer is applied times the α ∈ [0, 1] minimizing the energy after
    // the step along the motion the joint allows: the ball's centre moves
    // vertically (tangent to its circle) with the effective mass
    // m_eff = m + I/L², so E(v⁺) = ½ m_eff v⁺² + m g h v⁺ (the potential of the
    // position update) is least at v⁺ = −m g h / m_eff. The right answer is
    // applied whole (α = 1 is the bound), and no step has more energy than the
    // same step with no impulse.
    let (m, r, l, h, g) = (2.0, 0.1, 1.0, 1e-3, 9.81);
    let m_eff = m + 0.4 * m * r * r / (l * l);
    let (w0, ball) = hinged_ball_hitting_the_ground();
    let mut solved = w0.clone();
    let rec = solved.step().unwrap().clone();
    assert!(rec.ok() && rec.nc() == 1 && rec.total_normal_impulse() > 0.0);
    let v_solved = solved.body(sim::BodyId(ball)).unwrap().velocity();
    let mut none = w0.clone();
    let mut zero = |l: &Lcp| Solution::from_z(l, vec![0.0; l.n()], Status::MaxPivots, 1);
    let floor = none.step_with(&mut zero).unwrap().energy.after;
    for factor in [1.0, 3.0, 10.0, 50.0] {
        let mut w = w0.clone();
        let mut wrong = |l: &Lcp| {
            let right = lcp::solve(l, &lcp::Method::default());
            Solution::from_z(l, right.z.iter().map(|v| v * factor).collect(), Status::MaxPivots, 1)
        };
        let rec = w.step_with(&mut wrong).unwrap().clone();
        assert!(rec.zeroed);
        let v = w.body(sim::BodyId(ball)).unwrap().velocity();
        let expect = if factor == 1.0 { v_solved.z } else { -m * g * h / m_eff };
        assert!((v.z - expect).abs() <= 1e-9, "factor {factor}: v_z = {}, expected {expect}", v.z);
        assert!(v.x.abs() <= 1e-12, "factor {factor}: the ball left its circle, v_x = {}", v.x);
        let e = rec.energy;
        assert!(e.after <= floor + 1e-12, "factor {factor}: {} J after, {} J with no impulse", e.after, floor);
        assert!(e.created() <= 1e-12, "factor {factor}: created {:e} J", e.created());
    }
}

/// A sphere of 1 kg, radius 0.05 m, on a hinge (axis y) 1 m from the anchor,
/// released horizontal: `steps` steps of `h`, its energy at the start, and each
/// step's audit and velocity change `(Δv, Δω)`.
fn pendulum_run(h: f64, steps: usize) -> (f64, Vec<(sim::EnergyAudit, Vec3, Vec3)>) {
    let mut w = World::new(WorldParams { dt: h, ..Default::default() }).unwrap();
    let ball = w.add_sphere(0.05, 1.0, Vec3::new(1.0, 0.0, 2.0), 0.5).unwrap().0;
    let hinge = JointDesc {
        kind: JointKind::Hinge,
        body_a: None,
        body_b: ball,
        anchor: Vec3::new(0.0, 0.0, 2.0),
        axis: Vec3::Y,
        limits: None,
    };
    w.add_joint(hinge).unwrap();
    let e0 = w.energy();
    let velocities = |w: &World| {
        let b = w.body(sim::BodyId(ball)).unwrap();
        (b.velocity(), b.angular_velocity())
    };
    let run = (0..steps).map(|_| {
        let (v, om) = velocities(&w);
        let e = w.step().unwrap().energy;
        let (v2, om2) = velocities(&w);
        (e, v2 - v, om2 - om)
    });
    (e0, run.collect())
}

#[test]
fn a_frictionless_pendulums_hinge_does_no_work_and_its_energy_drifts_as_euler_does() {
    let (e0, steps) = pendulum_run(1e-3, 2000);
    let (m, i) = (1.0, 0.4 * 0.05 * 0.05);
    for (k, (e, dv, dw)) in steps.iter().enumerate() {
        // The ideal hinge does no work (its drift correction asks for C ≈ 0).
        assert!(e.joint_drift.abs() <= 1e-9 * e0, "step {k}: joint drift work {:e} J", e.joint_drift);
        // What semi-implicit Euler loses with the velocity projected onto the
        // joint: the energy of the step's velocity change, ½ m |Δv|² + ½ I |Δω|²
        // (a sphere: I isotropic); the pull back onto the circle after the step
        // is the projection's term, not energy created.
        let euler = -0.5 * (m * dv.norm_squared() + i * dw.norm_squared());
        assert!(
            (e.created() - euler).abs() <= 1e-9 * euler.abs(),
            "step {k}: created {:e} J, Euler {euler:e} J",
            e.created()
        );
        if k > 0 {
            assert_eq!(e.before, steps[k - 1].0.after, "step {k}: the audits do not chain");
        }
    }
    // That loss is first order: half the step, half the drift over the same
    // 2 s (0.7 % of E at h = 1 ms).
    let drift = |h: f64| {
        let (e0, run) = pendulum_run(h, (2.0 / h).round() as usize);
        (run.last().unwrap().0.after - e0) / e0
    };
    let (coarse, fine) = (drift(1e-3), drift(5e-4));
    assert!(coarse < 0.0 && coarse > -0.02, "drift {coarse:e}");
    assert!((coarse / fine - 2.0).abs() < 0.2, "drift {coarse:e} at h, {fine:e} at h/2");
}

#[test]
fn a_motor_does_its_torque_times_the_angle_it_turns() {
    // A bar on a vertical hinge (gravity does no work), its motor asking for
    // more speed than its torque bound τ reaches in 1 s: every step it pushes
    // with τ h, so its work is τ Δθ, and the step loses only what
    // semi-implicit Euler loses to an impulse, ½ (τ h)² / I a step.
    let (m, hx, hy, tau, h, steps) = (2.0, 0.5, 0.05, 0.5, 1e-3, 1000);
    let inertia = m / 12.0 * ((2.0 * hx) * (2.0 * hx) + (2.0 * hy) * (2.0 * hy));
    let mut w = World::new(WorldParams::default()).unwrap();
    let bar = w.add_box(Vec3::new(hx, hy, hy), m, Vec3::new(0.0, 0.0, 1.0), 0.5).unwrap().0;
    let hinge = JointDesc {
        kind: JointKind::Hinge,
        body_a: None,
        body_b: bar,
        anchor: Vec3::new(0.0, 0.0, 1.0),
        axis: Vec3::Z,
        limits: None,
    };
    let j = w.add_joint(hinge).unwrap();
    w.set_motor(j, 100.0, tau).unwrap();
    let e0 = w.energy();
    let (mut work, mut created) = (0.0, 0.0);
    for _ in 0..steps {
        let r = w.step().unwrap();
        assert!(r.ok());
        work += r.energy.motor_work;
        created += r.energy.created();
    }
    let angle = w.joints()[j.0].angle(w.bodies()); // < π: no wrap
                                                   // The work is τ Σ h θ̇⁺; the quaternion update turns by 2 atan(h θ̇⁺/2), short
                                                   // of h θ̇⁺ by (h θ̇⁺)³/12 a step: 5.6e-7 rad over this run.
    assert!((work - tau * angle).abs() <= 1e-6 * work, "motor work {work} J, τ Δθ = {} J", tau * angle);
    let euler = -(steps as f64) * 0.5 * (tau * h).powi(2) / inertia;
    assert!((created - euler).abs() <= 1e-6 * euler.abs(), "created {created:e} J, expected {euler:e} J");
    assert!((w.energy() - e0 - work - created).abs() <= 1e-12);
}

#[test]
fn a_hinge_stop_only_dissipates_and_is_no_contacts_penetration_correction() {
    // A 1 m, 1 kg bar hinged at one end falls from level onto its stop at
    // 0.6 rad: the stop's row is the joints' (a limit, not a contact), so the
    // contacts' correction does nothing; the stop is inelastic, so no step
    // creates energy: from level to rest on the stop the steps lose the drop in
    // potential, m g (L/2) sin 0.6, less the projections' 1.4 mJ.
    let mut w = World::new(WorldParams::default()).unwrap();
    let bar = w.add_box(Vec3::new(0.5, 0.03, 0.03), 1.0, Vec3::new(0.5, 0.0, 2.0), 0.5).unwrap().0;
    let hinge = JointDesc {
        kind: JointKind::Hinge,
        body_a: None,
        body_b: bar,
        anchor: Vec3::new(0.0, 0.0, 2.0),
        axis: Vec3::Y,
        limits: Some((-0.2, 0.6)),
    };
    w.add_joint(hinge).unwrap();
    let e0 = w.energy();
    let (mut worst, mut lost) = (f64::NEG_INFINITY, 0.0);
    for _ in 0..1500 {
        let r = w.step().unwrap();
        assert!(r.ok());
        let e = r.energy;
        assert_eq!(e.stabilization, 0.0);
        worst = worst.max(e.created());
        lost -= e.created();
    }
    assert!(worst <= 1e-12 * e0, "a step created {worst:e} J");
    let drop = 9.81 * 0.5 * 0.6f64.sin();
    assert!(w.bodies()[bar].angular_velocity().norm() < 1e-6);
    assert!((lost - drop).abs() < 2e-3 && lost > drop, "lost {lost} J, the drop is {drop} J");
}
