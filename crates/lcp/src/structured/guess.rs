//! A guessed basis for a structured contact LCP: projected Gauss–Seidel in
//! body space, read out as a complementary basis for the structured Lemke's
//! warm start. Only a guess: Lemke pivots from it to an exact answer, which
//! alone is judged (never the iterate of the sweeps).
//!
//! The sweeps keep `u = H z` (the bodies' velocity changes), so a row of `w`
//! costs its row of `G` and an update the column of `H`: O(nnz) per sweep,
//! no `M` formed. Each contact is visited as a block (`fn`, then its `fd`
//! projected on the polyhedral cone `Σ fd ≤ μ fn` by scaling, then `λ` from
//! the most opposed direction), because the `λ` row has a zero diagonal and
//! plain PGS cannot move it.
//!
//! The basis read out is the one an exact answer near the iterate would have,
//! contact by contact: `fn` basic when it carries load; a sliding contact
//! (cone full, tangential velocity left) has `λ` and the `fd` of the most
//! opposed direction basic; a sticking one the (at most two) adjacent
//! directions that span its tangential impulse, `w_λ` basic; an unloaded
//! contact whose velocity opposes a direction `λ` with that direction's `fd`
//! (the pairing of `solve_chain::structured_lemke` in the simulator, which keeps the
//! basis regular: opposite directions basic together with `w_λ` would make it
//! singular).

use super::operator::StructuredLcp;
use crate::contact::ContactLayout;

/// Options of the guess.
#[derive(Clone, Debug, PartialEq)]
pub struct GuessOptions {
    /// Sweeps over the contacts. Default 60.
    pub sweeps: usize,
    /// An impulse counts as load above this fraction of the largest normal impulse. Default 1e-6.
    pub load: f64,
    /// A cone counts as full within this fraction of `μ fn`. Default 1e-3.
    pub full: f64,
}

impl Default for GuessOptions {
    fn default() -> Self {
        GuessOptions { sweeps: 60, load: 1e-6, full: 1e-3 }
    }
}

/// The guessed basis (`true`: `z_j` basic) of the contact LCP `op` with
/// layout `lay` (its `K` the cone blocks of `lay` at any scale), from the
/// impulses `z0` when given (e.g. the previous step's, else zeros).
pub fn guess_basis(op: &StructuredLcp, lay: ContactLayout, o: &GuessOptions, z0: Option<&[f64]>) -> Vec<bool> {
    let z = sweep(op, lay, o.sweeps, z0);
    read_basis(op, lay, o, &z)
}

/// `sweeps` block sweeps from `z0` (or 0); returns `z`.
pub fn sweep(op: &StructuredLcp, lay: ContactLayout, sweeps: usize, z0: Option<&[f64]>) -> Vec<f64> {
    let n = op.n();
    let q = op.q();
    let mut z = z0.filter(|z| z.len() == n).map_or_else(|| vec![0.0; n], <[f64]>::to_vec);
    let mut u = vec![0.0; op.p()];
    op.h_times(&z, &mut u);
    // Diagonals of the impulse rows, cone scale s and friction μ per contact.
    let diag: Vec<f64> = (0..lay.impulses()).map(|i| op.at(i, i)).collect();
    let cone: Vec<(f64, f64)> = (0..lay.nc)
        .map(|c| {
            let l = lay.lambda_index(c);
            let s = lay.fd_of(c).next().map_or(1.0, |f| op.at(f, l));
            let s = if s > 0.0 { s } else { 1.0 };
            (s, op.at(l, lay.fn_index(c)) / s)
        })
        .collect();
    let set = |i: usize, v: f64, z: &mut [f64], u: &mut [f64]| {
        let d = v - z[i];
        if d != 0.0 {
            op.h_cols.axpy(i, d, u);
            z[i] = v;
        }
    };
    for _ in 0..sweeps {
        for c in 0..lay.nc {
            let (s, mu) = cone[c];
            let i = lay.fn_index(c);
            if diag[i] > 0.0 {
                let w = q[i] + op.g_rows.dot(i, &u);
                set(i, (z[i] - w / diag[i]).max(0.0), &mut z, &mut u);
            }
            // Friction without λ (w_fd = t + s·λ), then the cone by scaling.
            let mut total = 0.0;
            for f in lay.fd_of(c) {
                if diag[f] > 0.0 {
                    let t = q[f] + op.g_rows.dot(f, &u);
                    set(f, (z[f] - t / diag[f]).max(0.0), &mut z, &mut u);
                }
                total += z[f];
            }
            let cap = mu * z[i];
            if total > cap {
                let r = if total > 0.0 { cap / total } else { 0.0 };
                for f in lay.fd_of(c) {
                    set(f, z[f] * r, &mut z, &mut u);
                }
            }
            let most = lay.fd_of(c).map(|f| -(q[f] + op.g_rows.dot(f, &u))).fold(0.0f64, f64::max);
            z[lay.lambda_index(c)] = most / s;
        }
    }
    z
}

/// The complementary basis an exact answer near `z` would have (module docs).
///
/// Sweeps converge towards an answer that spreads load over redundant
/// contacts (the four corners of a face on a face: four normal rows of rank
/// three), whose basis is singular; Lemke's answers are vertices. So the
/// impulse columns read out are kept only while independent, contact pair by
/// contact pair (rows over the same columns of `G`), largest impulses first:
/// the normals, then the friction; a contact whose normal is dropped is read
/// as unloaded, a sliding one whose direction is dropped as sticking.
pub fn read_basis(op: &StructuredLcp, lay: ContactLayout, o: &GuessOptions, z: &[f64]) -> Vec<bool> {
    let n = op.n();
    let q = op.q();
    let mut u = vec![0.0; op.p()];
    op.h_times(&z[..lay.impulses().min(z.len())], &mut u);
    let top = lay.fn_range().map(|i| z[i]).fold(0.0f64, f64::max);
    let load = o.load * top;
    let k = lay.k;
    // Per contact: the most opposed direction (if the velocity opposes one)
    // and the friction columns an answer near z would have basic.
    let mut opposed = vec![None; lay.nc];
    let mut friction: Vec<Vec<usize>> = vec![Vec::new(); lay.nc];
    let mut sliding = vec![false; lay.nc];
    for c in 0..lay.nc {
        let (i, l, fd) = (lay.fn_index(c), lay.lambda_index(c), lay.fd_of(c));
        let (jmin, tmin) = fd
            .clone()
            .map(|f| q[f] + op.g_rows.dot(f, &u))
            .enumerate()
            .fold((0, f64::INFINITY), |a, (j, v)| if v < a.1 { (j, v) } else { a });
        opposed[c] = (tmin < 0.0).then_some(fd.start + jmin);
        if z[i] <= load {
            continue;
        }
        let mu = op.at(l, i) / op.at(fd.start, l);
        let total: f64 = z[fd.clone()].iter().sum();
        if total >= (1.0 - o.full) * mu * z[i] && z[l] > 0.0 {
            sliding[c] = true;
            friction[c].push(fd.start + jmin);
            continue;
        }
        // Sticking: the two adjacent directions spanning Σ fd_j d_j (directions
        // at angles 2πj/k): the largest fd and its larger neighbour.
        let (jmax, fmax) = (0..k).map(|j| (j, z[fd.start + j])).fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        if fmax > load {
            friction[c].push(fd.start + jmax);
            let (prev, next) = ((jmax + k - 1) % k, (jmax + 1) % k);
            let other = if z[fd.start + prev] > z[fd.start + next] { prev } else { next };
            if z[fd.start + other] > load && k > 2 {
                friction[c].push(fd.start + other);
            }
        }
    }
    // Contacts grouped by the columns of G their normal row touches.
    let mut groups: std::collections::HashMap<Vec<usize>, Vec<usize>> = std::collections::HashMap::new();
    for c in 0..lay.nc {
        let cols: Vec<usize> = op.g_rows.iter(lay.fn_index(c)).map(|(j, _)| j).collect();
        groups.entry(cols).or_default().push(c);
    }
    let mut loaded = vec![false; lay.nc];
    let mut basis = vec![false; n];
    for (cols, mut cs) in groups {
        let mut span = Span::new(cols);
        cs.sort_by(|&a, &b| z[lay.fn_index(b)].total_cmp(&z[lay.fn_index(a)]).then(a.cmp(&b)));
        for &c in &cs {
            let i = lay.fn_index(c);
            if z[i] > load && span.add(op, i) {
                loaded[c] = true;
                basis[i] = true;
            }
        }
        let mut fds: Vec<(usize, usize)> =
            cs.iter().filter(|&&c| loaded[c]).flat_map(|&c| friction[c].iter().map(move |&f| (c, f))).collect();
        fds.sort_by(|a, b| z[b.1].total_cmp(&z[a.1]).then(a.1.cmp(&b.1)));
        for (c, f) in fds {
            if span.add(op, f) {
                basis[f] = true;
                if sliding[c] {
                    basis[lay.lambda_index(c)] = true;
                }
            }
        }
        for &c in cs.iter().filter(|&&c| !loaded[c]) {
            if let Some(f) = opposed[c] {
                basis[f] = true;
                basis[lay.lambda_index(c)] = true;
            }
        }
    }
    basis
}

/// An orthonormal basis of the rows of `G` taken so far over a few columns (Gram–Schmidt).
pub(crate) struct Span {
    cols: Vec<usize>,
    rows: Vec<Vec<f64>>,
}

/// A row is independent of the span when this fraction of its norm is left.
const INDEPENDENT: f64 = 1e-6;

impl Span {
    pub(crate) fn new(cols: Vec<usize>) -> Self {
        Span { cols, rows: Vec::new() }
    }

    /// Takes row `i` of `G` if it is independent of the rows taken; whether it was.
    pub(crate) fn add(&mut self, op: &StructuredLcp, i: usize) -> bool {
        if self.rows.len() >= self.cols.len() {
            return false;
        }
        let mut v = vec![0.0; self.cols.len()];
        for (j, x) in op.g_rows.iter(i) {
            if let Ok(at) = self.cols.binary_search(&j) {
                v[at] = x;
            }
        }
        let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        for _ in 0..2 {
            for r in &self.rows {
                let d: f64 = r.iter().zip(&v).map(|(a, b)| a * b).sum();
                v.iter_mut().zip(r).for_each(|(x, a)| *x -= d * a);
            }
        }
        let left = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(left > INDEPENDENT * norm) {
            return false;
        }
        v.iter_mut().for_each(|x| *x /= left);
        self.rows.push(v);
        true
    }
}
