//! Joints (`sim::joints`): pendulums against their analytic periods, joints
//! held closed, dependent rows, a hinge and a slider against contact and
//! gravity with analytic forces — every LCP solved.

mod common;
use common::*;
use sim::math::Vec3;
use sim::{BodyDesc, JointDesc, JointId, JointKind, World, WorldParams};

fn world() -> World {
    World::new(WorldParams::default()).unwrap()
}

fn joint(kind: JointKind, a: Option<usize>, b: usize, anchor: Vec3, axis: Vec3) -> JointDesc {
    JointDesc { kind, body_a: a, body_b: b, anchor, axis, limits: None }
}

/// Times between successive upward zero crossings of `x(t)` (linear interpolation), averaged.
fn period(xs: &[f64], dt: f64) -> f64 {
    let ups: Vec<f64> = (1..xs.len())
        .filter(|&i| xs[i - 1] < 0.0 && xs[i] >= 0.0)
        .map(|i| (i - 1) as f64 * dt + dt * xs[i - 1] / (xs[i - 1] - xs[i]))
        .collect();
    assert!(ups.len() >= 3, "too few crossings: {}", ups.len());
    (ups[ups.len() - 1] - ups[0]) / (ups.len() - 1) as f64
}

/// A sphere of radius `r`, mass 1 on a hinge (axis y) `l` below the anchor at
/// (0, 0, 2), released at `theta0`; extra hinges on the same axis if `copies > 1`.
fn pendulum(l: f64, r: f64, theta0: f64, copies: usize) -> (World, usize) {
    let mut w = world();
    let anchor = Vec3::new(0.0, 0.0, 2.0);
    let p = anchor + Vec3::new(l * theta0.sin(), 0.0, -l * theta0.cos());
    let b = w.add_sphere(r, 1.0, p, 0.5).unwrap().0;
    for _ in 0..copies {
        w.add_joint(joint(JointKind::Hinge, None, b, anchor, Vec3::Y)).unwrap();
    }
    (w, b)
}

/// Runs a pendulum for `t` s: its period from the x crossings and the largest
/// error of the link length.
fn swing(mut w: World, b: usize, l: f64, t: f64) -> (f64, f64) {
    let anchor = Vec3::new(0.0, 0.0, 2.0);
    let steps = (t / 1e-3) as usize;
    let (mut xs, mut worst) = (Vec::with_capacity(steps), 0.0f64);
    for _ in 0..steps {
        step_ok(&mut w);
        let p = w.body(sim::BodyId(b)).unwrap().position();
        xs.push(p.x);
        worst = worst.max(((p - anchor).norm() - l).abs());
    }
    (period(&xs, 1e-3), worst)
}

#[test]
fn hinge_pendulum_swings_at_the_physical_pendulum_period_with_its_length_held() {
    let (l, r, theta0) = (1.0, 0.05, 0.05);
    let (w, b) = pendulum(l, r, theta0, 1);
    let (t, worst) = swing(w, b, l, 10.0);
    // T = 2π √(I_pivot / (m g l)), I_pivot = 2/5 m r² + m l²; the amplitude adds θ₀²/16.
    let expect = 2.0 * std::f64::consts::PI * ((0.4 * r * r + l * l) / (G * l)).sqrt() * (1.0 + theta0 * theta0 / 16.0);
    eprintln!("hinge pendulum: period {t} s vs {expect} s ({:.2e} off), length off by {worst:e} m", rel(t, expect));
    assert!(rel(t, expect) < 5e-3, "period {t} vs {expect}");
    assert!(worst <= 1e-6, "link length off by {worst:e} m");
}

#[test]
fn two_identical_hinges_are_one_hinge() {
    let (l, r, theta0) = (1.0, 0.05, 0.05);
    let (w1, b1) = pendulum(l, r, theta0, 1);
    let (w2, b2) = pendulum(l, r, theta0, 2);
    let mut probe = w2.clone();
    probe.step().unwrap();
    let (t1, e1) = swing(w1, b1, l, 8.0);
    let (t2, e2) = swing(w2, b2, l, 8.0);
    assert!(rel(t2, t1) < 1e-9, "period {t2} vs {t1} with one hinge");
    assert!(e1 <= 1e-6 && e2 <= 1e-6, "length errors {e1:e}, {e2:e}");
    assert!(probe.joint_error(JointId(1)).unwrap().0 <= 1e-6);
}

/// `n` unit boxes 0.2 m long on ball joints end to end along x from a world
/// anchor at (0, 0, 2): released horizontally.
fn chain(n: usize, kind: JointKind) -> World {
    let mut w = world();
    let half = Vec3::new(0.1, 0.02, 0.02);
    for i in 0..n {
        let c = Vec3::new(0.2 * i as f64 + 0.1, 0.0, 2.0);
        let b = w.add_body(BodyDesc::cuboid(half).mass(0.5).position(c)).unwrap().0;
        let anchor = Vec3::new(0.2 * i as f64, 0.0, 2.0);
        let a = (i > 0).then(|| b - 1);
        w.add_joint(joint(kind, a, b, anchor, Vec3::Y)).unwrap();
    }
    w
}

#[test]
fn five_link_ball_chain_released_horizontally_stays_closed() {
    let mut w = chain(5, JointKind::Ball);
    let (mut worst, mut lowest) = (0.0f64, f64::INFINITY);
    for _ in 0..2000 {
        step_ok(&mut w);
        for j in 0..5 {
            worst = worst.max(w.joint_error(JointId(j)).unwrap().0);
        }
        lowest = lowest.min(w.bodies()[4].position().z);
    }
    // It fell and swung: the last link went well below the anchor.
    assert!(lowest < 1.2, "lowest z {lowest}");
    eprintln!("5-link ball chain, 2 s: largest joint error {worst:e} m");
    assert!(worst <= 1e-6, "a joint opened by {worst:e} m");
}

#[test]
fn a_fixed_joint_to_the_world_holds_a_body_still() {
    let mut w = world();
    let b = w.add_box(Vec3::splat(0.1), 1.0, Vec3::new(0.3, 0.0, 1.0), 0.5).unwrap().0;
    w.set_angular_velocity(sim::BodyId(b), Vec3::new(1.0, 2.0, 3.0)).unwrap();
    w.add_joint(joint(JointKind::Fixed, None, b, Vec3::new(0.0, 0.0, 1.0), Vec3::Z)).unwrap();
    run_ok(&mut w, 500);
    let body = &w.bodies()[b];
    assert!((body.position() - Vec3::new(0.3, 0.0, 1.0)).norm() < 1e-6, "{:?}", body.position());
    assert!(body.velocity().norm() < 1e-9 && body.angular_velocity().norm() < 1e-9);
    // The reaction carries its weight.
    let r = w.last_record().joints[0];
    assert!((r.force - Vec3::new(0.0, 0.0, G)).norm() < 1e-9, "{:?}", r.force);
}

#[test]
fn a_box_on_a_tilted_slider_slides_at_g_cos_theta() {
    let mut w = world();
    let b = w.add_box(Vec3::splat(0.1), 1.0, Vec3::new(0.0, 0.0, 1.0), 0.5).unwrap().0;
    let th = 30f64.to_radians();
    let axis = Vec3::new(th.sin(), 0.0, th.cos());
    w.add_joint(joint(JointKind::Slider, None, b, Vec3::new(0.0, 0.0, 1.0), axis)).unwrap();
    run_ok(&mut w, 1000);
    let v = w.bodies()[b].velocity();
    let expect = -G * th.cos();
    assert!(rel(v.dot(axis), expect) < 1e-9, "{} vs {expect}", v.dot(axis));
    assert!((v - axis * v.dot(axis)).norm() < 1e-9, "off-axis velocity {:?}", v);
    assert!(w.joint_error(JointId(0)).unwrap().0 < 1e-6);
}

#[test]
fn a_hinged_bar_resting_on_a_sphere_carries_the_moment_balance() {
    // A 1 m, 2 kg bar hinged to the world at x = 0, resting at x = 0.95 on a
    // static sphere: F · 0.95 = m g · 0.5, the hinge takes m g − F.
    let mut w = world();
    let bar = w
        .add_body(BodyDesc::cuboid(Vec3::new(0.5, 0.05, 0.05)).mass(2.0).position(Vec3::new(0.5, 0.0, 1.0)))
        .unwrap()
        .0;
    let r = 0.1;
    w.add_body(BodyDesc::sphere(r).position(Vec3::new(0.95, 0.0, 0.95 - r)).fixed(true)).unwrap();
    w.add_joint(joint(JointKind::Hinge, None, bar, Vec3::new(0.0, 0.0, 1.0), Vec3::Y)).unwrap();
    let rec = run_ok(&mut w, 500);
    assert_eq!(rec.contacts.len(), 1);
    let f = rec.z[0] / 1e-3;
    let expect = 2.0 * G * 0.5 / 0.95;
    assert!(rel(f, expect) < 1e-6, "contact force {f} vs {expect}");
    let hinge = rec.joints[0].force.z;
    assert!(rel(hinge, 2.0 * G - expect) < 1e-6, "hinge {hinge} vs {}", 2.0 * G - expect);
    assert!(w.bodies()[bar].angular_velocity().norm() < 1e-9);
}

#[test]
fn a_hanging_parallelogram_closed_loop_swings_with_its_coupler_level() {
    // Two 0.5 m links hinged to the world at x = 0 and x = 1, a coupler
    // hinged to both: a closed loop whose 20 hinge rows have rank 17 at most.
    let mut w = world();
    let link = BodyDesc::cuboid(Vec3::new(0.02, 0.02, 0.25)).mass(0.5);
    let left = w.add_body(link.clone().position(Vec3::new(0.0, 0.0, 1.75))).unwrap().0;
    let right = w.add_body(link.position(Vec3::new(1.0, 0.0, 1.75))).unwrap().0;
    let coupler = w
        .add_body(BodyDesc::cuboid(Vec3::new(0.5, 0.02, 0.02)).mass(1.0).position(Vec3::new(0.5, 0.0, 1.5)))
        .unwrap()
        .0;
    for (a, b, anchor) in [
        (None, left, Vec3::new(0.0, 0.0, 2.0)),
        (None, right, Vec3::new(1.0, 0.0, 2.0)),
        (Some(left), coupler, Vec3::new(0.0, 0.0, 1.5)),
        (Some(right), coupler, Vec3::new(1.0, 0.0, 1.5)),
    ] {
        w.add_joint(joint(JointKind::Hinge, a, b, anchor, Vec3::Y)).unwrap();
    }
    w.set_velocity(sim::BodyId(coupler), Vec3::new(1.0, 0.0, 0.0)).unwrap();
    let (mut worst, mut tilt, mut reach) = (0.0f64, 0.0f64, 0.0f64);
    for _ in 0..3000 {
        step_ok(&mut w);
        for j in 0..4 {
            worst = worst.max(w.joint_error(JointId(j)).unwrap().0);
        }
        let c = &w.bodies()[coupler];
        tilt = tilt.max(c.orientation().angle_to(sim::math::Quat::IDENTITY));
        reach = reach.max(c.position().x - 0.5);
    }
    assert!(reach > 0.05, "the coupler hardly moved: {reach}");
    assert!(worst <= 1e-6, "a hinge opened by {worst:e} m");
    assert!(tilt < 1e-6, "the coupler tilted by {tilt:e} rad");
}

#[test]
fn a_door_swinging_shut_stops_against_its_stop() {
    // A 1 m × 2 m door hinged about z at the origin turns at 1 rad/s towards
    // a static stop that meets it at 90°; no restitution: it stays there.
    let mut w = world();
    let door = w
        .add_body(BodyDesc::cuboid(Vec3::new(0.5, 0.02, 1.0)).mass(10.0).position(Vec3::new(0.5, 0.0, 1.05)))
        .unwrap()
        .0;
    w.add_body(BodyDesc::cuboid(Vec3::splat(0.05)).position(Vec3::new(-0.07, 0.8, 1.05)).fixed(true)).unwrap();
    w.add_joint(joint(JointKind::Hinge, None, door, Vec3::new(0.0, 0.0, 1.05), Vec3::Z)).unwrap();
    w.set_angular_velocity(sim::BodyId(door), Vec3::new(0.0, 0.0, 1.0)).unwrap();
    w.set_velocity(sim::BodyId(door), Vec3::new(0.0, 0.5, 0.0)).unwrap();
    let (mut most, mut touched, mut worst) = (f64::NEG_INFINITY, false, 0.0f64);
    for _ in 0..2500 {
        let r = step_ok(&mut w);
        touched |= !r.contacts.is_empty();
        most = most.max(w.joints()[0].angle(w.bodies()));
        worst = worst.max(w.joint_error(JointId(0)).unwrap().0);
    }
    let right = std::f64::consts::FRAC_PI_2;
    assert!(touched, "the door never reached its stop");
    // No further than the stop's face plus the contact margin (1 mm at 0.8 m).
    assert!(most < right + 1.5e-3, "door angle {most} past {right}");
    let angle = w.joints()[0].angle(w.bodies());
    assert!((angle - right).abs() < 2e-3, "door at rest at {angle}");
    assert!(w.bodies()[door].angular_velocity().norm() < 1e-6, "still turning");
    assert!(worst <= 1e-6, "hinge opened by {worst:e} m");
}

#[test]
fn a_ball_chain_dropped_on_the_ground_piles_up_closed() {
    // Ten links over the ground: joints and contacts in one island, every LCP solved.
    let mut w = chain(10, JointKind::Ball);
    // Drop the whole chain: the first link free too (its joint to the world
    // stays; the chain hangs from it and its far end lands).
    w.add_ground(0.5).unwrap();
    let (mut worst, mut deepest, mut contacts) = (0.0f64, 0.0f64, 0usize);
    for _ in 0..2000 {
        let r = step_ok(&mut w);
        contacts = contacts.max(r.contacts.len());
        deepest = r.contacts.iter().fold(deepest, |d, c| d.max(-c.gap));
        for j in 0..10 {
            worst = worst.max(w.joint_error(JointId(j)).unwrap().0);
        }
    }
    assert!(contacts > 0, "the chain never reached the ground");
    assert!(worst <= 1e-6, "a joint opened by {worst:e} m");
    eprintln!(
        "10-link chain on the ground: joint error {worst:e} m, deepest {deepest:e} m, {contacts} contacts at most"
    );
    assert!(deepest < 1e-3, "penetration {deepest}");
}

#[test]
fn a_hinge_limit_stops_a_falling_bar_without_overshoot() {
    // A 1 m bar hinged at one end (axis y) starts level and falls; its hinge
    // stops it at 0.6 rad (the angle grows as it falls, about +y).
    let mut w = world();
    let bar = w
        .add_body(BodyDesc::cuboid(Vec3::new(0.5, 0.03, 0.03)).mass(1.0).position(Vec3::new(0.5, 0.0, 2.0)))
        .unwrap()
        .0;
    let mut d = joint(JointKind::Hinge, None, bar, Vec3::new(0.0, 0.0, 2.0), Vec3::Y);
    d.limits = Some((-0.2, 0.6));
    w.add_joint(d).unwrap();
    let (mut most, mut step_motion, mut hit) = (f64::NEG_INFINITY, 0.0f64, None);
    for s in 0..1500 {
        let before = w.joints()[0].angle(w.bodies());
        let r = step_ok(&mut w);
        let after = w.joints()[0].angle(w.bodies());
        step_motion = step_motion.max((after - before).abs());
        most = most.max(after);
        if hit.is_none() && !r.contacts.is_empty() && r.z[0] > 0.0 {
            hit = Some(s);
        }
    }
    assert!(hit.is_some(), "the limit never acted");
    // Falling freely it would pass 0.6 rad; it stops there, within one step's motion.
    assert!(most <= 0.6 + step_motion, "angle {most} past 0.6 (a step moves {step_motion})");
    let angle = w.joints()[0].angle(w.bodies());
    assert!((angle - 0.6).abs() < 1e-6, "rests at {angle}");
    assert!(w.bodies()[bar].angular_velocity().norm() < 1e-6);
    // At rest on the stop: the limit's impulse balances gravity's moment m g (L/2) cos θ.
    let r = w.last_record();
    let torque = r.z[0] / 1e-3;
    let expect = G * 0.5 * 0.6f64.cos();
    assert!(rel(torque, expect) < 1e-6, "limit torque {torque} vs {expect}");
}

#[test]
fn a_motor_drives_a_hinge_at_its_speed_within_its_force() {
    // A 1 kg bar hinged at one end (axis y) starts level: a motor at 1 rad/s
    // with 10 N·m (more than m g L/2 = 4.9) turns it at 1 rad/s; with 2 N·m
    // (less) it loses to gravity and its torque stays at the bound.
    for (max_force, holds) in [(10.0, true), (2.0, false)] {
        let mut w = world();
        let bar = w
            .add_body(BodyDesc::cuboid(Vec3::new(0.5, 0.03, 0.03)).mass(1.0).position(Vec3::new(0.5, 0.0, 2.0)))
            .unwrap()
            .0;
        let j = w.add_joint(joint(JointKind::Hinge, None, bar, Vec3::new(0.0, 0.0, 2.0), Vec3::Y)).unwrap();
        // Negative speed: up (the angle grows as it falls).
        w.set_motor(j, -1.0, max_force).unwrap();
        let rec = run_ok(&mut w, 300);
        let rate = w.bodies()[bar].angular_velocity().y;
        // The motor's impulse is its first friction row's: Σ c_j fd_j.
        let lay = sim::lcp::ContactLayout::new(rec.contacts.len(), rec.friction_dirs);
        let imp: f64 = lay
            .fd_of(0)
            .enumerate()
            .map(|(jj, f)| (2.0 * std::f64::consts::PI * jj as f64 / 8.0).cos() * rec.z[f])
            .sum();
        if holds {
            assert!((rate + 1.0).abs() < 1e-9, "rate {rate}");
            assert!(imp.abs() / 1e-3 <= max_force * (1.0 + 1e-9));
        } else {
            assert!(rate > 0.0, "it should fall: rate {rate}");
            assert!(rel(imp.abs() / 1e-3, max_force) < 1e-9, "torque {} vs bound {max_force}", imp / 1e-3);
        }
    }
}

#[test]
fn a_two_finger_gripper_lifts_a_cube_and_holds_it_without_slip() {
    // Fingers on sliders to a palm close on a 1 kg cube (μ = 1) with 20 N
    // each; the palm, on a vertical slider to the world, lifts 0.2 m in 2.2 s
    // (0.1 m/s, reached and left over 0.2 s: friction of 40 N can give the
    // cube 0.5 m/s² against gravity, not a step change of speed) and holds 2 s.
    // Round fingertips: one contact each, on a line through the cube's centre,
    // so no LCP answer lets the cube turn (flat pads give four corners a side,
    // and an answer loading one corner per pad, the two on a line along the
    // grip, is as exact as a spread one: with no torsional friction the cube
    // then pivots about that line, docs/joints.md).
    let mut w = world();
    w.add_ground(1.0).unwrap();
    let cube = w.add_box(Vec3::splat(0.05), 1.0, Vec3::new(0.0, 0.0, 0.05), 1.0).unwrap().0;
    let palm = w
        .add_body(BodyDesc::cuboid(Vec3::new(0.15, 0.05, 0.02)).mass(1.0).position(Vec3::new(0.0, 0.0, 0.2)).mu(1.0))
        .unwrap()
        .0;
    let left = w.add_sphere(0.02, 0.2, Vec3::new(-0.1, 0.0, 0.05), 1.0).unwrap().0;
    let right = w.add_sphere(0.02, 0.2, Vec3::new(0.1, 0.0, 0.05), 1.0).unwrap().0;
    let lift = w.add_joint(joint(JointKind::Slider, None, palm, Vec3::new(0.0, 0.0, 0.2), Vec3::Z)).unwrap();
    let jl = w.add_joint(joint(JointKind::Slider, Some(palm), left, Vec3::new(-0.1, 0.0, 0.05), Vec3::X)).unwrap();
    let jr = w.add_joint(joint(JointKind::Slider, Some(palm), right, Vec3::new(0.1, 0.0, 0.05), -Vec3::X)).unwrap();
    w.set_motor(lift, 0.0, 200.0).unwrap();
    w.set_motor(jl, 0.1, 20.0).unwrap();
    w.set_motor(jr, 0.1, 20.0).unwrap();
    let rel_z = |w: &World| w.bodies()[cube].position().z - w.bodies()[left].position().z;
    run_ok(&mut w, 1000);
    // Closed: the fingers touch the cube and squeeze it.
    // (A fingertip's gap to the cube was 0.1 − 0.02 − 0.05 = 0.03 m.)
    let closed = w.joints()[jl.0].displacement(w.bodies());
    assert!((closed - 0.03).abs() < 1e-3, "left finger moved {closed} m");
    let grip = rel_z(&w);
    for s in 0..2200 {
        let speed = 0.1 * (s as f64 / 200.0).min(1.0).min((2200 - s) as f64 / 200.0);
        w.set_motor(lift, speed, 200.0).unwrap();
        step_ok(&mut w);
    }
    w.set_motor(lift, 0.0, 200.0).unwrap();
    let held = rel_z(&w);
    run_ok(&mut w, 2000);
    let z = w.bodies()[cube].position().z;
    assert!((z - 0.25).abs() < 2e-3, "cube at {z}, lifted {}", z - 0.05);
    let (slip_lift, slip_hold) = ((held - grip).abs(), (rel_z(&w) - held).abs());
    eprintln!("gripper: cube lifted {:.6} m, slip {slip_lift:e} m lifting, {slip_hold:e} m holding", z - 0.05);
    assert!(slip_lift <= 1e-3 && slip_hold <= 1e-3, "slip {slip_lift:e} m lifting, {slip_hold:e} m holding");
    for j in 0..3 {
        assert!(w.joint_error(JointId(j)).unwrap().0 <= 1e-6);
    }
}

/// Steps `w` `k` times and returns the rate after each: `rate(w)`.
fn rates(w: &mut World, k: usize, rate: impl Fn(&World) -> f64) -> Vec<f64> {
    (0..k)
        .map(|_| {
            step_ok(w);
            rate(w)
        })
        .collect()
}

#[test]
fn a_damped_slider_decays_as_implicit_euler_at_any_damping() {
    // A 2 kg box on a horizontal slider (x) to the world, sent at 1 m/s:
    // m v̇ = −d v, each step of implicit Euler v ← v / (1 + h d / m).
    let (m, h) = (2.0, 1e-3);
    for d in [4.0, 2e4] {
        let mut w = world();
        let b = w.add_box(Vec3::splat(0.1), m, Vec3::new(0.0, 0.0, 1.0), 0.5).unwrap();
        w.set_velocity(b, Vec3::new(1.0, 0.0, 0.0)).unwrap();
        let j = w.add_joint(joint(JointKind::Slider, None, b.0, Vec3::new(0.0, 0.0, 1.0), Vec3::X)).unwrap();
        w.set_joint_damping(j, d).unwrap();
        let steps = if d < 1e3 { 1000 } else { 6 };
        let vs = rates(&mut w, steps, |w| w.bodies()[b.0].velocity().x);
        let factor = 1.0 / (1.0 + h * d / m);
        for (k, v) in vs.iter().enumerate() {
            let expect = factor.powi(k as i32 + 1);
            assert!(rel(*v, expect) < 1e-9, "d = {d}, step {k}: v = {v} vs {expect}");
        }
        if d < 1e3 {
            // Within the step of the continuous decay exp(−d t / m) (relative error ≈ t h (d/m)² / 2).
            let exact = (-d * 1.0 / m).exp();
            eprintln!("damped slider: v(1 s) = {} vs exp(−d t/m) = {exact}", vs[999]);
            assert!(rel(vs[999], exact) < 3e-3, "{} vs {exact}", vs[999]);
        }
        assert!(w.joint_error(j).unwrap().0 < 1e-9);
    }
}

#[test]
fn a_damped_hinge_slows_a_spinning_wheel_as_implicit_euler() {
    // A sphere (r = 0.1 m, 1 kg) hinged at its centre about y, spinning at
    // 3 rad/s: gravity has no moment, I ω̇ = −d ω with I = 2/5 m r².
    let (r, h, d) = (0.1, 1e-3, 0.008);
    let inertia = 0.4 * r * r;
    let mut w = world();
    let centre = Vec3::new(0.0, 0.0, 1.0);
    let b = w.add_sphere(r, 1.0, centre, 0.5).unwrap();
    w.set_angular_velocity(b, Vec3::new(0.0, 3.0, 0.0)).unwrap();
    let j = w.add_joint(joint(JointKind::Hinge, None, b.0, centre, Vec3::Y)).unwrap();
    w.set_joint_damping(j, d).unwrap();
    let ws = rates(&mut w, 500, |w| w.bodies()[b.0].angular_velocity().y);
    let factor = 1.0 / (1.0 + h * d / inertia);
    for (k, om) in ws.iter().enumerate() {
        let expect = 3.0 * factor.powi(k as i32 + 1);
        assert!(rel(*om, expect) < 1e-9, "step {k}: ω = {om} vs {expect}");
    }
    // The damper's torque is the joint's reaction about the axis: −d ω at the end of the step.
    let torque = w.last_record().joints[0].torque.y;
    assert!(rel(torque, -d * ws[499]) < 1e-9, "reaction {torque} vs {}", -d * ws[499]);
}

#[test]
fn damping_is_for_hinges_and_sliders_and_not_negative() {
    let mut w = world();
    let b = w.add_sphere(0.1, 1.0, Vec3::new(0.0, 0.0, 1.0), 0.5).unwrap().0;
    let ball = w.add_joint(joint(JointKind::Ball, None, b, Vec3::new(0.0, 0.0, 1.0), Vec3::Z)).unwrap();
    assert!(w.set_joint_damping(ball, 1.0).unwrap_err().to_string().contains("damping"));
    let c = w.add_sphere(0.1, 1.0, Vec3::new(1.0, 0.0, 1.0), 0.5).unwrap().0;
    let hinge = w.add_joint(joint(JointKind::Hinge, None, c, Vec3::new(1.0, 0.0, 1.0), Vec3::Y)).unwrap();
    assert!(w.set_joint_damping(hinge, -1.0).is_err());
    assert!(w.set_joint_damping(hinge, f64::NAN).is_err());
    assert!(w.set_joint_damping(hinge, 0.5).is_ok());
}
