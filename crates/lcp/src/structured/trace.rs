//! Counts of one run of the structured Lemke loop ([`super::pivot`]),
//! printed to standard error when `LCPSIM_LEMKE_TRACE` is set: a measuring
//! tool for where the pivots of a hard LCP go (e.g. with `heap_replay solve`
//! in the simulator's examples). Nothing here changes a run.
//!
//! Per run, one `lemke_trace` line: start (`cold`/`warm`), `n`, pivots,
//! status, seconds; `zero`/`tiny`: pivots whose step moved no value / none
//! by more than 1e-13 of the largest, `streak` the longest stretch of `θ = 0`;
//! `ties` and their sizes; `entered_*`: how often variables re-entered,
//! `back100`/`back1000`: entering variables that had left within that many
//! pivots; `z0` start..[least, largest], `z0_up` pivots that raised its
//! maximum; `drift`: values pushed below 0 by rows under the pivot tolerance
//! (count, least), `ratio`: by rows above it; `fresh`: the least value
//! (relative to the largest) after a refactorization and the first pivot it
//! fell below −1e-12; `small`: pivots under 1e-6 of their column (count,
//! least); `jumps`: refactorizations that moved the values by more than
//! 1e-6 of the largest (called by a small pivot + by the update count), the
//! largest move; `samples`: pivot:z0/negative values at powers of two.
//! Then one `lemke_end` line: the final basis's negative values, how its
//! answer (z clipped, w recomputed) stands against the acceptance rule, and
//! the run's numeric factorizations and fresh column orders.

use super::factor::{Basis, NONBASIC};
use super::operator::StructuredLcp;
use crate::accept::ROUND_OFF;
use crate::solution::Status;
use std::time::{Duration, Instant};

/// Whether runs are traced (`LCPSIM_LEMKE_TRACE` set), read once.
pub(crate) fn enabled() -> bool {
    static ON: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *ON.get_or_init(|| std::env::var_os("LCPSIM_LEMKE_TRACE").is_some())
}

/// The counts of one run (fields as in the module docs).
pub(crate) struct Trace {
    n: usize,
    t0: Instant,
    zero: usize,
    tiny: usize,
    streak: usize,
    cur: usize,
    ties: usize,
    tied_sum: usize,
    tied_max: usize,
    entered: Vec<u32>,
    left_at: Vec<usize>,
    back100: usize,
    back1000: usize,
    z0_start: f64,
    z0_min: f64,
    z0_max: f64,
    z0_up: usize,
    samples: Vec<(usize, f64, usize)>,
    refactors: usize,
    refactor_time: Duration,
    refactor_t0: Instant,
    drift_rows: usize,
    drift_min: f64,
    ratio_rows: usize,
    ratio_min: f64,
    fresh_min: f64,
    fresh_first: usize,
    small: usize,
    small_min: f64,
    /// Values before a refactorization, and whether a small pivot called it.
    old: Vec<f64>,
    old_small: bool,
    jumps_small: usize,
    jumps_count: usize,
    jump_max: f64,
}

impl Trace {
    pub(crate) fn new(n: usize, z0: f64) -> Self {
        Trace {
            n,
            t0: Instant::now(),
            zero: 0,
            tiny: 0,
            streak: 0,
            cur: 0,
            ties: 0,
            tied_sum: 0,
            tied_max: 0,
            entered: vec![0; 2 * n + 1],
            left_at: vec![usize::MAX; 2 * n + 1],
            back100: 0,
            back1000: 0,
            z0_start: z0,
            z0_min: z0,
            z0_max: z0,
            z0_up: 0,
            samples: Vec::new(),
            refactors: 0,
            refactor_time: Duration::ZERO,
            refactor_t0: Instant::now(),
            drift_rows: 0,
            drift_min: 0.0,
            ratio_rows: 0,
            ratio_min: 0.0,
            fresh_min: 0.0,
            fresh_first: 0,
            small: 0,
            small_min: 1.0,
            old: Vec::new(),
            old_small: false,
            jumps_small: 0,
            jumps_count: 0,
            jump_max: 0.0,
        }
    }

    /// Before a pivot by `θ` along `y` (`thresh` the pivot tolerance, `tied`
    /// positions tied, `rel` the pivot over its column's largest entry).
    pub(crate) fn before_pivot(&mut self, val: &[f64], y: &[f64], theta: f64, thresh: f64, tied: usize, rel: f64) {
        let vmax = val.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let ymax = y.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if theta == 0.0 {
            self.zero += 1;
            self.cur += 1;
            self.streak = self.streak.max(self.cur);
        } else {
            self.cur = 0;
        }
        if theta * ymax <= 1e-13 * vmax {
            self.tiny += 1;
        }
        if tied > 1 {
            self.ties += 1;
            self.tied_sum += tied;
            self.tied_max = self.tied_max.max(tied);
        }
        if rel < 1e-6 {
            self.small += 1;
        }
        self.small_min = self.small_min.min(rel);
        for (&v, &yc) in val.iter().zip(y) {
            let after = v - theta * yc;
            if yc > 0.0 && after < 0.0 && v >= 0.0 {
                if yc <= thresh {
                    self.drift_rows += 1;
                    self.drift_min = self.drift_min.min(after);
                } else {
                    self.ratio_rows += 1;
                    self.ratio_min = self.ratio_min.min(after);
                }
            }
        }
    }

    /// After pivot `k`: `e` entered, `left` left; z0's value if still basic.
    pub(crate) fn after_pivot(&mut self, k: usize, e: usize, left: usize, z0: Option<f64>, val: &[f64]) {
        self.entered[e] += 1;
        let back = self.left_at[e];
        if back != usize::MAX {
            self.back100 += usize::from(k - back <= 100);
            self.back1000 += usize::from(k - back <= 1000);
        }
        self.left_at[left] = k;
        let Some(z0) = z0 else { return };
        if z0 > self.z0_max {
            self.z0_up += 1;
        }
        self.z0_min = self.z0_min.min(z0);
        self.z0_max = self.z0_max.max(z0);
        if k.is_power_of_two() || k.is_multiple_of(5000) {
            self.samples.push((k, z0, val.iter().filter(|&&v| v < 0.0).count()));
        }
    }

    pub(crate) fn before_refactor(&mut self, val: &[f64], small: bool) {
        self.old.clear();
        self.old.extend_from_slice(val);
        self.old_small = small;
        self.refactor_t0 = Instant::now();
    }

    /// After a refactorization at pivot `k`, with its fresh values.
    pub(crate) fn after_refactor(&mut self, k: usize, val: &[f64]) {
        self.refactors += 1;
        self.refactor_time += self.refactor_t0.elapsed();
        let vmax = val.iter().fold(f64::MIN_POSITIVE, |a, v| a.max(v.abs()));
        let omax = self.old.iter().fold(f64::MIN_POSITIVE, |a, v| a.max(v.abs()));
        let jump = self.old.iter().zip(val).fold(0.0f64, |a, (o, v)| a.max((o - v).abs())) / omax;
        if jump > 1e-6 {
            if self.old_small {
                self.jumps_small += 1;
            } else {
                self.jumps_count += 1;
            }
        }
        self.jump_max = self.jump_max.max(jump);
        let m = val.iter().fold(0.0f64, |a, &v| a.min(v)) / vmax;
        if m < -1e-12 && self.fresh_first == 0 {
            self.fresh_first = k;
        }
        self.fresh_min = self.fresh_min.min(m);
    }

    /// The `lemke_trace` line.
    pub(crate) fn print(&self, kind: &str, pivots: usize, status: Status) {
        let n = self.n;
        let distinct = self.entered.iter().filter(|&&c| c > 0).count();
        let max_in = self.entered.iter().copied().max().unwrap_or(0);
        let over10 = self.entered.iter().filter(|&&c| c >= 10).count();
        let (w_in, z_in) = (self.entered[..n].iter().sum::<u32>(), self.entered[n..2 * n].iter().sum::<u32>());
        let secs = self.t0.elapsed().as_secs_f64();
        let samples: Vec<String> = self.samples.iter().map(|(k, z, neg)| format!("{k}:{z:.2e}/{neg}")).collect();
        eprintln!(
            "lemke_trace {kind} n {n} pivots {pivots} status {status:?} secs {secs:.2} us_per_pivot {:.0} \
             zero {} tiny {} streak {} ties {} tied_mean {:.1} tied_max {} refactors {} refactor_secs {:.2} \
             entered_distinct {distinct} entered_max {max_in} entered_ge10 {over10} w_in {w_in} z_in {z_in} \
             back100 {} back1000 {} z0 {:.3e}..[{:.3e},{:.3e}] z0_up {} drift {} {:.1e} ratio {} {:.1e} \
             fresh {:.1e} at {} small {} {:.1e} jumps {}+{} {:.1e} samples {}",
            1e6 * secs / pivots.max(1) as f64,
            self.zero,
            self.tiny,
            self.streak,
            self.ties,
            self.tied_sum as f64 / self.ties.max(1) as f64,
            self.tied_max,
            self.refactors,
            self.refactor_time.as_secs_f64(),
            self.back100,
            self.back1000,
            self.z0_start,
            self.z0_min,
            self.z0_max,
            self.z0_up,
            self.drift_rows,
            self.drift_min,
            self.ratio_rows,
            self.ratio_min,
            self.fresh_min,
            self.fresh_first,
            self.small,
            self.small_min,
            self.jumps_small,
            self.jumps_count,
            self.jump_max,
            samples.join(",")
        );
    }
}

/// The `lemke_end` line: the final basis's negative values and how its
/// answer (z clipped at 0, w recomputed) stands against the acceptance
/// rule at `tol`: rows over it, the worst row's `η` and what it is made of.
pub(crate) fn end(op: &StructuredLcp, b: &Basis, tol: f64) {
    let n = op.n();
    let mut z = Vec::new();
    let z0 = b.z_into(&mut z);
    let (mut zneg, mut zmin, mut wneg, mut wmin) = (0, 0.0f64, 0, 0.0f64);
    for (c, &v) in b.var.iter().enumerate() {
        let x = b.val[c];
        if x < 0.0 && v < n {
            wneg += 1;
            wmin = wmin.min(x);
        } else if x < 0.0 && v < 2 * n {
            zneg += 1;
            zmin = zmin.min(x);
        }
    }
    let vmax = b.val.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let zc: Vec<f64> = z.iter().map(|v| v.max(0.0)).collect();
    let mut w = vec![0.0; n];
    op.w_of(&zc, &mut w);
    let zsum: f64 = zc.iter().sum();
    let mut row = Vec::new();
    let (mut over, mut worst) = (0, (0.0f64, 0usize, 0.0f64));
    for i in 0..n {
        let v = if zc[i] > 0.0 { w[i].abs() } else { (-w[i]).max(0.0) };
        if v == 0.0 {
            continue;
        }
        op.row_into(i, &mut row);
        let (terms, rmax) = row.iter().fold((0.0, 0.0f64), |(t, m), &(j, x)| (t + x.abs() * zc[j], m.max(x.abs())));
        let s = terms + op.q()[i].abs();
        let eta = (v - ROUND_OFF * rmax * zsum).max(0.0) / s;
        over += usize::from(eta > tol);
        if eta > worst.0 {
            worst = (eta, i, s);
        }
    }
    let i = worst.1;
    let basic = if b.pos[n + i] != NONBASIC {
        "z"
    } else if b.pos[i] != NONBASIC {
        "w"
    } else {
        "-"
    };
    eprintln!(
        "lemke_end n {n} z0 {z0:.1e} vmax {vmax:.1e} z_neg {zneg} z_min {zmin:.1e} w_neg {wneg} w_min {wmin:.1e} \
         rows_over {over} worst_eta {:.1e} row {i} basic {basic} z {:.1e} w {:.1e} scale {:.1e} \
         factorizations {} fresh_orders {}",
        worst.0,
        z[i],
        w[i],
        worst.2,
        b.factor_counts().0,
        b.factor_counts().1
    );
}
