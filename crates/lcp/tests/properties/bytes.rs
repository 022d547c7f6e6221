//! Reads numbers out of fuzzer bytes: shared by the property modules of
//! `lcp` (this directory) and `sim` (`crates/sim/tests/properties/`), and so by
//! the fuzz targets that include them.

/// Reads numbers out of fuzzer bytes; past the end every read is 0.
pub struct Bytes<'a> {
    data: &'a [u8],
    at: usize,
}

impl<'a> Bytes<'a> {
    pub fn new(data: &'a [u8]) -> Self {
        Bytes { data, at: 0 }
    }

    pub fn u8(&mut self) -> u8 {
        let b = self.data.get(self.at).copied().unwrap_or(0);
        self.at += 1;
        b
    }

    pub fn bool(&mut self) -> bool {
        self.u8() & 1 == 1
    }

    /// One of `choices`.
    pub fn pick<T: Copy>(&mut self, choices: &[T]) -> T {
        choices[self.u8() as usize % choices.len()]
    }

    /// A float biased towards what breaks numerics: small integers and
    /// sixteenths, every magnitude from 1e-20 to 1e20, the extremes of f64,
    /// and now and then raw bits (NaN, ∞, subnormals).
    pub fn f64(&mut self) -> f64 {
        let sel = self.u8();
        match sel % 16 {
            0 => 0.0,
            1 => 1.0,
            2 => -1.0,
            3..=8 => self.u8() as i8 as f64 / 16.0,
            9..=11 => {
                let m = self.u8() as i8 as f64;
                m * 10f64.powi(self.u8() as i32 % 41 - 20)
            }
            12 => self.pick(&[1e-300, -1e-300, f64::MIN_POSITIVE, 5e-324, -5e-324]),
            13 => self.pick(&[1e300, -1e300, f64::MAX, f64::MIN, 1e154]),
            14 => 1.0 + (self.u8() as i8 as f64) * f64::EPSILON,
            _ => self.raw_f64(),
        }
    }

    /// Eight bytes as an f64's bits (NaN, ∞ and subnormals included).
    pub fn raw_f64(&mut self) -> f64 {
        let mut raw = [0u8; 8];
        raw.iter_mut().for_each(|b| *b = self.u8());
        f64::from_le_bytes(raw)
    }
}
