//! Warm starts for islands whose contacts changed since the previous step
//! (a pile forming: contacts come and go every step, so the island never has
//! the same contacts twice and [`super::warm_starts::WarmStarts`] would start
//! it cold).
//!
//! Each contact of the island takes the basis flags (`fn`, its `fd_j`, `λ`)
//! and the impulses of the previous step's contact between the same two
//! bodies nearest to it (within [`SAME_CONTACT`] and with a normal within
//! [`SAME_NORMAL`]), each previous contact lending its flags once, nearest
//! pairs first (two contacts with the flags of one made the basis singular on
//! a forming 200-cube heap, n = 8,910, and that step started cold: 7,871
//! pivots); a new contact starts with every flag off (its `w` basic) and no
//! impulse. The chain takes that basis as the previous one (the structured
//! Lemke starts from it with covering vector `B·1`, cold if it is singular)
//! and the impulses as the start of its guessed basis.
//!
//! Every island of two or more dynamic bodies gets one; single bodies keep
//! the rule of `warm_starts` (same contact count, else cold), so their
//! answers, the cube corpus's, stay as they were. Measured on a pour of 45
//! cubes (`cube_pour(45, 0)`, 3,000 steps) against mapping only islands of
//! the structured Lemke's size: 545,000 → 344,149 pivots in all, 127 → 21
//! pivots a step while the first cubes land (steps 750–1,000).

use crate::geometry::Contact;
use crate::islands::Islands;
use crate::pipeline::record::StepRecord;
use lcp::contact::ContactLayout;
use std::collections::{HashMap, HashSet};

/// Farthest a contact point may have moved in one step and still be the same contact (m).
const SAME_CONTACT: f64 = 0.02;

/// Least cosine between the normals of the same contact on two steps.
const SAME_NORMAL: f64 = 0.9;

/// Per island, a basis and physical impulses mapped from the previous step's
/// `prev` by contact (`None` for single bodies, for islands not `wanted`, or
/// when `prev` has no basis). Each island's mapping depends only on `prev`
/// and its own contacts, so leaving out an island changes no other's.
pub(crate) fn by_contact(
    prev: &StepRecord,
    contacts: &[Contact],
    islands: &Islands,
    k: usize,
    wanted: impl Fn(usize) -> bool,
) -> Vec<Option<(Vec<bool>, Vec<f64>)>> {
    // Only coupled islands that want one (a world of single bodies, or of
    // islands warm-started by `warm_starts`, need not hash the previous contacts).
    let coupled = |i: usize| islands.bodies_of(i).len() >= 2 && wanted(i);
    if !(0..islands.len()).any(coupled) {
        return Vec::new();
    }
    let mut out = vec![None; islands.len()];
    let Some(basis) = prev.basis.as_ref().filter(|_| prev.friction_dirs == k) else { return out };
    let old = ContactLayout::new(prev.contacts.len(), k);
    // Impulses are mapped only from a record that holds them all.
    let z_old = (prev.z.len() == old.n()).then_some(&prev.z[..]);
    if basis.len() != old.n() {
        return out;
    }
    let mut by_pair: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    for (c, ct) in prev.contacts.iter().enumerate() {
        by_pair.entry((ct.body_a, ct.body_b)).or_default().push(c);
    }
    for (i, slot) in out.iter_mut().enumerate() {
        if !coupled(i) {
            continue;
        }
        let ids = islands.contacts_of(i);
        let lay = ContactLayout::new(ids.len(), k);
        // Candidate pairs (new contact, previous contact) by distance; each
        // previous contact serves one new contact at most.
        let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
        for (c, &g) in ids.iter().enumerate() {
            let ct = &contacts[g];
            for &p in by_pair.get(&(ct.body_a, ct.body_b)).map_or(&[][..], |v| &v[..]) {
                let d = (prev.contacts[p].point - ct.point).norm();
                if d <= SAME_CONTACT && prev.contacts[p].normal.dot(ct.normal) >= SAME_NORMAL {
                    pairs.push((d, c, p));
                }
            }
        }
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        let (mut mask, mut z) = (vec![false; lay.n()], vec![0.0; lay.n()]);
        let (mut new_done, mut old_used) = (vec![false; ids.len()], HashSet::new());
        for (_, c, p) in pairs {
            if new_done[c] || !old_used.insert(p) {
                continue;
            }
            new_done[c] = true;
            // fn, each fd_j and λ of the previous contact, in this island's layout.
            let unknowns = std::iter::once((lay.fn_index(c), old.fn_index(p)))
                .chain((0..k).map(|j| (lay.fd_index(c, j), old.fd_index(p, j))))
                .chain(std::iter::once((lay.lambda_index(c), old.lambda_index(p))));
            for (new, was) in unknowns {
                mask[new] = basis[was];
                z[new] = z_old.map_or(0.0, |zo| zo[was]);
            }
        }
        *slot = Some((mask, z));
    }
    out
}
