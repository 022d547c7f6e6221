//! Broad phases on the same moving random boxes: parry's BVH (rebuilt, or
//! updated in place and refitted as Rapier does each step) against the plain
//! sweep-and-prune of [`crate::sap`]. Every method must report the same pairs
//! (checked each step; against brute force too up to 3,000 boxes).
//!
//! Boxes: n cubes-ish of half extents in [0.25, 0.75] m with centres uniform
//! in a cube of side (8 n)^(1/3) m (about one box per 8 m³, a few overlaps
//! per box), each moving at a random velocity of up to 1 m/s; a step is
//! 1/60 s. Seeded (SplitMix64), so every run sees the same boxes.

use crate::sap::{brute_force, Aabb3, SweepAndPrune};
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Vector;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};
use serde_json::json;
use std::time::Instant;

struct Rng(u64);

impl Rng {
    /// Uniform in [0, 1) (SplitMix64).
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

struct Boxes {
    centre: Vec<[f64; 3]>,
    half: Vec<[f64; 3]>,
    velocity: Vec<[f64; 3]>,
}

const DT: f64 = 1.0 / 60.0;

impl Boxes {
    fn random(n: usize, seed: u64) -> Self {
        let mut rng = Rng(seed);
        let side = (8.0 * n as f64).cbrt();
        let mut b = Boxes { centre: vec![], half: vec![], velocity: vec![] };
        for _ in 0..n {
            b.centre.push([0, 1, 2].map(|_| rng.range(0.0, side)));
            b.half.push([0, 1, 2].map(|_| rng.range(0.25, 0.75)));
            b.velocity.push([0, 1, 2].map(|_| rng.range(-1.0, 1.0) / 3f64.sqrt()));
        }
        b
    }
    fn advance(&mut self) {
        for (c, v) in self.centre.iter_mut().zip(&self.velocity) {
            for k in 0..3 {
                c[k] += v[k] * DT;
            }
        }
    }
    fn aabbs(&self) -> Vec<Aabb3> {
        self.centre
            .iter()
            .zip(&self.half)
            .map(|(c, h)| Aabb3 { min: [0, 1, 2].map(|k| c[k] - h[k]), max: [0, 1, 2].map(|k| c[k] + h[k]) })
            .collect()
    }
}

fn parry_aabb(b: &Aabb3) -> Aabb {
    Aabb::new(Vector::new(b.min[0], b.min[1], b.min[2]), Vector::new(b.max[0], b.max[1], b.max[2]))
}

/// The BVH's overlapping leaf pairs, all of them (no change detection), as (i < j).
fn bvh_pairs(bvh: &Bvh, ws: &mut BvhWorkspace, pairs: &mut Vec<(u32, u32)>) {
    pairs.clear();
    bvh.traverse_bvtt_single_tree::<false>(ws, &mut |a, b| pairs.push((a.min(b), a.max(b))));
}

#[derive(Default, Clone)]
struct Timing {
    seconds: Vec<f64>,
    pairs: Vec<usize>,
}

impl Timing {
    fn median_ms(&self) -> f64 {
        let mut s = self.seconds.clone();
        s.sort_by(f64::total_cmp);
        1e3 * s[s.len() / 2]
    }
}

const METHODS: [&str; 3] = ["sap", "bvh_rebuild", "bvh_refit"];

/// Times one size; returns the timings of each method in [`METHODS`]' order.
fn measure(n: usize, steps: usize) -> Result<Vec<Timing>, String> {
    let mut boxes = Boxes::random(n, 0x5EED + n as u64);
    let mut sap = SweepAndPrune::default();
    let first = boxes.aabbs();
    let mut refit = Bvh::from_leaves(BvhBuildStrategy::Binned, &first.iter().map(parry_aabb).collect::<Vec<_>>());
    let mut ws = BvhWorkspace::default();
    let mut out = vec![Timing::default(); METHODS.len()];
    let mut found: [Vec<(u32, u32)>; 3] = Default::default();
    // Step 0 warms up (the SAP's first full sort, the BVH's first build); not timed.
    for step in 0..=steps {
        boxes.advance();
        let aabbs = boxes.aabbs();
        let t = Instant::now();
        sap.update(&aabbs, &mut found[0]);
        let t_sap = t.elapsed().as_secs_f64();

        let t = Instant::now();
        let leaves: Vec<Aabb> = aabbs.iter().map(parry_aabb).collect();
        let rebuilt = Bvh::from_leaves(BvhBuildStrategy::Binned, &leaves);
        bvh_pairs(&rebuilt, &mut ws, &mut found[1]);
        let t_rebuild = t.elapsed().as_secs_f64();

        let t = Instant::now();
        for (i, b) in aabbs.iter().enumerate() {
            refit.insert_or_update_partially(parry_aabb(b), i as u32, 0.0);
        }
        refit.refit(&mut ws);
        bvh_pairs(&refit, &mut ws, &mut found[2]);
        let t_refit = t.elapsed().as_secs_f64();

        for f in found.iter_mut() {
            f.sort_unstable();
        }
        if found[1] != found[0] || found[2] != found[0] {
            return Err(format!("n = {n}, step {step}: the methods disagree on the pairs"));
        }
        if n <= 3000 && step == steps && brute_force(&aabbs) != found[0] {
            return Err(format!("n = {n}: sweep-and-prune disagrees with brute force"));
        }
        if step > 0 {
            for (m, t) in [t_sap, t_rebuild, t_refit].into_iter().enumerate() {
                out[m].seconds.push(t);
                out[m].pairs.push(found[m].len());
            }
        }
    }
    Ok(out)
}

/// Runs every size and prints a markdown table (or one JSON object).
pub fn run(sizes: &[usize], steps: usize, json_out: bool) -> Result<(), String> {
    let mut rows = Vec::new();
    for &n in sizes {
        let t = measure(n, steps.max(1))?;
        rows.push((n, t));
    }
    if json_out {
        let v: Vec<_> = rows
            .iter()
            .map(|(n, t)| {
                let m: serde_json::Map<String, serde_json::Value> = METHODS
                    .iter()
                    .zip(t)
                    .map(|(name, t)| (name.to_string(), json!({"ms_median": t.median_ms(), "pairs": t.pairs})))
                    .collect();
                json!({"n": n, "steps": steps, "methods": m})
            })
            .collect();
        println!("{}", json!({"parry3d_f64": "0.31", "dt": DT, "sizes": v}));
        return Ok(());
    }
    println!("| boxes | pairs per step | SAP (ms/update) | BVH rebuilt (ms) | BVH refitted (ms) |");
    println!("|---|---|---|---|---|");
    for (n, t) in &rows {
        let p = &t[0].pairs;
        println!(
            "| {n} | {}–{} | {:.3} | {:.3} | {:.3} |",
            p.iter().min().unwrap_or(&0),
            p.iter().max().unwrap_or(&0),
            t[0].median_ms(),
            t[1].median_ms(),
            t[2].median_ms()
        );
    }
    Ok(())
}
