//! The product's main scene over a grid of angles, μ and cone scales: the
//! default solver must solve every LCP of every step ("no Lemke failure at any
//! scale"). Covers resting, sliding, tipping and tumbling
//! cubes, i.e. face, edge and corner contacts.

use sim::scenes::CubeOnSlope;
use sim::{ConeScale, WorldParams};

#[test]
fn cube_on_slope_grid_has_no_lcp_failure() {
    let mut failures = Vec::new();
    let mut solved = 0usize;
    for scale in [ConeScale::Unscaled, ConeScale::TimeStep, ConeScale::Value(1e-6)] {
        for angle in (0..=60).step_by(5) {
            for mu in [0.2, 0.5, 1.0, 1.5] {
                let mut sc = CubeOnSlope::new(angle as f64, mu);
                sc.speed = if angle == 0 { 1.0 } else { 0.0 };
                let mut s = sc.build(WorldParams { cone_scale: scale, ..Default::default() }).unwrap();
                let traj = s.world.run(400).unwrap();
                solved += traj.status.iter().flatten().count();
                for (step, st) in traj.status.iter().enumerate() {
                    if let Some(st) = st {
                        if *st != sim::lcp::Status::Solved {
                            failures.push(format!(
                                "{scale:?} θ {angle} μ {mu} step {step}: {st:?} (LCP size {})",
                                traj.lcp_size[step]
                            ));
                        }
                    }
                }
            }
        }
    }
    assert!(failures.is_empty(), "{} of {solved} LCPs failed:\n{}", failures.len(), failures.join("\n"));
}
