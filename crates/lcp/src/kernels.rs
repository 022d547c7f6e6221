//! Branch-free sweeps: Lemke's per-pivot scans of a column and of the basic
//! values, and the finiteness check of every input.
//!
//! Written over four independent lanes with `if`-selects instead of
//! `f64::max` (whose NaN rule keeps LLVM from vectorizing) and without
//! data-dependent branches, which the ratio test otherwise mispredicts on
//! nearly every row. Results are exactly those of the plain loops: max and
//! min are order-independent.

pub(crate) const LANES: usize = 4;

#[inline(always)]
pub(crate) fn pick_max(m: f64, x: f64) -> f64 {
    if x > m {
        x
    } else {
        m
    }
}

#[inline(always)]
pub(crate) fn pick_min(m: f64, x: f64) -> f64 {
    if x < m {
        x
    } else {
        m
    }
}

/// `max(init, max_i |a_i|)` and whether every `a_i` is finite (NaN and ±∞
/// turn `a_i · 0` into NaN).
pub(crate) fn max_abs_finite(a: &[f64], init: f64) -> (f64, bool) {
    let (mut acc, mut nan) = ([init; LANES], [0.0f64; LANES]);
    let mut chunks = a.chunks_exact(LANES);
    for c in &mut chunks {
        for k in 0..LANES {
            acc[k] = pick_max(acc[k], c[k].abs());
            nan[k] += c[k] * 0.0;
        }
    }
    for &v in chunks.remainder() {
        acc[0] = pick_max(acc[0], v.abs());
        nan[0] += v * 0.0;
    }
    (acc.iter().fold(init, |m, &x| pick_max(m, x)), nan.iter().sum::<f64>() == 0.0)
}

/// The acceptance rule's first looks at every row ([`crate::accept`]):
/// whether some `z_i` is negative or not finite, and the first row whose
/// violation `v_i` (`|w_i|` where `z_i > 0`, else `max(−w_i, 0)`, a NaN `w_i`
/// counting 0 there) is neither 0 nor within `tol·|q_i|` nor, with the
/// diagonal `d` given and `zsum = Σ z`, within `tol·(|q_i| + |d_i| z_i) +
/// ρ·|d_i|·zsum` (`n`, the rows' count, when there is none). With `past`
/// holding words for all `n` rows, every such row is also marked there (bit
/// `i % 64` of word `i / 64`; else it is left as it is). The verdicts of the
/// row-by-row tests, in one pass without early exits, which vectorizes.
pub(crate) fn rows_past_cheap_tests(
    (q, z, w): (&[f64], &[f64], &[f64]),
    tol: f64,
    diagonal: Option<(&[f64], f64)>,
    past: Option<&mut [u64]>,
) -> (bool, usize) {
    let n = q.len().min(z.len()).min(w.len());
    let past = past.filter(|p| p.len() * 64 >= n);
    match (diagonal.filter(|(d, _)| d.len() >= n), past) {
        (Some((d, zsum)), None) => cheap_tests::<true>((&q[..n], &z[..n], &w[..n], &d[..n]), tol, zsum),
        (None, None) => cheap_tests::<false>((&q[..n], &z[..n], &w[..n], &q[..n]), tol, 0.0),
        (Some((d, zsum)), Some(p)) => marked_tests::<true>((&q[..n], &z[..n], &w[..n], &d[..n]), tol, zsum, p),
        (None, Some(p)) => marked_tests::<false>((&q[..n], &z[..n], &w[..n], &q[..n]), tol, 0.0, p),
    }
}

/// Whether row `i` clears [`rows_past_cheap_tests`]'s tests, and whether its `z_i` is bad.
#[inline(always)]
fn cheap_test<const DIAG: bool>(
    (q, z, w, d): (&[f64], &[f64], &[f64], &[f64]),
    tol: f64,
    zsum: f64,
    i: usize,
) -> (bool, bool) {
    let (qi, zi, wi, di) = (q[i].abs(), z[i], w[i], d[i].abs());
    let bad = !((zi >= 0.0) & (zi.abs() < f64::INFINITY));
    let v = crate::accept::violation(zi, wi);
    let by_diag = DIAG && v <= tol * (qi + di * zi) + crate::accept::ROUND_OFF * di * zsum;
    ((v == 0.0) | (v <= tol * qi) | by_diag, bad)
}

/// [`rows_past_cheap_tests`] over rows of equal lengths, the diagonal read when `DIAG`.
#[inline(always)]
fn cheap_tests<const DIAG: bool>(rows: (&[f64], &[f64], &[f64], &[f64]), tol: f64, zsum: f64) -> (bool, usize) {
    let n = rows.0.len();
    let (mut bad, mut first) = (false, n);
    for i in 0..n {
        let (clear, bad_z) = cheap_test::<DIAG>(rows, tol, zsum, i);
        bad |= bad_z;
        first = first.min(if clear { n } else { i });
    }
    (bad, first)
}

/// [`cheap_tests`] marking the rows past them in `past`.
#[inline(always)]
fn marked_tests<const DIAG: bool>(
    rows: (&[f64], &[f64], &[f64], &[f64]),
    tol: f64,
    zsum: f64,
    past: &mut [u64],
) -> (bool, usize) {
    let n = rows.0.len();
    let (mut bad, mut first) = (false, n);
    // (By words of 64 rows: a row's bit is its verdict shifted into place.)
    for (word, start) in (0..n).step_by(64).enumerate() {
        let mut bits = 0u64;
        for (k, i) in (start..(start + 64).min(n)).enumerate() {
            let (clear, bad_z) = cheap_test::<DIAG>(rows, tol, zsum, i);
            bad |= bad_z;
            bits |= u64::from(!clear) << k;
        }
        if first == n && bits != 0 {
            first = start + bits.trailing_zeros() as usize;
        }
        past[word] = bits;
    }
    (bad, first)
}

/// The rows marked in `past` (as [`rows_past_cheap_tests`] marks them), in
/// order, from row `from` on.
pub(crate) fn marked_rows(past: &[u64], from: usize) -> impl Iterator<Item = usize> + '_ {
    let first = from / 64;
    past.iter().enumerate().skip(first).flat_map(move |(word, &bits)| {
        // (Bits of rows before `from` in its word cleared.)
        let mut bits = if word == first { bits & (u64::MAX << (from % 64)) } else { bits };
        std::iter::from_fn(move || {
            (bits != 0).then(|| {
                let k = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                word * 64 + k
            })
        })
    })
}

/// `a.iter().sum()`, bit for bit, without waiting on the adds of zeros: the
/// sum of a sequence is a chain of adds, one after another, and a basic
/// solution's `z` is mostly zeros (a resting stack's: 30–99 nonzero of
/// 400), whose adds change nothing (`s + ±0 = s` for `s ≠ −0`). Chunks of
/// four zeros are skipped after one test; a zero sum is summed again as
/// given (its sign).
pub(crate) fn sum_in_order(a: &[f64]) -> f64 {
    let mut s = -0.0;
    let mut chunks = a.chunks_exact(LANES);
    for c in &mut chunks {
        if c.iter().any(|&x| x != 0.0) {
            s = c.iter().fold(s, |s, &x| s + x);
        }
    }
    s = chunks.remainder().iter().fold(s, |s, &x| s + x);
    if s == 0.0 {
        a.iter().sum()
    } else {
        s
    }
}

/// The most violated index of a complementary point: `v_i = −z_i` where
/// `basic[i]`, else `−w_i`; the first index of the largest `v_i` above
/// `floor` (a NaN `v_i` never counts) with that `v_i` (`(floor, None)` when
/// none is above), and whether some `z_i < 0`. The verdict of the plain scan
/// (`v_i > worst` in order), in a pass that vectorizes and a second over
/// the rows only when some `v_i` is above `floor`.
// (Inlined into the exchange rounds' loop, its one caller, as LLVM chose
// before the rule's kernels beside it grew: a call cost the resting cube 0.5 %.)
#[inline(always)]
pub(crate) fn most_violated(basic: &[bool], z: &[f64], w: &[f64], floor: f64) -> ((f64, Option<usize>), bool) {
    let n = basic.len().min(z.len()).min(w.len());
    let (basic, z, w) = (&basic[..n], &z[..n], &w[..n]);
    let v = |i: usize| if basic[i] { -z[i] } else { -w[i] };
    // (Over lanes, `z_i` or `w_i` picked by masks: a running max would wait
    // on one compare after another, and a branch on `basic[i]` becomes a
    // choice of pointers that does not vectorize.)
    let pick = |b: bool, zi: f64, wi: f64| {
        let on = u64::from(b).wrapping_neg();
        -f64::from_bits((zi.to_bits() & on) | (wi.to_bits() & !on))
    };
    let (mut acc, mut neg) = ([floor; LANES], [false; LANES]);
    let (mut cb, mut cz, mut cw) = (basic.chunks_exact(LANES), z.chunks_exact(LANES), w.chunks_exact(LANES));
    for ((b, zc), wc) in (&mut cb).zip(&mut cz).zip(&mut cw) {
        for k in 0..LANES {
            acc[k] = pick_max(acc[k], pick(b[k], zc[k], wc[k]));
            neg[k] |= zc[k] < 0.0;
        }
    }
    for ((&b, &zi), &wi) in cb.remainder().iter().zip(cz.remainder()).zip(cw.remainder()) {
        acc[0] = pick_max(acc[0], pick(b, zi, wi));
        neg[0] |= zi < 0.0;
    }
    let top = acc.iter().fold(floor, |m, &x| pick_max(m, x));
    let negative = neg.iter().any(|&b| b);
    // (`top > floor` only if some `v_i` is: then its first index is the scan's.)
    let worst = if top > floor { (top, (0..n).position(|i| v(i) == top)) } else { (floor, None) };
    (worst, negative)
}

/// `Σ a_i b_i` over four lanes (summed as `(l0 + l1) + (l2 + l3)`, then the
/// remainder): vectorizes, where a sequential sum cannot be reordered and
/// waits on one add after another. Not bitwise the sequential sum, and no
/// less accurate. For residuals, not for pivoting (whose decisions should not
/// hinge on a summation order).
pub(crate) fn dot4(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0f64; LANES];
    let (mut ca, mut cb) = (a.chunks_exact(LANES), b.chunks_exact(LANES));
    for (x, y) in (&mut ca).zip(&mut cb) {
        for k in 0..LANES {
            acc[k] += x[k] * y[k];
        }
    }
    let tail: f64 = ca.remainder().iter().zip(cb.remainder()).map(|(x, y)| x * y).sum();
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// [`dot4`] for a `b` whose nonzero entries below `chunked = len − len % 4`
/// are `b[j]` for `j` in `nz` (ascending, each `< chunked`): every lane adds
/// the same products in the same order, and a skipped product `a_j · 0`
/// (`±0` for a finite `a_j`) would have left its lane unchanged (a lane
/// starting at `+0` is never `−0`), so the sum is bitwise [`dot4`]'s for a
/// finite `a`. The tail is summed as [`dot4`] sums it.
pub(crate) fn dot4_sparse(a: &[f64], b: &[f64], nz: &[usize]) -> f64 {
    let n = a.len().min(b.len());
    let chunked = n - n % LANES;
    let mut acc = [0.0f64; LANES];
    for &j in nz {
        acc[j % LANES] += a[j] * b[j];
    }
    let tail: f64 = a[chunked..n].iter().zip(&b[chunked..n]).map(|(x, y)| x * y).sum();
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// Whether every `a_i` is finite (`a_i · 0` is NaN for NaN and ±∞), in
/// `4·LANES` sums: independent adds the sweep overlaps, where
/// [`max_abs_finite`]'s `LANES` wait on one another.
pub(crate) fn all_finite(a: &[f64]) -> bool {
    let mut nan = [0.0f64; 4 * LANES];
    let mut chunks = a.chunks_exact(4 * LANES);
    for c in &mut chunks {
        for k in 0..4 * LANES {
            nan[k] += c[k] * 0.0;
        }
    }
    let tail: f64 = chunks.remainder().iter().map(|v| v * 0.0).sum();
    nan.iter().sum::<f64>() + tail == 0.0
}

/// `min(init.0, min { max(v_i, 0) / x_i : x_i > thresh })`, the ratio test's
/// step, and `max(init.1, max_i |v_i|)`, the scale of its ties, in one sweep.
pub(crate) fn min_ratio(v: &[f64], x: &[f64], thresh: f64, init: (f64, f64)) -> (f64, f64) {
    let n = v.len().min(x.len());
    let (v, x) = (&v[..n], &x[..n]);
    let ratio = |v: f64, x: f64| if x > thresh { (if v > 0.0 { v } else { 0.0 }) / x } else { f64::INFINITY };
    let (mut acc, mut big) = ([init.0; LANES], [init.1; LANES]);
    let (mut cv, mut cx) = (v.chunks_exact(LANES), x.chunks_exact(LANES));
    for (a, b) in (&mut cv).zip(&mut cx) {
        for k in 0..LANES {
            acc[k] = pick_min(acc[k], ratio(a[k], b[k]));
            big[k] = pick_max(big[k], a[k].abs());
        }
    }
    for (&a, &b) in cv.remainder().iter().zip(cx.remainder()) {
        acc[0] = pick_min(acc[0], ratio(a, b));
        big[0] = pick_max(big[0], a.abs());
    }
    (acc.iter().fold(init.0, |m, &x| pick_min(m, x)), big.iter().fold(init.1, |m, &x| pick_max(m, x)))
}

/// Appends to `out` every `i` (ascending) with `x_i > thresh` and
/// `max(v_i, 0) − θ·x_i ≤ vtol`: the rows tied with the ratio test's step.
/// Lanes are tested four at a time; only a chunk with a hit is looked into.
pub(crate) fn ties(v: &[f64], x: &[f64], thresh: f64, theta: f64, vtol: f64, out: &mut Vec<usize>) {
    let n = v.len().min(x.len());
    let (v, x) = (&v[..n], &x[..n]);
    let tied = |v: f64, x: f64| (x > thresh) & ((if v > 0.0 { v } else { 0.0 }) - theta * x <= vtol);
    let (mut cv, mut cx) = (v.chunks_exact(LANES), x.chunks_exact(LANES));
    for (c, (a, b)) in (&mut cv).zip(&mut cx).enumerate() {
        let hit: [bool; LANES] = std::array::from_fn(|k| tied(a[k], b[k]));
        if hit.iter().fold(false, |h, &k| h | k) {
            out.extend((0..LANES).filter(|&k| hit[k]).map(|k| c * LANES + k));
        }
    }
    let base = n - cv.remainder().len();
    for (k, (&a, &b)) in cv.remainder().iter().zip(cx.remainder()).enumerate() {
        if tied(a, b) {
            out.push(base + k);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn max_abs_finite_matches_the_plain_loop() {
        let a = [1.0, -7.5, 3.0, 0.0, 2.0, -1.0, 6.0];
        assert_eq!(max_abs_finite(&a, 0.0), (7.5, true));
        assert_eq!(max_abs_finite(&a[..3], 10.0), (10.0, true));
        assert!(!max_abs_finite(&[1.0, f64::NAN, 2.0, 3.0, 4.0], 0.0).1);
        assert!(!max_abs_finite(&[1.0, 2.0, 3.0, 4.0, f64::NEG_INFINITY], 0.0).1);
    }

    #[test]
    fn all_finite_rejects_nan_and_infinities_at_every_position() {
        let ok: Vec<f64> = (0..37).map(|i| (i as f64 - 18.0) * 1e300).collect();
        assert!(all_finite(&ok) && all_finite(&[]) && all_finite(&[f64::MAX, f64::MIN_POSITIVE, -0.0]));
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -f64::NAN] {
            for i in 0..ok.len() {
                let mut a = ok.clone();
                a[i] = bad;
                assert!(!all_finite(&a), "{bad} at {i} of {}", a.len());
            }
        }
    }

    #[test]
    fn dot4_sums_every_product() {
        let a: Vec<f64> = (1..=11).map(f64::from).collect();
        let b: Vec<f64> = (1..=11).map(|i| f64::from(i % 3) - 1.0).collect();
        let exact: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
        assert_eq!(dot4(&a, &b), exact);
        assert_eq!(dot4(&a[..3], &b[..3]), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
        assert_eq!(dot4(&[], &[]), 0.0);
        assert!(dot4(&[1.0, f64::NAN], &[1.0, 1.0]).is_nan());
    }

    use proptest::strategy::Strategy as _;

    /// A float of magnitude 2^-100 … 2^100 (either sign).
    fn spread() -> impl proptest::strategy::Strategy<Value = f64> {
        (-1e3f64..1e3, -100i32..100).prop_map(|(m, e)| m * 2f64.powi(e))
    }

    proptest::proptest! {
        /// Bitwise dot4's sum for any finite `a` and a `b` with zeros of both
        /// signs, values over 200 binary orders, and now and then NaN or ∞.
        #[test]
        fn dot4_sparse_is_dot4_bit_for_bit(
            a in proptest::collection::vec(spread(), 0..40),
            b in proptest::collection::vec(
                proptest::prop_oneof![
                    8 => proptest::strategy::Just(0.0f64),
                    4 => proptest::strategy::Just(-0.0f64),
                    1 => proptest::strategy::Just(f64::NAN),
                    1 => proptest::strategy::Just(f64::INFINITY),
                    16 => spread(),
                ],
                0..40,
            ),
        ) {
            let n = a.len().min(b.len());
            let nz: Vec<usize> = (0..n - n % LANES).filter(|&j| b[j] != 0.0).collect();
            let (s, d) = (dot4_sparse(&a, &b, &nz), dot4(&a, &b));
            proptest::prop_assert!(s.to_bits() == d.to_bits() || (s.is_nan() && d.is_nan()), "{s:e} {d:e}");
        }
    }

    /// An entry of `q`, `z`, `w` or `M_ii`: zeros of both signs, values over
    /// 200 binary orders, round-off sized ones, now and then NaN or ∞.
    fn entry() -> impl proptest::strategy::Strategy<Value = f64> {
        proptest::prop_oneof![
            6 => proptest::strategy::Just(0.0f64),
            2 => proptest::strategy::Just(-0.0f64),
            1 => proptest::strategy::Just(f64::NAN),
            1 => proptest::strategy::Just(f64::NEG_INFINITY),
            4 => (-1.0f64..1.0).prop_map(|m| m * 1e-12),
            12 => spread(),
        ]
    }

    proptest::proptest! {
        /// The same verdicts as the rule's tests read row by row (a bad
        /// `z_i`; the first row past `v_i = 0`, `v_i ≤ tol·|q_i|` and, with
        /// the diagonal, `v_i ≤ tol·(|q_i| + |M_ii| z_i) + ρ·|M_ii|·Σ z`).
        #[test]
        fn rows_past_cheap_tests_is_the_row_by_row_verdict(
            rows in proptest::collection::vec((entry(), entry(), entry(), entry()), 0..150),
            positive in proptest::bool::ANY,
            tol in proptest::prop_oneof![proptest::strategy::Just(1e-9f64), 0.0f64..1.0],
        ) {
            let mut q: Vec<f64> = rows.iter().map(|r| r.0).collect();
            let mut z: Vec<f64> = rows.iter().map(|r| r.1).collect();
            let w: Vec<f64> = rows.iter().map(|r| r.2).collect();
            let d: Vec<f64> = rows.iter().map(|r| r.3).collect();
            if positive {
                // (Most calls: every z_i ≥ 0 and finite, the rows decide.)
                z.iter_mut().for_each(|v| *v = if v.is_finite() { v.abs() } else { 1.0 });
                q.iter_mut().for_each(|v| *v = if v.is_nan() { 0.5 } else { *v });
            }
            let zsum: f64 = z.iter().sum();
            let bad = z.iter().any(|&v| !(v >= 0.0 && v.is_finite()));
            let violation = |i: usize| if z[i] > 0.0 { w[i].abs() } else { (-w[i]).max(0.0) };
            let clear = |i: usize, diag: bool| {
                let (v, m) = (violation(i), d[i].abs());
                v == 0.0
                    || v <= tol * q[i].abs()
                    || diag && v <= tol * (q[i].abs() + m * z[i]) + crate::accept::ROUND_OFF * m * zsum
            };
            for diag in [false, true] {
                let first = (0..q.len()).find(|&i| !clear(i, diag)).unwrap_or(q.len());
                let marked: Vec<usize> = (0..q.len()).filter(|&i| !clear(i, diag)).collect();
                let given = diag.then_some((d.as_slice(), zsum));
                let mut past = [0u64; 3];
                proptest::prop_assert_eq!(rows_past_cheap_tests((&q, &z, &w), tol, given, None), (bad, first));
                proptest::prop_assert_eq!(rows_past_cheap_tests((&q, &z, &w), tol, given, Some(&mut past)), (bad, first));
                let from = first.min(q.len()).saturating_sub(1);
                let expect: Vec<usize> = marked.iter().copied().filter(|&i| i >= from).collect();
                proptest::prop_assert_eq!(marked_rows(&past, from).collect::<Vec<_>>(), expect);
                // (Too few words for the rows: none written, the same verdicts.)
                let mut short = [7u64];
                proptest::prop_assert_eq!(rows_past_cheap_tests((&q, &z, &w), tol, given, Some(&mut short)), (bad, first));
                proptest::prop_assert!(q.len() <= 64 || short == [7u64]);
            }
        }
    }

    proptest::proptest! {
        /// The sum in order of entries mostly zero (of either sign) is the plain sum, bit for bit.
        #[test]
        fn sum_in_order_is_the_plain_sum(
            a in proptest::collection::vec(proptest::prop_oneof![
                8 => proptest::strategy::Just(0.0f64),
                2 => proptest::strategy::Just(-0.0f64),
                8 => entry(),
            ], 0..60),
        ) {
            proptest::prop_assert_eq!(sum_in_order(&a).to_bits(), a.iter().sum::<f64>().to_bits());
        }
    }

    proptest::proptest! {
        /// The plain scan's most violated index and value (strictly above
        /// the last, in order) and its negatives of `z`.
        #[test]
        fn most_violated_is_the_plain_scan(
            rows in proptest::collection::vec((proptest::bool::ANY, entry(), entry()), 0..30),
            floor in proptest::prop_oneof![proptest::strategy::Just(0.0f64), 0.0f64..1e3],
        ) {
            let basic: Vec<bool> = rows.iter().map(|r| r.0).collect();
            let z: Vec<f64> = rows.iter().map(|r| r.1).collect();
            let w: Vec<f64> = rows.iter().map(|r| r.2).collect();
            let mut worst = (floor, None);
            for i in 0..rows.len() {
                let v = if basic[i] { -z[i] } else { -w[i] };
                if v > worst.0 {
                    worst = (v, Some(i));
                }
            }
            let negative = z.iter().any(|&v| v < 0.0);
            let (got, neg) = most_violated(&basic, &z, &w, floor);
            proptest::prop_assert_eq!((got.0.to_bits(), got.1, neg), (worst.0.to_bits(), worst.1, negative));
        }
    }

    #[test]
    fn min_ratio_skips_small_pivots_and_clamps_negative_values() {
        let v = [4.0, 1.0, -3.0, 9.0, 2.0];
        let x = [2.0, 1e-20, 1.0, 3.0, 0.5];
        // Row 1 is below the threshold, row 2's value counts as 0.
        let none = (f64::INFINITY, 0.0);
        assert_eq!(min_ratio(&v, &x, 1e-12, none), (0.0, 9.0));
        assert_eq!(min_ratio(&v[3..], &x[3..], 1e-12, none), (3.0, 9.0));
        assert_eq!(min_ratio(&v[..2], &x[..2], 1.0, none), (2.0, 4.0));
        assert_eq!(min_ratio(&v[..2], &x[..2], 5.0, (7.0, 5.0)), (7.0, 5.0));
        assert_eq!(min_ratio(&v[2..3], &x[2..3], 1e-12, none), (0.0, 3.0));
    }

    #[test]
    fn ties_lists_the_rows_reaching_zero_at_the_step() {
        // Ratios 2, -, 0 (clamped), 3, 4, 2, 2.5 at θ = 2 with vtol 0.1.
        let v = [4.0, 1.0, -3.0, 9.0, 2.0, 2.0, 2.5];
        let x = [2.0, 0.0, 1.0, 3.0, 0.5, 1.0, 1.0];
        let mut out = Vec::new();
        ties(&v, &x, 1e-12, 2.0, 0.1, &mut out);
        // Row 2 is far below zero at θ = 2 (−2 ≤ 0.1 counts: it reached zero first).
        assert_eq!(out, vec![0, 2, 5]);
        out.clear();
        ties(&v, &x, 1e-12, 2.0, 0.6, &mut out);
        assert_eq!(out, vec![0, 2, 5, 6]);
    }
}
