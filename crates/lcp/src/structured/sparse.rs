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
        Self::build(majors, entries.iter().copied(), entries.len(), None)
    }

    /// [`Compressed::new`], with where each entry went: `slots[e]` is the
    /// place in `val` that entry `e` was summed into (for [`Compressed::refill`]).
    pub(crate) fn with_slots(
        majors: usize,
        entries: impl Iterator<Item = (usize, usize, f64)> + Clone,
    ) -> (Self, Vec<usize>) {
        let count = entries.clone().count();
        let mut slots = vec![0; count];
        let c = Self::build(majors, entries, count, Some(&mut slots));
        (c, slots)
    }

    fn build(
        majors: usize,
        entries: impl Iterator<Item = (usize, usize, f64)> + Clone,
        count: usize,
        mut slots: Option<&mut Vec<usize>>,
    ) -> Self {
        let mut start = vec![0; majors + 1];
        entries.clone().for_each(|(a, _, _)| start[a + 1] += 1);
        for a in 0..majors {
            start[a + 1] += start[a];
        }
        let mut next = start.clone();
        let mut sorted = vec![(0, 0.0, 0); count];
        for (e, (a, b, v)) in entries.enumerate() {
            sorted[next[a]] = (b, v, e);
            next[a] += 1;
        }
        let mut ptr = vec![0; majors + 1];
        let (mut idx, mut val) = (Vec::with_capacity(count), Vec::with_capacity(count));
        for a in 0..majors {
            let run = &mut sorted[start[a]..start[a + 1]];
            // Contact LCPs come in order: a check is cheaper than a sort.
            if !run.is_sorted_by_key(|&(b, _, _)| b) {
                run.sort_by_key(|&(b, _, _)| b);
            }
            let mut last = None;
            for &(b, v, e) in run.iter() {
                if last != Some(b) {
                    last = Some(b);
                    idx.push(b);
                    val.push(v);
                } else {
                    *val.last_mut().expect("a previous entry") += v;
                }
                if let Some(s) = slots.as_deref_mut() {
                    s[e] = idx.len() - 1;
                }
            }
            ptr[a + 1] = idx.len();
        }
        Compressed { ptr, idx, val }
    }

    /// New values for the same entries as those `slots` came from
    /// ([`Compressed::with_slots`]): each summed into its place in the order
    /// given, as [`Compressed::new`] sums them, so the result is the same to
    /// the bit. `false` (and the values left partly written) when an entry's
    /// place does not hold its `(major, minor)`: another pattern.
    pub(crate) fn refill(
        &mut self,
        slots: &[usize],
        entries: impl ExactSizeIterator<Item = (usize, usize, f64)>,
    ) -> bool {
        if entries.len() != slots.len() {
            return false;
        }
        self.val.iter_mut().for_each(|v| *v = 0.0);
        for ((a, b, v), &s) in entries.zip(slots) {
            if a + 1 >= self.ptr.len() || !(self.ptr[a]..self.ptr[a + 1]).contains(&s) || self.idx[s] != b {
                return false;
            }
            self.val[s] += v;
        }
        true
    }

    /// The submatrix on the majors `majors` (ascending) and the minors `b`
    /// with `new_minor[b] != usize::MAX`, renumbered `new_minor[b]`
    /// (increasing in `b`): the matrix [`Compressed::new`] builds from the
    /// same entries, to the bit (each kept entry is one already summed, and
    /// the renumbering keeps every major's minors sorted), without sorting.
    pub(crate) fn restricted(&self, majors: impl Iterator<Item = usize>, new_minor: &[usize]) -> Self {
        let mut c = Compressed { ptr: vec![0], idx: Vec::new(), val: Vec::new() };
        for a in majors {
            for (b, v) in self.iter(a) {
                if new_minor[b] != usize::MAX {
                    c.idx.push(new_minor[b]);
                    c.val.push(v);
                }
            }
            c.ptr.push(c.idx.len());
        }
        c
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
