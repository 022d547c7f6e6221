//! The previous basis of an island solved on its dense `M` (a jointed
//! island's `J P Jᵀ`, or one holding a torsion patch), before
//! `dense_loaded` and the dense Lemke: the body-space stages assume the
//! block-diagonal `M_b⁻¹` and one cone row per normal, so such an island's
//! warm basis is solved here by `lcp::on_basis` (its kept factorization
//! refined, exchanges of the indices the rule rejects), judged by the same
//! acceptance rule. Reported as the previous-basis stage.
//!
//! The LCP is read through [`CoupledSpaceLcp`]: the body-space products
//! minus the joints' coupling `E Yᵀ Y Eᵀ` (the island's `Y`, lent), plus the
//! motors' and patches' virtual rows — the dense `M`'s entries to round-off,
//! without forming it: a held gripper's steps (n = 130) formed it only to
//! read its basis block and a few products.

use super::stage::Found;
use crate::contact::CoupledSpaceLcp;
use crate::pipeline::island::IslandLcp;
use lcp::on_basis::{solve_on_basis_ruled, BasisTolerances};

/// The island's `warm` basis solved on its LCP at `accept_tol`, or `None`
/// (no basis, a scaled cone, or no accepted answer: the caller pivots).
pub(super) fn attempt(isl: &mut IslandLcp, warm: Option<&[bool]>, accept_tol: f64) -> Option<Found> {
    // (Scaled cones would need the physical LCP's check beside it: left to the Lemke.)
    let warm = warm.filter(|_| isl.lcp.scale() == 1.0)?;
    // At most REPAIR_ROUNDS exchanges: on the chain of `benchmarks/joints.py`
    // the rounds a small block gets beyond them (each a fresh factorization
    // and a dense product) answered fewer steps (2,123 against 2,228 of
    // 3,000) and left more pivots to the Lemke (383,071 against 265,839).
    let tol =
        BasisTolerances { accept_tol, tight: accept_tol, loose: true, polish: true, more_rounds: false, eager_rows: 0 };
    let (y, rank) = isl.coupling.factor();
    let op = CoupledSpaceLcp::new(&isl.lcp, y, rank);
    let sol = solve_on_basis_ruled(&op, warm, tol, None, &mut isl.basis_ws)?.solution;
    // At scale 1 the LCP is the physical one: its z and w (M z + q, as
    // checked) are the island's, copied into its last answer's buffers.
    let (mut z, mut w) = (std::mem::take(&mut isl.z), std::mem::take(&mut isl.w));
    z.clone_from(&sol.z);
    w.clone_from(&sol.w);
    Some(Found { sol, physical: Some((z, w)) })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::joints::scenes::{chain, gripper, gripper_lift_speed};
    use crate::math::Vec3;
    use crate::{World, WorldParams};
    use lcp::on_basis::{BasisAnswer, BasisWorkspace};
    use lcp::operator::LcpOperator;

    /// The largest difference of two vectors relative to their largest entry.
    fn rel(a: &[f64], b: &[f64]) -> f64 {
        let top = a.iter().chain(b).fold(1e-300f64, |m, v| m.max(v.abs()));
        a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs())) / top
    }

    fn bits(v: &[f64]) -> Vec<u64> {
        v.iter().map(|x| x.to_bits()).collect()
    }

    /// Per step, `control` then the step taken stage by stage; on every
    /// dense-only island with a previous basis, the operator is checked
    /// against the dense `M` (`check`). Returns (islands, both answered,
    /// verdicts that differ, both answered but more than 1e-9 apart).
    fn compare(
        w: &mut World,
        steps: usize,
        mut control: impl FnMut(&mut World, usize),
    ) -> (usize, usize, usize, usize) {
        let (mut compared, mut both, mut differ, mut far) = (0, 0, 0, 0);
        for step in 0..steps {
            control(w, step);
            w.forces_stage().unwrap();
            w.detect();
            w.islands();
            w.assemble_for_solve().unwrap();
            let mut warm = w.ws.warm.clone();
            for i in 0..w.ws.islands.len() {
                let nc = w.ws.islands.contacts_of(i).len();
                let (_, basis) = warm.take(w.ws.islands.bodies_of(i), nc);
                let isl = &w.ws.pool[i];
                let Some(basis) = basis.filter(|_| isl.dense_only() && isl.lcp.scale() == 1.0) else { continue };
                match check(isl, &basis, step) {
                    (Some(a), Some(b)) => {
                        let d = rel(&a.solution.z, &b.solution.z);
                        if d > 1e-9 {
                            eprintln!("step {step}: n {}, both answered, their answers {d:e} apart", isl.lcp.n());
                            far += 1;
                        }
                        both += 1
                    }
                    (None, None) => {}
                    (a, b) => {
                        eprintln!("step {step}: n {} op {} dense {}", isl.lcp.n(), a.is_some(), b.is_some());
                        differ += 1
                    }
                }
                compared += 1;
            }
            w.solve(None).unwrap();
            w.integrate();
        }
        (compared, both, differ, far)
    }

    /// One island: the operator's block is the dense `M`'s to the bit, its
    /// rows, diagonal and products to round-off; every answer either
    /// reading of `M` finds on `basis` (fresh workspaces) is accepted by the
    /// rule on both readings. Returns both readings' answers.
    fn check(isl: &IslandLcp, basis: &[bool], step: usize) -> (Option<BasisAnswer>, Option<BasisAnswer>) {
        let mut formed = isl.clone();
        formed.form_matrix();
        let dense = formed.lcp.to_lcp().unwrap();
        let (y, rank) = isl.coupling.factor();
        let op = CoupledSpaceLcp::new(&isl.lcp, y, rank);
        let n = dense.n();
        let all: Vec<usize> = (0..n).collect();
        let (mut block, mut one) = (vec![0.0; n * n], vec![0.0; n]);
        op.block(&all, &all, &mut block);
        let (mut row, mut drow) = (vec![0.0; n], vec![0.0; n]);
        for i in 0..n {
            LcpOperator::row(&dense, i, &mut drow);
            assert_eq!(bits(&block[i * n..(i + 1) * n]), bits(&drow), "step {step}: block row {i}");
            op.block(&[i], &all, &mut one);
            assert_eq!(bits(&one), bits(&drow), "step {step}: the 1 × n block {i}");
            op.row(i, &mut row);
            assert!(rel(&row, &drow) < 1e-12, "step {step}: row {i}, {:e}", rel(&row, &drow));
            let scale = drow.iter().fold(1.0f64, |m, v| m.max(v.abs()));
            assert!((op.diag(i) - drow[i]).abs() <= 1e-12 * scale, "step {step}: diagonal {i}");
        }
        // Products of a z loading every kind of index, of some rows, of moved columns.
        let z: Vec<f64> = (0..n).map(|j| ((j * 7 % 5) as f64) * 0.1).collect();
        let (mut wo, mut wd) = (vec![0.0; n], vec![0.0; n]);
        op.w_of(&z, &mut wo);
        LcpOperator::w_of(&dense, &z, &mut wd);
        assert!(rel(&wo, &wd) < 1e-12, "step {step}: w_of {:e}", rel(&wo, &wd));
        let rows: Vec<usize> = (0..n).rev().step_by(2).collect();
        let mut wr = vec![f64::NAN; n];
        op.w_rows(&z, &rows, &mut wr);
        assert!(rows.iter().all(|&r| (wr[r] - wo[r]).abs() <= 1e-12 * (1.0 + wo[r].abs())), "step {step}: w_rows");
        op.w_after_rows(&z, &mut wr);
        assert_eq!(bits(&wr), bits(&wo), "step {step}: w_after_rows is w_of");
        let moved: Vec<(usize, f64)> = (0..n).step_by(3).map(|j| (j, 0.01 * j as f64)).collect();
        op.add_columns(&moved, &mut wo);
        LcpOperator::add_columns(&dense, &moved, &mut wd);
        assert!(rel(&wo, &wd) < 1e-12, "step {step}: add_columns {:e}", rel(&wo, &wd));
        // The previous basis on both readings, as `attempt` solves it.
        let tol = BasisTolerances {
            accept_tol: 1e-9,
            tight: 1e-9,
            loose: true,
            polish: true,
            more_rounds: false,
            eager_rows: 0,
        };
        let on_op = solve_on_basis_ruled(&op, basis, tol, None, &mut BasisWorkspace::default());
        let on_dense = solve_on_basis_ruled(&dense, basis, tol, None, &mut BasisWorkspace::default());
        // And from the island's own workspace (its kept factorization refined), as the step solves it.
        let kept_op = solve_on_basis_ruled(&op, basis, tol, None, &mut isl.basis_ws.clone());
        let kept_dense = solve_on_basis_ruled(&dense, basis, tol, None, &mut isl.basis_ws.clone());
        for found in [&on_op, &on_dense, &kept_op, &kept_dense].into_iter().flatten() {
            let z = &found.solution.z;
            let (mut w1, mut w2) = (vec![0.0; n], vec![0.0; n]);
            op.w_of(z, &mut w1);
            LcpOperator::w_of(&dense, z, &mut w2);
            let accepted = |o: &dyn LcpOperator, w: &[f64]| lcp::accept::accepts_operator(o, z, w, 1e-9);
            assert!(accepted(&op, &w1) && accepted(&dense, &w2), "step {step}: the readings' verdicts differ");
        }
        (on_op, on_dense)
    }

    /// The gripper closing on the cube, lifting and holding it: the
    /// operator is the dense coupled LCP (`check`) on every jointed island,
    /// and the previous basis gets the same verdict through both.
    #[test]
    fn the_gripper_s_operator_is_its_dense_coupled_lcp() {
        let (mut w, lift) = gripper();
        let (compared, both, differ, far) = compare(&mut w, 2600, |w, step| {
            w.set_motor(lift, gripper_lift_speed(step), 200.0).unwrap();
        });
        assert!(compared > 2500 && both > 2400, "{compared} islands compared, {both} answered by both");
        assert_eq!((differ, far), (0, 0), "verdicts that differ, answers apart, of {compared}");
        assert!(w.bodies()[1].position().z > 0.15, "the cube is lifted");
    }

    /// The dense `M` of a jointed island formed at the `assemble` stage
    /// (coupled there) is, bit for bit, the one the solve forms when it
    /// needs it (`IslandLcp::form_matrix`), on the chain lying on the ground
    /// and on the gripper holding the cube (its motors' rows replace contacts').
    #[test]
    fn a_jointed_island_s_matrix_is_the_same_formed_early_or_late() {
        let (gripper, _) = gripper();
        for (mut w, steps) in [(chain(), 1500), (gripper, 1200)] {
            for _ in 0..steps {
                w.step().unwrap();
            }
            // (A copy of the world starts its step's buffers afresh.)
            let mut late = w.clone();
            for v in [&mut w, &mut late] {
                v.forces_stage().unwrap();
                v.detect();
                v.islands();
            }
            w.assemble();
            late.assemble_for_solve().unwrap();
            let mut jointed = 0;
            for (early, isl) in w.ws.pool[..w.ws.islands.len()].iter().zip(&mut late.ws.pool) {
                if !isl.jointed {
                    continue;
                }
                isl.form_matrix();
                let (a, b) = (early.lcp.to_lcp().unwrap(), isl.lcp.to_lcp().unwrap());
                assert_eq!(bits(a.m()), bits(b.m()));
                jointed += 1;
            }
            assert!(jointed > 0, "a jointed island with contacts");
        }
    }

    #[test]
    #[ignore]
    fn chain_diagnostic() {
        let mut w = chain();
        let steps: usize = std::env::var("CHAIN_STEPS").ok().and_then(|s| s.parse().ok()).unwrap_or(300);
        let r = compare(&mut w, steps, |_, _| {});
        eprintln!("chain: {r:?}");
    }

    /// A box with torsional friction on the ground, twisted by a torque
    /// below and then above what its friction holds (an island whose dense
    /// `M` is formed only for its patch's cone, no joint).
    #[test]
    fn a_torsion_patch_s_operator_is_its_dense_lcp() {
        let mut w = World::new(WorldParams::default()).unwrap();
        w.add_ground(0.5).unwrap();
        let cube = w.add_box(Vec3::splat(0.05), 1.0, Vec3::new(0.0, 0.0, 0.05), 0.5).unwrap();
        w.set_torsional_friction(cube, 0.02).unwrap();
        let (compared, both, differ, far) = compare(&mut w, 600, |w, step| {
            let torque = if step < 300 { 0.1 } else { 1.0 };
            w.apply_torque(cube, Vec3::new(0.0, 0.0, torque)).unwrap();
        });
        assert!(compared > 500 && both > 150, "{compared} islands compared, {both} answered by both");
        assert_eq!((differ, far), (0, 0), "verdicts that differ, answers apart, of {compared}");
    }
}
