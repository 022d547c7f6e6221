//! A heavy body resting or sliding on a light one (box–box
//! and sphere–box), and the energy audit of every step. Every contact LCP of
//! 2,000 steps is solved, box–box and sphere–box, resting and sliding, at
//! 1e6, 1e7 and 1e8 kg on 1 kg (`mass_ratio_failures`, ignored, prints the
//! figures, which the CI test below asserts). Box–box at 1e7 and 1e8 used to fail on many steps (resting: 100
//! and 944 of 2,000; sliding: 45 and 184; at 1e6 sliding 1, at 1e8
//! sphere–box sliding 1): the bases on Lemke's path mix the light box's
//! mobility with the heavy one's (1e-7–1e-8 of it), at cond 1e10–1e17, where
//! no `f64` rung of the ladder resolves ties and values. The ladder's
//! double-double rung (Lemke in ~106-bit arithmetic) solves them in
//! 40–160 pivots, a few milliseconds at n = 80. The failed-solve policy
//! (a failed step adds no energy) is tested with the ladder switched off.
//! At 1e7 and 1e8 box–box resting, `f64` answers within the acceptance rule
//! had the heavy box's weight up to 59 % off and the box rising at 1.8 cm/s
//! (energy +6.3e-5 of E₀): the body-space check now re-solves them in
//! double-double (`heavy_box_rests_with_its_weight`).

mod common;
use common::G;
use sim::lcp::{LemkeOptions, Method};
use sim::math::Vec3;
use sim::{World, WorldParams};

/// A 1 m box (or a sphere of radius 0.5 m) of `heavy` kg on a 0.1 m, 1 kg box
/// on the ground (μ = 0.5 everywhere), the heavy body moving at `slide` m/s along x.
fn heavy_on_light(heavy: f64, sphere: bool, slide: f64) -> World {
    heavy_on_light_with(WorldParams::default(), heavy, sphere, slide)
}

/// [`heavy_on_light`] with the world's parameters given.
fn heavy_on_light_with(params: WorldParams, heavy: f64, sphere: bool, slide: f64) -> World {
    let mut w = World::new(params).unwrap();
    w.add_ground(0.5).unwrap();
    w.add_box(Vec3::new(0.05, 0.05, 0.05), 1.0, Vec3::new(0.0, 0.0, 0.05), 0.5).unwrap();
    let top = if sphere {
        w.add_sphere(0.5, heavy, Vec3::new(0.0, 0.0, 0.6), 0.5).unwrap()
    } else {
        w.add_box(Vec3::new(0.5, 0.5, 0.5), heavy, Vec3::new(0.0, 0.0, 0.6), 0.5).unwrap()
    };
    w.set_velocity(top, Vec3::new(slide, 0.0, 0.0)).unwrap();
    w
}

/// What [`run`] saw: failed steps, the largest rise of E above its start ÷
/// |E₀|, the most energy one step created ÷ |E₀|, and the solved islands
/// whose applied answer is outside the body-space rule (`IslandRecord::body_eta`).
struct Outcome {
    failed: usize,
    rise: f64,
    created: f64,
    outside: usize,
    /// The largest body-space error `η_body` of an answer.
    worst: f64,
}

/// Runs `steps` steps.
fn run(w: &mut World, steps: usize) -> Outcome {
    let e0 = w.energy();
    let mut o = Outcome { failed: 0, rise: 0.0, created: 0.0, outside: 0, worst: 0.0 };
    for _ in 0..steps {
        let r = w.step().unwrap();
        o.failed += usize::from(!r.ok());
        o.outside += r.islands.iter().filter(|i| i.body_eta > sim::lcp::accept::DEFAULT_TOL).count();
        o.worst = r.islands.iter().fold(o.worst, |m, i| m.max(i.body_eta));
        let audit = r.energy;
        // The audit is the world's energy bookkeeping, step by step.
        assert!((audit.after - w.energy()).abs() <= 1e-12 * e0.abs());
        o.created = o.created.max(audit.created() / e0.abs());
        o.rise = o.rise.max((w.energy() - e0) / e0.abs());
    }
    o
}

/// The heavy-on-light cases: heavy mass (kg), a sphere (else a box) on the
/// light box, and its initial sliding speed (m/s).
fn cases() -> impl Iterator<Item = (f64, bool, f64)> {
    [1e6, 1e7, 1e8].into_iter().flat_map(|heavy| {
        [false, true]
            .into_iter()
            .flat_map(move |sphere| [0.0, 0.5].into_iter().map(move |slide| (heavy, sphere, slide)))
    })
}

#[test]
fn heavy_on_light_every_lcp_is_solved() {
    // Box–box and sphere–box, resting and sliding, at 1e6, 1e7 and 1e8 kg:
    // every LCP of 2,000 steps solved (12 s in release since the warm start's
    // exchanges serve islands of two bodies too; box–box at 1e7 and 1e8 ran
    // 500 steps before, to keep this test near 40 s). Before the componentwise
    // acceptance rule and failed-step policy: up to 175 failures at 1e6;
    // before the double-double rung, box–box 1e7 and 1e8 failed on 45–944
    // steps of 2,000.
    for (heavy, sphere, slide) in cases() {
        let mut w = heavy_on_light(heavy, sphere, slide);
        let Outcome { failed, rise, created, .. } = run(&mut w, 2000);
        assert_eq!(failed, 0, "{heavy:e} kg, sphere {sphere}, slide {slide}: {failed} failed LCPs");
        // Energy never grows beyond round-off. Measured over 2,000
        // steps: at most 3.6e-12 of E₀ (1e8 box–box resting). Before
        // the body-space check (`solve_chain::answer_check`) box–box
        // resting rose by 6.3e-5 of E₀ at 1e8 (4.1e-5 by step 200)
        // and 1.3e-10 at 1e7: solved steps whose answers, within the
        // acceptance rule's 1e-9 of rows scaled by the light box's
        // mobility times 1e8-kg impulses, left the boxes rising at mm/s.
        let bound = 1e-10;
        assert!(rise <= bound, "{heavy:e} kg, sphere {sphere}, slide {slide}: energy rose by {rise:e} of E₀");
        // Nor does one step create energy beyond round-off: at most
        // 1.3e-12 of E₀. With the warm start's exchanges kept from
        // islands of two bodies, 2.2e-8 at 1e7 box–box resting (where
        // 3 answers stayed outside the body-space rule, against 0
        // now). (The sphere sliding
        // on the light box is pushed out of a penetration of a few
        // µm: 6.8e-7 of E₀ in a step, the stabilization's
        // work, which the audit does not count as created; see
        // `stabilization_work_is_not_created_energy`.)
        assert!(created <= bound, "{heavy:e} kg, sphere {sphere}, slide {slide}: a step created {created:e} of E₀");
    }
}

#[test]
fn heavy_box_rests_with_its_weight() {
    // A 1e7 or 1e8 kg box resting on a 1 kg box: once settled, the contacts
    // under the heavy box carry its weight, Σ fn = m g h each step, and it
    // stays at rest. Before the body-space check: Σ fn off by up to 59 %
    // (1e8, step 178; 0.23 % at 1e7) and the heavy box moving at up to
    // 1.8 cm/s (1.4e-4 m/s at 1e7); after: 8.6e-7 and 5.7e-6 m/s (500 steps).
    // Every applied answer passes the body-space rule.
    for heavy in [1e7, 1e8] {
        let mut w = heavy_on_light(heavy, false, 0.0);
        for _ in 0..500 {
            let r = w.step().unwrap();
            let top: f64 = r
                .contacts
                .iter()
                .enumerate()
                .filter(|(_, c)| c.body_a == 2 || c.body_b == 2)
                .map(|(i, _)| r.z[i])
                .sum();
            let off = top / (heavy * G * r.dt) - 1.0;
            let step = r.step;
            assert!(step < 10 || off.abs() <= 1e-5, "{heavy:e} kg, step {step}: Σ fn off the weight by {off:e}");
            for isl in &r.islands {
                assert!(isl.body_eta <= 1e-9, "{heavy:e} kg, step {step}: body-space error {:e}", isl.body_eta);
            }
            let v = w.body(sim::BodyId(2)).unwrap().velocity().norm();
            assert!(v <= 1e-4, "{heavy:e} kg, step {step}: the heavy box moves at {v:e} m/s");
        }
    }
}

#[test]
fn failed_steps_add_no_energy_box_on_box() {
    // Before the failed-solve policy a failed step applied no impulse: the
    // heavy body sank into the light one and a later solve threw it up
    // (5.9 MJ → 14 MJ at 1e6; 1.2 GJ gained at 1e8 sphere–box). Now a failed
    // step never has more energy than the step with no contact impulse, which
    // loses ½ m h² g²: it creates none. The full ladder now solves every one
    // of these LCPs, so the failures come from Lemke's first rung alone
    // (`fallback: false`).
    let first_rung = LemkeOptions { fallback: false, ..Default::default() };
    let params = WorldParams { method: Method::Lemke(first_rung), ..WorldParams::default() };
    for heavy in [1e7, 1e8] {
        for sphere in [false] {
            let mut w = heavy_on_light_with(params.clone(), heavy, sphere, 0.0);
            let e0 = w.energy().abs();
            let mut failed = 0;
            // (Up to 2,000 steps until ten failed ones.)
            for _ in 0..2000 {
                let r = w.step().unwrap();
                if !r.ok() {
                    failed += 1;
                    let c = r.energy.created();
                    assert!(
                        c <= 1e-12 * e0,
                        "{heavy:e} kg, sphere {sphere}, step {}: a failed step created {c:e} J",
                        r.step
                    );
                }
                if failed == 10 {
                    break;
                }
            }
            assert!(failed > 0, "{heavy:e} kg box–box: no failed step left to test the policy on");
        }
    }
}

#[test]
fn stabilization_work_is_not_created_energy() {
    // A cube started 1 mm into the ground is pushed out by the penetration
    // correction (erp 0.2 of the depth per step): energy the contact adds
    // through the velocities, Baumgarte's known gain. The audit records it as
    // `stabilization` (Σ fn·erp·|φ|/h) and the step creates nothing beyond
    // round-off; before, these steps counted it as created. The same for the
    // 1e7 kg sphere sliding on a 1 kg box (up to 4.7 µm deep: 6.8e-7 of E₀
    // in a step).
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_ground(0.5).unwrap();
    let cube = w.add_box(Vec3::new(0.5, 0.5, 0.5), 1.0, Vec3::new(0.0, 0.0, 0.499), 0.5).unwrap();
    let mut pushed = 0.0;
    for _ in 0..200 {
        let r = w.step().unwrap();
        let e = r.energy;
        // S is Σ fn·erp·|φ|/h over the penetrating contacts, from the record.
        let h = r.dt;
        let s: f64 = (r.contacts.iter().zip(r.normal_impulses()))
            .filter(|(c, _)| c.gap < -1e-12)
            .map(|(c, f)| f * 0.2 * -c.gap / h)
            .sum();
        assert!((e.stabilization - s).abs() <= 1e-12 * s, "step {}: S {:e} J vs {s:e} J", r.step, e.stabilization);
        assert!(e.created() <= 1e-12 * G, "step {}: created {:e} J (S {:e} J)", r.step, e.created(), e.stabilization);
        pushed += e.stabilization;
    }
    // The cube came out of the ground, and what lifted it is S.
    let z = w.body(cube).unwrap().position().z;
    assert!((z - 0.5).abs() <= 1e-9, "the cube rests at z = {z}");
    assert!(pushed >= G * 1e-3 * 0.99, "stabilization work {pushed:e} J for a 1 mm rise of a 1 kg cube");
    let mut sphere = heavy_on_light(1e7, true, 0.5);
    let e0 = sphere.energy().abs();
    let (mut most, mut created) = (0.0f64, 0.0f64);
    for _ in 0..200 {
        let e = sphere.step().unwrap().energy;
        most = most.max(e.stabilization / e0);
        created = created.max(e.created() / e0);
    }
    assert!(most > 1e-7, "the sphere met no penetration ({most:e} of E₀)");
    assert!(created <= 1e-12, "a step created {created:e} of E₀");
}

#[test]
fn energy_never_grows_resting_and_sliding() {
    // A cube resting, a cube sliding to rest on the ground, a cube sliding down a 40° slope.
    let p = WorldParams::default;
    let mut rest = sim::scenes::BoxStack::new(1).build(p()).unwrap().world;
    let mut slide = sim::scenes::BoxStack::new(1).build(p()).unwrap().world;
    slide.set_velocity(sim::BodyId(1), Vec3::new(1.0, 0.0, 0.0)).unwrap();
    let mut slope = sim::scenes::CubeOnSlope::new(40.0, 0.5).build(p()).unwrap().world;
    for (name, w) in [("resting", &mut rest), ("sliding", &mut slide), ("slope", &mut slope)] {
        let scale = w.energy().abs().max(G);
        for _ in 0..2000 {
            let r = w.step().unwrap().clone();
            assert!(r.ok(), "{name}");
            assert!(r.energy.created() <= 1e-12 * scale, "{name} step {}: created {:e} J", r.step, r.energy.created());
        }
    }
}

#[test]
#[ignore]
fn mass_ratio_failures() {
    // cargo test --release -p lcpsim-sim --test mass_ratio -- --ignored --nocapture
    for (heavy, sphere, slide) in cases() {
        let mut w = heavy_on_light(heavy, sphere, slide);
        let Outcome { failed, rise, created, outside, worst } = run(&mut w, 2000);
        println!(
            "{heavy:e} kg sphere {sphere} slide {slide}: failed {failed}/2000, rise {rise:e}·E₀, \
             max created {created:e}·E₀, outside the body-space rule {outside} (largest η_body {worst:.2e})"
        );
    }
}

/// Writes `.lcpsparse` file `path` (layout: `crates/lcp/tests/common/sparse.rs`).
fn write_lcpsparse(path: &str, m: &[f64], q: &[f64], basis: &[bool]) {
    let n = q.len();
    let nz: Vec<usize> = (0..n * n).filter(|&k| m[k] != 0.0).collect();
    let mut b = b"LCPSPARSE1".to_vec();
    b.extend((n as u64).to_le_bytes());
    b.extend((nz.len() as u64).to_le_bytes());
    nz.iter().for_each(|&k| b.extend((k as u32).to_le_bytes()));
    nz.iter().for_each(|&k| b.extend(m[k].to_le_bytes()));
    q.iter().for_each(|v| b.extend(v.to_le_bytes()));
    b.extend(basis.iter().map(|&v| v as u8));
    std::fs::write(path, b).unwrap();
}

#[test]
#[ignore]
fn dump_failing_lcps() {
    // How tests/data/repros/heavy1e6_slide_step1876.lcpsparse was made (before
    // the double-double rung; MAX=4 HEAVY=1e6 SLIDE=0.5):
    // HEAVY=1e7 SPHERE=0 SLIDE=0 DUMP=/tmp/dir cargo test --release -p lcpsim-sim
    //   --test mass_ratio dump_failing_lcps -- --ignored --nocapture
    // Each failing LCP is written as DUMP/step{N}.lcpsparse with the previous
    // LCP's support (z > w) as its basis when the sizes agree.
    let env = |k: &str, d: &str| std::env::var(k).unwrap_or_else(|_| d.to_string());
    let heavy: f64 = env("HEAVY", "1e7").parse().unwrap();
    let sphere = env("SPHERE", "0") == "1";
    let slide: f64 = env("SLIDE", "0").parse().unwrap();
    let (dir, max): (String, usize) = (env("DUMP", "/tmp/heavy_dumps"), env("MAX", "5").parse().unwrap());
    std::fs::create_dir_all(&dir).unwrap();
    let mut w = heavy_on_light(heavy, sphere, slide);
    let prev = std::sync::Arc::new(std::sync::Mutex::new((Vec::<bool>::new(), 0usize)));
    let p2 = prev.clone();
    let dir2 = dir.clone();
    w.set_sink(Box::new(move |c: &sim::CapturedLcp<'_>| {
        let mut g = p2.lock().unwrap();
        let p = sim::lcp::Lcp::new(c.m.to_vec(), c.q.to_vec()).unwrap();
        let ok = c.status == sim::lcp::Status::Solved && sim::lcp::accept::accepts(&p, c.z, c.w, 1e-9);
        if !ok && g.1 < max {
            let basis = if g.0.len() == c.n() { g.0.clone() } else { vec![false; c.n()] };
            write_lcpsparse(&format!("{dir2}/step{}.lcpsparse", c.step), c.m, c.q, &basis);
            println!("step {} n {} status {:?} pivots {}", c.step, c.n(), c.status, c.pivots);
            g.1 += 1;
        }
        g.0 = c.z.iter().zip(c.w).map(|(z, w)| z > w).collect();
    }));
    println!("{} failed", run(&mut w, 2000).failed);
}
