//! The assembled LCP against the Stewart–Trinkle formulation: layout, A = J M_b⁻¹ Jᵀ, the scaled
//! problem D M D, D q with D = diag(I, I, s·I), physical λ, LCP capture and
//! what a failed solve does to a step.

mod common;
use common::*;
use sim::lcp::{self, Lcp, Solution, Status};
use sim::math::{Quat, Vec3};
use sim::scenes::{BoxStack, CubeOnSlope};
use sim::{BodyDesc, ConeScale, LcpBuffer, World, WorldParams};

/// A tumbling cube touching a slope with one edge, plus a second cube on it:
/// contacts with one and with two dynamic bodies, all rows non-trivial.
fn messy_world(params: WorldParams) -> World {
    let mut w = World::new(params).unwrap();
    w.add_plane(sim::Plane::slope_deg(20.0, sim::Downhill::PlusX).unwrap(), 0.8).unwrap();
    let q = Quat::from_axis_angle(Vec3::new(0.3, 1.0, 0.1), 0.4);
    let lower = w
        .add_body(
            BodyDesc::cuboid(Vec3::new(0.5, 0.4, 0.3))
                .mass(2.0)
                .orientation(q)
                .position(Vec3::new(0.0, 0.0, 0.9))
                .velocity(Vec3::new(0.3, -0.2, -0.5))
                .angular_velocity(Vec3::new(0.5, 1.0, -0.3))
                .mu(0.6),
        )
        .unwrap();
    // Lower it until its lowest corner touches the slope.
    let plane = sim::Plane::slope_deg(20.0, sim::Downhill::PlusX).unwrap();
    let b = w.body(lower).unwrap().clone();
    let lowest = sim::geometry::BoxShape::new(Vec3::new(0.5, 0.4, 0.3))
        .unwrap()
        .corners()
        .iter()
        .map(|&c| plane.distance(b.point_to_world(c)))
        .fold(f64::INFINITY, f64::min);
    w.set_position(lower, b.position() - plane.normal() * lowest).unwrap();
    // A ball resting on the box's top face region (contact between two dynamic bodies).
    let top = w.body(lower).unwrap().point_to_world(Vec3::new(0.0, 0.0, 0.3));
    let up = w.body(lower).unwrap().orientation().rotate(Vec3::Z);
    w.add_sphere(0.2, 0.5, top + up * 0.2, 0.4).unwrap();
    w
}

/// Builds the LCP of the current state of `w` without stepping.
fn assemble(w: &mut World) -> Lcp {
    w.forces_stage().unwrap();
    w.detect();
    w.assemble();
    w.contact_lcp().to_lcp().unwrap()
}

#[test]
fn layout_is_fn_fd_lambda_with_size_k_plus_2_per_contact() {
    for k in [2usize, 4, 8, 16] {
        let mut s = CubeOnSlope::new(0.0, 0.5).build(WorldParams { friction_dirs: k, ..Default::default() }).unwrap();
        let lcp = assemble(&mut s.world);
        let nc = 4;
        assert_eq!(lcp.n(), nc * (k + 2));
        let c = s.world.contact_lcp();
        assert_eq!(c.layout().fd_index(1, 0), nc + k);
        assert_eq!(c.layout().lambda_index(0), nc * (k + 1));
        // Cone rows: [μ, −1…−1, 0] pattern; friction rows: +1 in their λ column.
        for i in 0..nc {
            let l = c.layout().lambda_index(i);
            assert_eq!(lcp.at(l, i), 0.5);
            for j in 0..k {
                assert_eq!(lcp.at(l, c.layout().fd_index(i, j)), -1.0);
                assert_eq!(lcp.at(c.layout().fd_index(i, j), l), 1.0);
            }
            assert_eq!(lcp.q()[l], 0.0);
        }
    }
}

#[test]
fn a_block_equals_j_minv_jt_computed_densely() {
    let mut w = messy_world(WorldParams::default());
    let lcp = assemble(&mut w);
    let contacts = w.contacts().to_vec();
    assert!(contacts.iter().any(|c| !w.bodies()[c.body_b].is_static()), "need a contact between two dynamic bodies");
    let nc = contacts.len();
    let k = 8;
    let nb = w.body_count();
    // Dense J (rows [normals; friction], 6·nb columns) from the contacts alone.
    let basis = sim::contact::FrictionBasis::new(k);
    let mut jrows: Vec<Vec<f64>> = vec![vec![0.0; 6 * nb]; nc * (k + 1)];
    for (i, c) in contacts.iter().enumerate() {
        let dirs: Vec<Vec3> =
            std::iter::once(c.normal).chain((0..k).map(|j| basis.direction(c.normal, c.tangent, j))).collect();
        for (r, d) in dirs.iter().enumerate() {
            let row = if r == 0 { i } else { nc + i * k + r - 1 };
            for (body, sign) in [(c.body_a, 1.0), (c.body_b, -1.0)] {
                let b = &w.bodies()[body];
                if b.is_static() {
                    continue;
                }
                let arm = c.point - b.position();
                let ang = arm.cross(*d);
                for (m, v) in d.to_array().iter().chain(ang.to_array().iter()).enumerate() {
                    jrows[row][6 * body + m] += sign * v;
                }
            }
        }
    }
    // Dense M_b⁻¹.
    let minv = |body: usize, x: &[f64]| -> [f64; 6] {
        let b = &w.bodies()[body];
        if b.is_static() {
            return [0.0; 6];
        }
        let lin = Vec3::new(x[0], x[1], x[2]) * b.inv_mass();
        let ang = b.inv_inertia_world() * Vec3::new(x[3], x[4], x[5]);
        [lin.x, lin.y, lin.z, ang.x, ang.y, ang.z]
    };
    let na = nc * (k + 1);
    let mut worst: f64 = 0.0;
    for i in 0..na {
        for j in 0..na {
            let mut a = 0.0;
            for body in 0..nb {
                let wj = minv(body, &jrows[j][6 * body..6 * body + 6]);
                a += (0..6).map(|m| jrows[i][6 * body + m] * wj[m]).sum::<f64>();
            }
            worst = worst.max((a - lcp.at(i, j)).abs());
        }
    }
    assert!(worst < 1e-12, "max |A − J M⁻¹ Jᵀ| = {worst:e}");
    // b1 = J_d v*, and b0 = J_n v* + stabilization.
    let (vf, wf) = w.free_velocities();
    let vstar: Vec<f64> = (0..nb).flat_map(|b| vf[b].to_array().into_iter().chain(wf[b].to_array())).collect();
    let params = w.params().clone();
    for (row, jr) in jrows.iter().enumerate() {
        let jv: f64 = jr.iter().zip(&vstar).map(|(a, b)| a * b).sum();
        let bias = if row < nc { params.stabilization.bias(contacts[row].gap, params.dt) } else { 0.0 };
        assert!((lcp.q()[row] - jv - bias).abs() < 1e-12, "q[{row}]");
    }
}

#[test]
fn scaled_assembly_is_d_m_d_of_the_unscaled_one() {
    for s in [1e-3, 1e-6, 0.37, 20.0] {
        let mut w1 = messy_world(WorldParams::default());
        let mut ws = messy_world(WorldParams { cone_scale: ConeScale::Value(s), ..Default::default() });
        let (l1, ls) = (assemble(&mut w1), assemble(&mut ws));
        let n = l1.n();
        let nc = w1.contacts().len();
        let d = |i: usize| if i >= nc * 9 { s } else { 1.0 };
        for i in 0..n {
            assert_eq!(ls.q()[i], d(i) * l1.q()[i]);
            for j in 0..n {
                let expect = d(i) * l1.at(i, j) * d(j);
                assert!((ls.at(i, j) - expect).abs() <= 1e-15 * expect.abs(), "({i},{j}): {} vs {expect}", ls.at(i, j));
            }
        }
    }
    // ConeScale::TimeStep is s = h.
    let mut wt = messy_world(WorldParams { cone_scale: ConeScale::TimeStep, dt: 2e-3, ..Default::default() });
    assemble(&mut wt);
    assert_eq!(wt.contact_lcp().scale(), 2e-3);
}

#[test]
fn physical_impulses_do_not_depend_on_the_scale_and_lambda_is_the_sliding_speed() {
    let run = |scale: ConeScale| {
        let mut sc = CubeOnSlope::new(0.0, 0.5);
        sc.speed = 2.0;
        let mut s = sc.build(WorldParams { cone_scale: scale, ..Default::default() }).unwrap();
        step_ok(&mut s.world)
    };
    let r1 = run(ConeScale::Unscaled);
    for scale in [ConeScale::TimeStep, ConeScale::Value(1e-6)] {
        let rs = run(scale);
        for (a, b) in r1.z.iter().zip(&rs.z) {
            assert!((a - b).abs() < 1e-12, "{:?} vs {:?}", r1.z, rs.z);
        }
        assert!(rs.residuals.residual < 1e-12, "physical residual {:e}", rs.residuals.residual);
    }
    // Sliding at ≈ 2 m/s (minus one step of deceleration): λ is that speed at every loaded contact.
    let v = 2.0 - 0.5 * G * 1e-3;
    for (i, &l) in r1.lambdas().iter().enumerate() {
        if r1.z[i] > 0.0 {
            assert!((l - v).abs() < 1e-9, "λ {l} vs {v}");
        }
    }
    // Pattern (+, +, +): sliding.
    assert!(r1.pattern(1, 1e-12).iter().all(|&b| b));
}

#[test]
fn every_solved_lcp_reaches_the_sink() {
    let mut s = CubeOnSlope::new(30.0, 0.3)
        .build(WorldParams { cone_scale: ConeScale::TimeStep, ..Default::default() })
        .unwrap();
    let buf = LcpBuffer::new();
    s.world.set_sink(Box::new(buf.clone()));
    let mut records = Vec::new();
    for _ in 0..5 {
        records.push(step_ok(&mut s.world));
    }
    let caps = buf.drain();
    assert_eq!(caps.len(), 5);
    for (c, r) in caps.iter().zip(&records) {
        assert_eq!((c.step, c.contacts, c.friction_dirs, c.q.len(), c.m.len()), (r.step, 4, 8, 40, 1600));
        assert_eq!(c.time, r.time);
        assert_eq!(c.scale, 1e-3);
        assert_eq!(c.status, Status::Solved);
        assert_eq!(c.method, "lemke");
        // The sink holds the scaled problem: λ_scaled = λ / s.
        let lcp = Lcp::new(c.m.clone(), c.q.clone()).unwrap();
        let w = lcp.w_of(&c.z);
        assert!(w.iter().zip(&c.w).all(|(a, b)| (a - b).abs() < 1e-12));
        for i in 0..4 {
            assert!((c.z[36 + i] * 1e-3 - r.lambdas()[i]).abs() < 1e-12);
        }
    }
    // No contacts, nothing captured; taking the sink back stops the capture.
    let mut free = World::new(WorldParams::default()).unwrap();
    free.add_sphere(0.1, 1.0, Vec3::new(0.0, 0.0, 5.0), 0.5).unwrap();
    let b2 = LcpBuffer::new();
    free.set_sink(Box::new(b2.clone()));
    let r = free.step().unwrap();
    assert_eq!((r.status, r.lcp_size), (None, 0));
    assert!(b2.is_empty());
    assert!(s.world.take_sink().is_some());
    step_ok(&mut s.world);
    assert!(buf.is_empty());
    // A closure is a sink too.
    let mut count = 0usize;
    let counter = std::sync::Arc::new(std::sync::atomic::AtomicUsize::new(0));
    let c2 = counter.clone();
    s.world.set_sink(Box::new(move |l: &sim::CapturedLcp<'_>| {
        c2.fetch_add(l.n(), std::sync::atomic::Ordering::Relaxed);
    }));
    step_ok(&mut s.world);
    count += counter.load(std::sync::atomic::Ordering::Relaxed);
    assert_eq!(count, 40);
}

#[test]
fn a_failed_solve_is_recorded_and_the_step_goes_on() {
    let mut s = BoxStack::new(1).build(WorldParams::default()).unwrap();
    // A solver that gives up with NaNs: no impulse, the box falls freely this step.
    let mut nan = |l: &Lcp| Solution {
        z: vec![f64::NAN; l.n()],
        w: vec![f64::NAN; l.n()],
        status: Status::Numerical,
        pivots: 3,
        residuals: Default::default(),
        basis: None,
        accepted: false,
    };
    let r = s.world.step_with(&mut nan).unwrap().clone();
    assert_eq!(r.status, Some(Status::Numerical));
    assert_eq!(r.pivots, 3);
    assert!(r.zeroed);
    assert!(r.z.iter().all(|&v| v == 0.0));
    assert!((s.world.body(s.body).unwrap().velocity().z + G * 1e-3).abs() < 1e-15);
    // A finite but failed answer is recorded, not applied.
    let mut partial = |l: &Lcp| {
        let mut z = vec![0.0; l.n()];
        z[0] = 0.004;
        z[1] = -1.0;
        Solution::from_z(l, z, Status::MaxPivots, 7)
    };
    let r = s.world.step_with(&mut partial).unwrap().clone();
    assert_eq!(r.status, Some(Status::MaxPivots));
    assert!(r.zeroed);
    assert_eq!(r.z[1], -1.0, "the record keeps the solver's answer");
    // Not the answer itself but its admissible part (fn ≥ 0), scaled
    // so that the step adds no energy: it slows the fall, never reverses it.
    let vz = s.world.body(s.body).unwrap().velocity().z;
    assert!(vz > -2.0 * G * 1e-3 && vz < 0.0, "vz = {vz:e}");
    assert!(r.energy.created() <= 1e-15, "created {:e} J", r.energy.created());
    // Then the default solver recovers: ERP pushes the box back up and it settles.
    for _ in 0..3000 {
        s.world.step().unwrap();
    }
    let b = s.world.body(s.body).unwrap();
    assert!((b.position().z - 0.5).abs() < 1e-6, "z = {}", b.position().z);
    // A wrong-length z is unusable too.
    let mut short = |_: &Lcp| Solution {
        z: vec![0.0; 1],
        w: vec![0.0; 1],
        status: Status::Solved,
        pivots: 0,
        residuals: Default::default(),
        basis: None,
        accepted: false,
    };
    assert!(s.world.step_with(&mut short).unwrap().zeroed);
    let _ = lcp::Method::default();
}
