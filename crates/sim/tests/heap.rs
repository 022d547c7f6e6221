//! The seeded cube heap.

use sim::scenes::CubeHeap;
use sim::WorldParams;

#[test]
fn cube_heap_starts_apart_inside_its_walls() {
    for (n, seed, walls) in [(1, 0, false), (14, 3, true), (55, 1, true), (100, 2, false)] {
        let mut s = CubeHeap { walls, ..CubeHeap::new(n, seed) }.build(WorldParams::default()).unwrap();
        assert_eq!(s.bodies.len(), n);
        let statics = s.world.bodies().iter().filter(|b| b.is_static()).count();
        assert_eq!(statics, 1 + 4 * usize::from(walls), "ground (+ four walls)");
        // Nothing touches at the start: the cubes fall into place.
        s.world.forces_stage().unwrap();
        s.world.detect();
        assert!(s.world.contacts().iter().all(|c| c.gap > 0.0), "n {n}: {:?}", s.world.contacts().first());
        // The same seed builds the same heap; another seed another one.
        let again = CubeHeap { walls, ..CubeHeap::new(n, seed) }.build(WorldParams::default()).unwrap();
        assert_eq!(again.world.bodies(), s.world.bodies());
        let other = CubeHeap { walls, ..CubeHeap::new(n, seed + 1) }.build(WorldParams::default()).unwrap();
        assert_ne!(other.world.bodies(), s.world.bodies());
    }
    assert!(CubeHeap { spacing: 1.0, ..CubeHeap::new(5, 0) }.build(WorldParams::default()).is_err());
    assert!(CubeHeap::new(0, 0).build(WorldParams::default()).is_err());
}

/// Too slow for the suite: islands of n = 1,500–4,000 once the heap forms, each
/// step a cold or warm Lemke of up to n pivots (not measured since islands of
/// n ≥ 1,500 go to the structured Lemke; with dense Lemke, measured in
/// release on `many_bodies heap:14` (14 cubes, n up to 1,160), 4 of 661 island
/// LCPs ended `ray_termination` / `numerical` in 300 steps (steps 280–298)).
/// Passes at 1973259: 300 steps in 121.5 s (shared machine), 485,575 pivots,
/// largest LCP n = 5,000, slowest step 240 (21.6 s), penetration 5.4e-4 m.
/// Run with `cargo test --release -p lcpsim-sim --test heap -- --ignored`.
#[test]
#[ignore]
fn heap_of_fifty_cubes_settles_without_failures_or_penetration() {
    let s = heap_runs_without_failures_or_penetration(50, 300, WorldParams::default());
    assert_eq!(s.world.last_record().islands.len(), 1, "one heap, one island");
}

/// Runs the walled heap of `n` cubes (seed 0) for `steps` steps: every island
/// solved on every step, penetration ≤ 1 mm. Prints the run's figures.
fn heap_runs_without_failures_or_penetration(n: usize, steps: usize, params: WorldParams) -> sim::scenes::Scene {
    let mut s = CubeHeap { walls: true, ..CubeHeap::new(n, 0) }.build(params).unwrap();
    let mut retaken = 0;
    let mut penetration = 0.0f64;
    let (t0, mut pivots, mut slowest, mut largest) = (std::time::Instant::now(), 0, (0.0f64, 0), 0);
    for _ in 0..steps {
        let ts = std::time::Instant::now();
        let r = s.world.step().unwrap();
        for t in &r.retakes {
            let failed: Vec<_> = t.unsolved().map(|i| (i.lcp_size, i.status, i.pivots)).collect();
            eprintln!(
                "step {} retaken in halves: part at t = {:.4} s, h = {:.2e} s, failed {failed:?}",
                r.step, t.time, t.h
            );
        }
        assert!(r.ok(), "step {}: {:?}", r.step, r.islands.iter().map(|i| (i.lcp_size, i.status)).collect::<Vec<_>>());
        penetration = r.contacts.iter().fold(penetration, |p, c| p.max(-c.gap));
        pivots += r.pivots;
        retaken += usize::from(r.parts > 1);
        let (secs, n) = (ts.elapsed().as_secs_f64(), r.islands.iter().map(|i| i.lcp_size).max().unwrap_or(0));
        if secs > 1.0 {
            // Progress of the slow steps (a forming heap's take seconds to minutes each).
            eprintln!("step {} (n = {n}): {} pivots, {} parts, {secs:.1} s", r.step, r.pivots, r.parts);
        }
        if secs > slowest.0 {
            slowest = (secs, r.step);
        }
        largest = largest.max(n);
    }
    eprintln!(
        "heap of {n} cubes, {steps} steps: {:.1} s, {pivots} pivots, largest LCP {largest}, slowest step {} ({:.1} s), \
         max penetration {penetration:.2e} m, {retaken} steps retaken in parts",
        t0.elapsed().as_secs_f64(),
        slowest.1,
        slowest.0
    );
    assert!(penetration <= 1e-3, "penetration {penetration} m");
    s
}

/// A 200-cube heap runs 200 steps with no failed step and
/// penetration ≤ 1 mm, a step whose LCP fails taken again in halves up to
/// three halvings deep (`WorldParams::max_halvings`; every part's LCP solved
/// exactly). Too slow for the suite (~11 min). Passes at 1d556a4: 200
/// steps in 653 s, 1,312,633 pivots, largest LCP n = 15,340, penetration
/// 6.1e-4 m, no step retaken; the slowest, step 199, 145 s. At b125512,
/// before a warm run's ray went on from where it stopped: 914 s, 1,500,472
/// pivots, step 198 retaken. At e545440, before the polish's false ray was
/// mended: 1,814 s, 2,777,670 pivots, steps 183, 194, 196 and 198 retaken,
/// and with two halvings step 183 stayed failed (docs/reliability.md,
/// "Retaking a failed step in halves", "A false ray in the polish" and "A
/// warm run's ray"). The history below is of the LCPs themselves, at `h`:
/// the cubes
/// land at steps 140–200 and the heap is one island of n = 4,000–13,000 whose
/// contacts change every step. Measured in release on the loaded 2-core
/// machine (`many_bodies heap:200 200 1`, one run each; the runs part ways
/// after step ~145, every LCP having many answers):
/// - before friction for loaded contacts only (main at 66be6d9): steps
///   170–179 took 958–25,934 pivots each, 94,450 pivots and 460 s in all
///   (step 175, n = 9,900: 25,934 pivots, 176 s); in an earlier run step
///   180 (n = 12,580) ended `numerical` after 55,656 pivots;
/// - with it (sub-LCPs of ~55–65 % of n: about half the contacts carry no
///   load), the repaired singular warm bases and the lexicographic rule on
///   `B⁻¹B₀` (16d6ab1): steps 170–179 take 470–16,105 pivots each, 51,979
///   pivots and 209 s in all; steps 180–184 (n = 12,610–13,380) solved in
///   21,907–86,846 pivots (101–494 s, a build beside it); step 185
///   (n = 13,460) ended `numerical` after 94,900 pivots; steps 186–195
///   5,085–37,443 pivots (3–37 s) except steps 192 and 195 (n = 13,460,
///   13,810): `ray_termination` and `numerical` after ~100,000 pivots
///   (~195 s). Such steps are slow because
///   most runs fail before one succeeds: warm and cold runs end on rays,
///   cycles or answers a hair outside the acceptance rule (natural residual
///   ~5e-9) and are restarted; in a run without the warm-basis repair, step
///   181 (n = 13,060) failed so on the sub-LCP (n = 8,434, 47,380 pivots)
///   and on the full LCP after it.
/// - at d626ab3 (`heap_replay record 200 200 DIR`, which also saves each
///   large island's LCP for `heap_replay solve`): steps 140–178 take at most
///   5,396 pivots and 12 s each (30 s for steps 0–171), step 179 (n = 12,130)
///   12,073 pivots (68 s), step 180 (n = 12,610) 75,323 (397 s), step 181
///   (n = 13,090) 134,331 (1,217 s; the run was stopped there).
/// - with a second start from a basis guessed by body-space projected
///   Gauss–Seidel (`lcp::structured::guess`) once the warm start has taken
///   max(2,000, n/2) pivots: on those saved LCPs, from the guess (300 sweeps,
///   0.1–0.8 s) steps 160–174 take 921–3,885 pivots where the warm basis
///   takes 73–3,885 (so the guess comes second), step 175 6,466 against
///   3,967, step 179 9,548 against 12,073, step 180 19,383 against 75,323.
///   The live run: steps 0–178 as before, step 179 15,614 pivots (49 s),
///   step 180 (n = 12,580: the runs part ways here) 62,347 (368 s), step
///   181 39,682 (350 s), step 182 49,962 (501 s), step 183 (n = 13,360)
///   `numerical` after 83,673 (835 s): still failing. The guess is a
///   vertex's (its normals and friction read out largest first, kept while
///   independent per contact pair) but misses more normal flags than the
///   previous basis (step 175: 195 of 990 against 127), and no guess so far
///   shortens the ordinary steps; it shortens the worst ones 1.3–4×.
/// - with the structured Lemke's ~3× cheaper pivots too (3fbe560, idle
///   machine, `many_bodies heap:200 200 1`): steps 0–173 under 1 s each,
///   176–193 2–95 s (2,793–98,150 pivots), no failure through step 193;
///   step 194 (n = 13,620) `ray_termination` after 246,628 pivots (261 s).
/// - the same at a973d7c on the loaded machine (`heap_replay record 200 195
///   DIR`): pivots identical step for step (step 190: 98,150, 201 s; steps
///   0–193 in 1,192 s). Step 194's LCP replayed with the step's rule: the
///   warm sub-LCP (n = 8,562) hits its cap (6,810); from the guess the
///   sub-LCP (n = 10,038) ends `cycling` (2,237 pivots), its cold runs a ray
///   at natural residual 8.0e-9 (15,425) and `numerical` at 1.1e-8 (17,818;
///   its basis's values refined thrice on the LCP still have z down to
///   −2.1e-9: a vertex a hair infeasible, not round-off), the restart a ray
///   (4,369); on the full LCP the guess's basis is all but singular (a ray
///   after 2 pivots at residual 6.7e36) and the cold runs end `numerical` or
///   on rays. Block principal pivoting (`lcp::structured::bpp`) from the
///   previous basis or the guess lowered no infeasible count on steps
///   175–179; a pivot tolerance of 1e-6 or a tie tolerance of 1e-10 ended
///   step 194 on cycles and `numerical` runs as well.
/// - where step 190's 98,150 pivots went (main at 5fb3878, replayed with
///   `LCPSIM_LEMKE_TRACE=1 heap_replay solve step`, which prints each
///   Lemke run's counts): 22 runs, the answer from three short warm runs
///   (102–501 pivots) of the last start. Runs end
///   `Solved` but rejected by the rule (14,279, 19,992 and 19,526 pivots),
///   on rays (2,368; 15,232) and cycles (2,344; 4,219). Not a stall: on the
///   runs over 10,000 pivots 0.4–1.7 % of pivots have θ = 0 (up to 15 % on
///   the short failing ones; longest stretch 78), a tie of two or more rows
///   occurs once (at the end), z0 never rises, and a variable enters at
///   most 38 times. On step 176 (16 runs, 31,442 pivots) 6 of the 7 failed
///   runs of over 100 pivots took pivots down to 1e-9 of their column (the
///   pivot tolerance), after which a fresh factorization moved the values
///   by 1e6–1e45 of the largest (the seventh ended 3 rows outside the rule,
///   η = 1.4e-8); the accepted ones took none below 1e-7. A pivot costs 0.3–0.4 ms at n ≈ 6,200 and 0.5–1.7 ms
///   at n = 7,770–13,350 (loaded machine), refactorizations 14–44 % of it.
/// - with Harris's ratio test on small pivots (`lcp::structured`'s pivot
///   loop; the saved LCPs, `heap_replay solve step`): steps 174–193 take
///   603,027 pivots against 699,759 (step 190 5,165, 188 3,186, 176 11,118,
///   181 36,902; but 182 121,277 against 61,780, 186 33,272 against 3,710:
///   every path is chaotic), step 194 is solved (262,379 pivots, 366 s).
///   What still fails: runs that cycle half way (z0 ≈ 1e-3; going on
///   after the cycle with a wider tie tolerance, 1e-10, they cycled again
///   within 12–38 pivots in 3 of 3 runs, with the plain lexicographic rule
///   in 1 of 2), and answers rejected at rows whose scale is ~1e-11
///   (contacts at the edge of touching, `q_i ≈ −1e-11`), where the basis's
///   values carry ~1e-12 of round-off. Letting z0 leave once it is within
///   1e-10 of 0 rejected more answers (step 187: 71,803 pivots against 17,399).
/// - at 1973259 (`heap_replay record 200 184 DIR`, the test's trajectory):
///   steps 0–174 in 8 s, 175–182 10,171–193,744 pivots each (4–163 s), step
///   183 (n = 13,360) `numerical` after 211,742 pivots (this test: failed
///   there after 653 s). Its 41 runs: warm starts end on rays within 3–78
///   pivots; cold runs cycle (565–9,134 pivots), end on rays with z0 at
///   round-off, or end with 1–3 rows outside the rule whose scale is ~1e-11
///   (cubes falling side by side); the loaded-friction rounds that follow an
///   answer ended on such a ray start from a numerically singular basis
///   (`B⁻¹(B·1)` 1,094 where it is 1) and go cold. Tried on step 183's LCP
///   and on steps 175–182 saved from the earlier run above (d626ab3's
///   trajectory; 172,991 pivots with 1973259's solver) and dropped: a ray or cycle
///   with z0 at round-off restarted from its basis (164,615; step 183 still
///   fails), plus a cycle continued without Harris's test (144,936; fails);
///   pivoting the entering variable or its complement into z0's place there
///   (both pivots 0: the ray is one of the LCP's own solutions); numerically
///   dependent warm columns repaired like structurally dependent ones; the
///   polish without Harris's test; four refinement steps of the basis values
///   (the rows stay out: the vertex, not its round-off); a covering vector
///   on the infeasible values only (step 175: 3,995 → 12,444–17,610 pivots).
///   Lemke from the basis read back from its own accepted answer
///   (`guess::read_basis`, or `z_j > 0`) takes 651–17,361 pivots: the
///   degenerate flags carry what a warm start needs, so no approximate
///   answer (sweeps, Newton) read into a basis can be a cheap start.
/// - with the rule's floor `ρ = max(1e-13, n·ε)` (3.0e-12 at n = 13,360;
///   measured, not adopted: docs/reliability.md): step 183 is solved
///   (44,041 pivots replayed), the test fails at step 185 (n = 13,460,
///   `cycling`) after 719 s.
/// Run with `cargo test --release -p lcpsim-sim --test heap -- --ignored --nocapture`.
#[test]
#[ignore]
fn heap_of_two_hundred_cubes_runs_without_failures_or_penetration() {
    let params = WorldParams { max_halvings: 3, ..WorldParams::default() };
    heap_runs_without_failures_or_penetration(200, 200, params);
}

/// The structured Lemke in the step: a block of 4×4×2 touching cubes is one
/// island of n ≥ 1,500 (the structured Lemke's; no dense `M` is formed),
/// solved on every step, at rest: the ground carries the weight and nothing sinks.
#[test]
fn a_block_of_touching_cubes_is_solved_by_the_structured_lemke() {
    use sim::scenes::BoxPile;
    let mut s =
        BoxPile { nx: 4, ny: 4, nz: 2, spacing: 1.0, ..Default::default() }.build(WorldParams::default()).unwrap();
    let (h, g) = (s.world.params().dt, 9.81);
    let mut penetration = 0.0f64;
    for _ in 0..40 {
        let r = s.world.step().unwrap();
        assert!(r.ok(), "step {}: {:?}", r.step, r.islands.iter().map(|i| (i.lcp_size, i.status)).collect::<Vec<_>>());
        assert_eq!(r.islands.len(), 1, "one block, one island");
        assert!(r.islands[0].lcp_size >= 1500, "n = {}: under the structured Lemke's threshold", r.islands[0].lcp_size);
        penetration = r.contacts.iter().fold(penetration, |p, c| p.max(-c.gap));
        // The ground's contacts (normal +z) carry the block's weight m·g·h per step.
        let ground: f64 = r
            .contacts
            .iter()
            .zip(r.normal_impulses())
            .filter(|(c, _)| c.normal.z > 0.99 && c.point.z.abs() < 1e-3)
            .map(|(_, f)| f)
            .sum();
        assert!((ground - 32.0 * g * h).abs() <= 1e-6 * 32.0 * g * h, "step {}: ground impulse {ground}", r.step);
    }
    assert!(penetration <= 1e-3, "penetration {penetration} m");
}
