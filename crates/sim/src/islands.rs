//! Contact islands: the dynamic bodies linked through contacts, each with its
//! own LCP (contacts of different islands share no dynamic body, so their
//! rows of `A = J M⁻¹ Jᵀ` do not couple and the LCPs are independent).
//!
//! Union-find over the bodies, rebuilt every step from the contacts: a
//! contact between two dynamic bodies joins their sets; a static body joins
//! nothing (a contact with the ground belongs to its dynamic body's island
//! only). Islands are numbered in the order of their first contact, and each
//! island keeps its contacts in the global contact order, so a world whose
//! contacts form one island has exactly the LCP of the whole step. Bodies
//! without contacts are in no island. Allocation-free once warm.

use crate::dynamics::Body;
use crate::geometry::Contact;

const NONE: usize = usize::MAX;

/// The islands of one step: contacts and dynamic bodies grouped per island.
#[derive(Clone, Debug, Default)]
pub struct Islands {
    ready: bool,
    /// Union-find parent per body.
    parent: Vec<usize>,
    /// Island of each root body (`NONE` for roots without contacts).
    island_of_root: Vec<usize>,
    /// Island per contact.
    contact_island: Vec<usize>,
    /// Contacts grouped by island (global indices, ascending), and where each island starts.
    contacts: Vec<usize>,
    contact_start: Vec<usize>,
    /// Dynamic bodies grouped by island (ascending), and where each island starts.
    bodies: Vec<usize>,
    body_start: Vec<usize>,
    /// Scratch: island per body (`NONE` for static bodies and bodies without contacts).
    body_key: Vec<usize>,
}

impl Islands {
    /// Whether [`Islands::build`] ran since the last [`Islands::invalidate`].
    pub fn is_ready(&self) -> bool {
        self.ready
    }

    /// Marks the islands stale (the contacts changed).
    pub fn invalidate(&mut self) {
        self.ready = false;
    }

    /// Number of islands.
    pub fn len(&self) -> usize {
        self.contact_start.len().saturating_sub(1)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Global indices of island `i`'s contacts, ascending.
    pub fn contacts_of(&self, i: usize) -> &[usize] {
        &self.contacts[self.contact_start[i]..self.contact_start[i + 1]]
    }

    /// Island `i`'s dynamic bodies, ascending.
    pub fn bodies_of(&self, i: usize) -> &[usize] {
        &self.bodies[self.body_start[i]..self.body_start[i + 1]]
    }

    /// Where island `i`'s contacts lie in [`Islands::all_contacts`].
    pub fn contact_range(&self, i: usize) -> std::ops::Range<usize> {
        self.contact_start[i]..self.contact_start[i + 1]
    }

    /// Where island `i`'s bodies lie in [`Islands::all_bodies`].
    pub fn body_range(&self, i: usize) -> std::ops::Range<usize> {
        self.body_start[i]..self.body_start[i + 1]
    }

    /// Every island's contacts, island after island.
    pub fn all_contacts(&self) -> &[usize] {
        &self.contacts
    }

    /// Every island's bodies, island after island.
    pub fn all_bodies(&self) -> &[usize] {
        &self.bodies
    }

    /// The island of each contact.
    pub fn contact_islands(&self) -> &[usize] {
        &self.contact_island
    }

    fn find(&mut self, mut b: usize) -> usize {
        while self.parent[b] != b {
            // Path halving.
            self.parent[b] = self.parent[self.parent[b]];
            b = self.parent[b];
        }
        b
    }

    /// Groups `contacts` (between `bodies`) into islands.
    pub fn build(&mut self, contacts: &[Contact], bodies: &[Body]) {
        self.build_linked(contacts, bodies, &[]);
    }

    /// As [`Islands::build`], with `links` (pairs of dynamic bodies joined
    /// by a joint) joining islands as contacts do. An island still needs a
    /// contact: bodies linked only by joints are in no island.
    pub fn build_linked(&mut self, contacts: &[Contact], bodies: &[Body], links: &[(usize, usize)]) {
        let nb = bodies.len();
        self.parent.clear();
        self.parent.extend(0..nb);
        for &(a, b) in links {
            let (ra, rb) = (self.find(a), self.find(b));
            let (lo, hi) = (ra.min(rb), ra.max(rb));
            self.parent[hi] = lo;
        }
        // Join the dynamic bodies of every contact (the lower root wins: deterministic).
        for c in contacts {
            if bodies[c.body_a].is_static || bodies[c.body_b].is_static {
                continue;
            }
            let (ra, rb) = (self.find(c.body_a), self.find(c.body_b));
            let (lo, hi) = (ra.min(rb), ra.max(rb));
            self.parent[hi] = lo;
        }
        // Number the islands in the order of their first contact.
        self.island_of_root.clear();
        self.island_of_root.resize(nb, NONE);
        self.contact_island.clear();
        let mut count = 0;
        for c in contacts {
            let body = if bodies[c.body_a].is_static { c.body_b } else { c.body_a };
            let root = self.find(body);
            if self.island_of_root[root] == NONE {
                self.island_of_root[root] = count;
                count += 1;
            }
            self.contact_island.push(self.island_of_root[root]);
        }
        // Contacts and bodies per island: stable counting sorts.
        counting_sort(&self.contact_island, count, &mut self.contact_start, &mut self.contacts);
        self.body_key.clear();
        for (b, body) in bodies.iter().enumerate() {
            let island = if body.is_static {
                NONE
            } else {
                {
                    let root = self.find(b);
                    self.island_of_root[root]
                }
            };
            self.body_key.push(island);
        }
        counting_sort(&self.body_key, count, &mut self.body_start, &mut self.bodies);
        self.ready = true;
    }
}

/// `start[i]..start[i + 1]` of `out` lists, ascending, the indices `k` with
/// `key[k] == i` (keys `≥ count` are left out).
fn counting_sort(key: &[usize], count: usize, start: &mut Vec<usize>, out: &mut Vec<usize>) {
    start.clear();
    start.resize(count + 1, 0);
    for &i in key.iter().filter(|&&i| i < count) {
        start[i + 1] += 1;
    }
    for i in 0..count {
        start[i + 1] += start[i];
    }
    out.clear();
    out.resize(start[count], 0);
    // Fill with a moving cursor per island, kept in start[i] and restored after.
    for (k, &i) in key.iter().enumerate().filter(|(_, &i)| i < count) {
        out[start[i]] = k;
        start[i] += 1;
    }
    for i in (1..=count).rev() {
        start[i] = start[i - 1];
    }
    start[0] = 0;
}
