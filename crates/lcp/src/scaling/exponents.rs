//! The binary exponents of `M` and one Ruiz round's row and column maxima
//! over them.
//!
//! The exponents are i16, rows padded to whole 256-bit registers
//! ([`LANES`] entries) with [`ZERO_EXPONENT`], which never wins a maximum.
//! With AVX2 a row converts eight entries at a time, and a round keeps the
//! column maxima of up to four registers (n ≤ 64) in registers across all
//! rows; without it, plain loops the compiler vectorizes as it can. Both
//! give the same integers, which the tests check.

/// i16 lanes in a 256-bit register; padded rows hold a multiple of them.
pub(super) const LANES: usize = 16;

/// Exponent standing for an exact zero: below any real one by more than
/// `4·MAX_EXPONENT`, and far enough from `i16::MIN` that adding two scale
/// exponents cannot overflow.
pub(super) const ZERO_EXPONENT: i16 = -16_000;

/// `floor(log2 |v|)` from the bit pattern (subnormals count as −1023);
/// `ZERO_EXPONENT` for zero and for non-finite values. Reads only the upper
/// 32 bits, so that a slice of them converts in 32-bit SIMD lanes: a
/// subnormal below 2⁻¹⁰⁴⁴ (upper mantissa bits all zero) counts as zero.
#[inline]
pub(super) fn exponent(v: f64) -> i16 {
    let hi = (v.to_bits() >> 32) as u32;
    let biased = (hi >> 20) & 0x7ff;
    if (hi & 0x7fff_ffff == 0) | (biased == 0x7ff) {
        ZERO_EXPONENT
    } else {
        biased as i16 - 1023
    }
}

/// `dst[j] = exponent(src[j])`.
pub(super) fn of_row(src: &[f64], dst: &mut [i16]) {
    assert_eq!(src.len(), dst.len());
    let mut done = 0;
    #[cfg(target_arch = "x86_64")]
    if is_x86_feature_detected!("avx2") {
        // SAFETY: AVX2 is present; `of_row` reads and writes whole chunks of 8
        // within the equal lengths asserted above.
        done = unsafe { avx2::of_row(src, dst) };
    }
    for (d, &v) in dst[done..].iter_mut().zip(&src[done..]) {
        *d = exponent(v);
    }
}

/// What one Ruiz round reads: the `n × stride` exponent matrix `ex`
/// (row-major), the row exponents `r` (`n = row_exp.len()`), the column
/// exponents `c` (`stride = col_exp.len()`) and `floor`, the maximum of nothing.
#[derive(Clone, Copy, Debug)]
pub(super) struct Round<'a> {
    pub ex: &'a [i16],
    pub row_exp: &'a [i16],
    pub col_exp: &'a [i16],
    pub floor: i16,
}

/// `row_max[i] = r_i + max_j (e_ij + c_j)` and
/// `col_max[j] = max_i (e_ij + c_j + r_i)` for every padded column `j` of the
/// round `rd`. The sums must fit in i16.
pub(super) fn maxima(rd: Round<'_>, row_max: &mut [i16], col_max: &mut [i16]) {
    let (n, stride) = (rd.row_exp.len(), rd.col_exp.len());
    assert!(stride % LANES == 0 && rd.ex.len() == n * stride && row_max.len() == n && col_max.len() == stride);
    #[cfg(target_arch = "x86_64")]
    if is_x86_feature_detected!("avx2") {
        // SAFETY: AVX2 is present; the asserts above bound every access.
        unsafe {
            match stride / LANES {
                1 => avx2::held::<1>(rd, row_max, col_max),
                2 => avx2::held::<2>(rd, row_max, col_max),
                3 => avx2::held::<3>(rd, row_max, col_max),
                4 => avx2::held::<4>(rd, row_max, col_max),
                _ => avx2::any(rd, row_max, col_max),
            }
        }
        return;
    }
    portable(rd, row_max, col_max);
}

fn portable(rd: Round<'_>, row_max: &mut [i16], col_max: &mut [i16]) {
    let Round { ex, row_exp, col_exp, floor } = rd;
    col_max.fill(floor);
    for ((row, &ri), rmax_out) in ex.chunks_exact(col_exp.len()).zip(row_exp).zip(row_max.iter_mut()) {
        let mut rmax = floor;
        for ((&e, &cj), cmax) in row.iter().zip(col_exp).zip(col_max.iter_mut()) {
            let v = e + cj;
            rmax = rmax.max(v);
            *cmax = (*cmax).max(v + ri);
        }
        *rmax_out = rmax + ri;
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::{Round, LANES, ZERO_EXPONENT};
    use std::arch::x86_64::*;

    /// Converts the leading multiple of 8 entries (see `super::exponent`);
    /// returns how many.
    ///
    /// # Safety
    /// AVX2 must be available and `dst` as long as `src`.
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn of_row(src: &[f64], dst: &mut [i16]) -> usize {
        let (low, no_exp, inf) = (_mm256_set1_epi32(0x7ff), _mm256_set1_epi32(0x7fff_ffff), _mm256_set1_epi32(0x7ff));
        let (bias, zero) = (_mm256_set1_epi32(1023), _mm256_set1_epi32(ZERO_EXPONENT as i32));
        // Dwords (pairs of i16) of `packs` back in entry order (see below).
        let order = _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7);
        let chunks = src.len() / 8;
        for c in 0..chunks {
            let a = _mm256_loadu_pd(src.as_ptr().add(8 * c));
            let b = _mm256_loadu_pd(src.as_ptr().add(8 * c + 4));
            // Upper halves of entries [0 1 4 5 | 2 3 6 7].
            let hi = _mm256_castps_si256(_mm256_shuffle_ps(_mm256_castpd_ps(a), _mm256_castpd_ps(b), 0b11_01_11_01));
            let biased = _mm256_and_si256(_mm256_srli_epi32(hi, 20), low);
            let none = _mm256_or_si256(
                _mm256_cmpeq_epi32(_mm256_and_si256(hi, no_exp), _mm256_setzero_si256()),
                _mm256_cmpeq_epi32(biased, inf),
            );
            let e = _mm256_blendv_epi8(_mm256_sub_epi32(biased, bias), zero, none);
            // i16 pairs [0 1, 4 5, ·, · | 2 3, 6 7, ·, ·] → [0 1, 2 3, 4 5, 6 7, …].
            let packed = _mm256_permutevar8x32_epi32(_mm256_packs_epi32(e, e), order);
            _mm_storeu_si128(dst.as_mut_ptr().add(8 * c).cast(), _mm256_castsi256_si128(packed));
        }
        8 * chunks
    }

    /// Largest of the 16 lanes.
    #[target_feature(enable = "avx2")]
    fn hmax(v: __m256i) -> i16 {
        let mut m = _mm_max_epi16(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
        m = _mm_max_epi16(m, _mm_shuffle_epi32(m, 0b01_00_11_10));
        m = _mm_max_epi16(m, _mm_shuffle_epi32(m, 0b10_11_00_01));
        m = _mm_max_epi16(m, _mm_srli_epi32(m, 16));
        _mm_cvtsi128_si32(m) as i16
    }

    /// `B` registers per row: column exponents and maxima stay in registers.
    ///
    /// # Safety
    /// AVX2 must be available and the slices sized as `maxima` asserts.
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn held<const B: usize>(rd: Round<'_>, row_max: &mut [i16], col_max: &mut [i16]) {
        let Round { ex, row_exp, col_exp, floor } = rd;
        let lowest = _mm256_set1_epi16(floor);
        let c: [__m256i; B] = std::array::from_fn(|b| _mm256_loadu_si256(col_exp.as_ptr().add(LANES * b).cast()));
        let mut cmax = [lowest; B];
        for ((row, &ri), rmax_out) in ex.chunks_exact(LANES * B).zip(row_exp).zip(row_max.iter_mut()) {
            let r = _mm256_set1_epi16(ri);
            let mut rmax = lowest;
            for b in 0..B {
                let v = _mm256_add_epi16(_mm256_loadu_si256(row.as_ptr().add(LANES * b).cast()), c[b]);
                rmax = _mm256_max_epi16(rmax, v);
                cmax[b] = _mm256_max_epi16(cmax[b], _mm256_add_epi16(v, r));
            }
            *rmax_out = hmax(rmax) + ri;
        }
        for (b, m) in cmax.iter().enumerate() {
            _mm256_storeu_si256(col_max.as_mut_ptr().add(LANES * b).cast(), *m);
        }
    }

    /// Any padded width: column maxima in memory.
    ///
    /// # Safety
    /// As [`held`].
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn any(rd: Round<'_>, row_max: &mut [i16], col_max: &mut [i16]) {
        let Round { ex, row_exp, col_exp, floor } = rd;
        let lowest = _mm256_set1_epi16(floor);
        col_max.fill(floor);
        for ((row, &ri), rmax_out) in ex.chunks_exact(col_exp.len()).zip(row_exp).zip(row_max.iter_mut()) {
            let r = _mm256_set1_epi16(ri);
            let mut rmax = lowest;
            for ((e, c), m) in
                row.chunks_exact(LANES).zip(col_exp.chunks_exact(LANES)).zip(col_max.chunks_exact_mut(LANES))
            {
                let v = _mm256_add_epi16(_mm256_loadu_si256(e.as_ptr().cast()), _mm256_loadu_si256(c.as_ptr().cast()));
                rmax = _mm256_max_epi16(rmax, v);
                let old = _mm256_loadu_si256(m.as_ptr().cast());
                _mm256_storeu_si256(m.as_mut_ptr().cast(), _mm256_max_epi16(old, _mm256_add_epi16(v, r)));
            }
            *rmax_out = hmax(rmax) + ri;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_row_converts_as_each_entry_does() {
        let specials = [
            0.0,
            -0.0,
            1.0,
            -1.5,
            f64::MIN_POSITIVE,
            f64::MIN_POSITIVE / 2.0,
            f64::from_bits(1),
            -f64::from_bits(1 << 33),
            f64::MAX,
            -f64::MAX,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            1e-300,
            3e300,
            0.75,
            -2.0f64.powi(-1022),
        ];
        let mut x = 99u64;
        let src: Vec<f64> = (0..203)
            .map(|k| {
                x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                if k % 3 == 0 {
                    specials[(x >> 40) as usize % specials.len()]
                } else {
                    f64::from_bits(x)
                }
            })
            .collect();
        for len in [0, 1, 7, 8, 9, 16, 40, 203] {
            let mut dst = vec![0i16; len];
            of_row(&src[..len], &mut dst);
            let want: Vec<i16> = src[..len].iter().map(|&v| exponent(v)).collect();
            assert_eq!(dst, want, "len {len}");
        }
    }

    /// Every path against the plain loop, on widths 1–6 registers.
    #[test]
    fn every_path_gives_the_plain_maxima() {
        let mut x = 12345u64;
        let mut next = |span: u64| {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((x >> 33) % span) as i16
        };
        for n in [1usize, 7, 16, 17, 40, 64, 65, 100] {
            let stride = n.next_multiple_of(LANES);
            let floor = -16_000;
            let ex: Vec<i16> = (0..n * stride)
                .map(|k| if k % stride >= n || next(7) == 0 { floor } else { next(2100) - 1075 })
                .collect();
            let row_exp: Vec<i16> = (0..n).map(|_| next(2001) - 1000).collect();
            let col_exp: Vec<i16> = (0..stride).map(|j| if j < n { next(2001) - 1000 } else { 0 }).collect();
            let (mut r1, mut c1) = (vec![0; n], vec![0; stride]);
            let (mut r2, mut c2) = (vec![0; n], vec![0; stride]);
            let rd = Round { ex: &ex, row_exp: &row_exp, col_exp: &col_exp, floor };
            portable(rd, &mut r1, &mut c1);
            maxima(rd, &mut r2, &mut c2);
            assert_eq!((&r1, &c1), (&r2, &c2), "n = {n}");
            // And against the definition.
            for i in 0..n {
                let want = (0..stride).map(|j| ex[i * stride + j] + col_exp[j]).max().unwrap() + row_exp[i];
                assert_eq!(r1[i], want);
            }
        }
    }
}
