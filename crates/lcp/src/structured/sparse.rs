//! Compressed sparse storage by major index (rows of a CSR, columns of a CSC).

/// Entries grouped by major index: `idx[ptr[a]..ptr[a + 1]]` are the minor
/// indices of major index `a` (sorted, repeated entries summed), `val` their values.
#[derive(Clone, Debug, Default)]
pub(crate) struct Compressed {
    ptr: Vec<usize>,
    idx: Vec<usize>,
    val: Vec<f64>,
}

impl Compressed {
    /// From `(major, minor, value)` entries over `majors` major indices.
    ///
    /// A counting sort by major index, then each major's entries sorted by
    /// minor index, both stable: repeated entries are summed in the order
    /// given, as a stable sort of all entries would (a sort of all entries
    /// took 8 % of a 52-cube heap's solve, n = 1,440).
    pub(crate) fn new(majors: usize, entries: &[(usize, usize, f64)]) -> Self {
        let mut start = vec![0; majors + 1];
        entries.iter().for_each(|&(a, _, _)| start[a + 1] += 1);
        for a in 0..majors {
            start[a + 1] += start[a];
        }
        let mut next = start.clone();
        let mut sorted = vec![(0, 0.0); entries.len()];
        for &(a, b, v) in entries {
            sorted[next[a]] = (b, v);
            next[a] += 1;
        }
        let mut ptr = vec![0; majors + 1];
        let (mut idx, mut val) = (Vec::with_capacity(entries.len()), Vec::with_capacity(entries.len()));
        for a in 0..majors {
            let run = &mut sorted[start[a]..start[a + 1]];
            // Contact LCPs come in order: a check is cheaper than a sort.
            if !run.is_sorted_by_key(|&(b, _)| b) {
                run.sort_by_key(|&(b, _)| b);
            }
            let mut last = None;
            for &(b, v) in run.iter() {
                if last == Some(b) {
                    *val.last_mut().expect("a previous entry") += v;
                    continue;
                }
                last = Some(b);
                idx.push(b);
                val.push(v);
            }
            ptr[a + 1] = idx.len();
        }
        Compressed { ptr, idx, val }
    }

    /// `(minor, value)` of major index `a`.
    #[inline]
    pub(crate) fn iter(&self, a: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let r = self.ptr[a]..self.ptr[a + 1];
        self.idx[r.clone()].iter().copied().zip(self.val[r].iter().copied())
    }

    /// Entry `(a, b)` (0 if absent), by binary search.
    pub(crate) fn get(&self, a: usize, b: usize) -> f64 {
        let r = self.ptr[a]..self.ptr[a + 1];
        self.idx[r.clone()].binary_search(&b).map_or(0.0, |k| self.val[r.start + k])
    }

    /// `Σ_b A[a, b] x_b`.
    #[inline]
    pub(crate) fn dot(&self, a: usize, x: &[f64]) -> f64 {
        self.iter(a).map(|(b, v)| v * x[b]).sum()
    }

    /// `y_b += s·A[a, b]`.
    #[inline]
    pub(crate) fn axpy(&self, a: usize, s: f64, y: &mut [f64]) {
        for (b, v) in self.iter(a) {
            y[b] += s * v;
        }
    }
}
