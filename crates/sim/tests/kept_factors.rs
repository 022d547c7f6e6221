//! The structured stage's kept operators and basis factors
//! (`solve_chain::kept_factors`) answer as building them afresh each step
//! does: the same stages, the same pivots, the same motion to round-off.
//! (One test in this file: the switch is process-wide.)

use sim::scenes::BoxPile;
use sim::solve_chain::kept_factors;
use sim::{SolveStage, WorldParams};

#[test]
fn a_resting_block_steps_alike_with_kept_and_with_fresh_factors() {
    // 50 cubes side by side in two layers: one island of n ≥ 1,500, which
    // the structured stage answers from its previous basis every step.
    let pile = BoxPile { nx: 5, ny: 5, nz: 2, spacing: 1.0, ..Default::default() };
    let mut worlds = [pile.build(WorldParams::default()).unwrap(), pile.build(WorldParams::default()).unwrap()];
    let (mut structured, mut answered) = (0, 0);
    for step in 0..200 {
        let mut records = Vec::new();
        for (k, s) in worlds.iter_mut().enumerate() {
            kept_factors::set_enabled(k == 0);
            let before = kept_factors::answers();
            records.push(s.world.step().unwrap().clone());
            answered += kept_factors::answers() - before;
        }
        let [kept, fresh] = [&records[0], &records[1]];
        assert_eq!(kept.islands.len(), fresh.islands.len(), "step {step}");
        for (a, b) in kept.islands.iter().zip(&fresh.islands) {
            assert_eq!(a.status, lcp::Status::Solved, "step {step}");
            assert_eq!(b.status, lcp::Status::Solved, "step {step}");
            assert_eq!((a.lcp_size, a.stage, a.pivots), (b.lcp_size, b.stage, b.pivots), "step {step}");
            assert!(a.residual <= 1e-9 && b.residual <= 1e-9, "step {step}: {:e} {:e}", a.residual, b.residual);
            if a.stage == Some(SolveStage::StructuredLemke) && a.lcp_size >= sim::solve_chain::STRUCTURED_MIN_N {
                structured += 1;
            }
        }
    }
    kept_factors::set_enabled(true);
    // Most steps answered by the structured stage on a large island, on kept factors.
    assert!(
        structured >= 150 && answered >= 150,
        "{structured} steps on the structured stage, {answered} on kept factors"
    );
    let [a, b] = &worlds;
    for &body in &a.bodies {
        let (p, q) = (a.world.body(body).unwrap().position(), b.world.body(body).unwrap().position());
        assert!((p - q).norm() <= 1e-12, "{body:?}: {p:?} and {q:?}");
    }
}
