//! Warm starts for large islands whose contacts changed since the previous
//! step (a heap settling: contacts come and go every step, so the island
//! never has the same contacts twice and [`super::warm_starts::WarmStarts`] starts it cold).
//!
//! Each contact of the island takes the basis flags (`fn`, its `fd_j`, `λ`)
//! of the previous step's contact between the same two bodies nearest to it
//! (within [`SAME_CONTACT`] and with a normal within [`SAME_NORMAL`]), each
//! previous contact lending its flags once, nearest pairs first (two contacts
//! with the flags of one made the basis singular on a forming 200-cube heap,
//! n = 8,910, and that step started cold: 7,871 pivots); a new contact starts
//! with every flag off (its `w` basic). The structured Lemke
//! starts from that basis (covering vector `B·1`; cold if it is singular).
//! Only islands of the structured Lemke's size get one: smaller islands keep
//! their previous rule and answers.

use crate::geometry::Contact;
use crate::islands::Islands;
use crate::pipeline::record::StepRecord;
use lcp::contact::ContactLayout;
use std::collections::{HashMap, HashSet};

/// Farthest a contact point may have moved in one step and still be the same contact (m).
const SAME_CONTACT: f64 = 0.02;

/// Least cosine between the normals of the same contact on two steps.
const SAME_NORMAL: f64 = 0.9;

/// Per island, a basis mapped from the previous step's `prev` by contact
/// (`None` for islands under `min_n` unknowns or when `prev` has no basis).
pub(crate) fn by_contact(
    prev: &StepRecord,
    contacts: &[Contact],
    islands: &Islands,
    k: usize,
    min_n: usize,
) -> Vec<Option<Vec<bool>>> {
    let mut out = vec![None; islands.len()];
    let Some(basis) = prev.basis.as_ref().filter(|_| prev.friction_dirs == k) else { return out };
    let old = ContactLayout::new(prev.contacts.len(), k);
    // Built only when some island is large enough (a 1,000-body world of small
    // islands spent 10 % of its step hashing the previous contacts).
    let large = |i: usize| ContactLayout::new(islands.contacts_of(i).len(), k).n() >= min_n;
    if basis.len() != old.n() || !(0..islands.len()).any(large) {
        return out;
    }
    let mut by_pair: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    for (c, ct) in prev.contacts.iter().enumerate() {
        by_pair.entry((ct.body_a, ct.body_b)).or_default().push(c);
    }
    for (i, slot) in out.iter_mut().enumerate() {
        if !large(i) {
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
        let mut mask = vec![false; lay.n()];
        let (mut new_done, mut old_used) = (vec![false; ids.len()], HashSet::new());
        for (_, c, p) in pairs {
            if new_done[c] || !old_used.insert(p) {
                continue;
            }
            new_done[c] = true;
            mask[lay.fn_index(c)] = basis[old.fn_index(p)];
            for j in 0..k {
                mask[lay.fd_index(c, j)] = basis[old.fd_index(p, j)];
            }
            mask[lay.lambda_index(c)] = basis[old.lambda_index(p)];
        }
        *slot = Some(mask);
    }
    out
}
