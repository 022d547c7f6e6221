//! Warm starts per island: the final basis of each island of the previous
//! step, handed to this step's island with **the same dynamic bodies and the
//! same number of contacts** (hence the same LCP size and layout). Any other
//! island (new, split, merged, or with contacts gained or lost) starts cold.
//! For a world whose contacts form one island this is the previous rule (the
//! basis of the previous step's LCP when the size is unchanged). The island's
//! physical impulses are kept with its basis: the start of the guessed basis
//! tried when the previous one fails ([`super::guessed_basis`]).

use crate::islands::Islands;
use crate::pipeline::island::IslandLcp;

const NONE: usize = usize::MAX;

/// The previous step's islands and their bases.
#[derive(Clone, Debug, Default)]
pub struct WarmStarts {
    /// Bodies of every island, island after island, and where each starts.
    bodies: Vec<usize>,
    start: Vec<usize>,
    /// Contacts and final basis per island.
    contacts: Vec<usize>,
    basis: Vec<Option<Vec<bool>>>,
    /// Per island, whether its answer left the warm basis it started from.
    moved: Vec<bool>,
    /// Physical impulses `z` of every island, island after island, and where each starts.
    impulses: Vec<f64>,
    impulse_start: Vec<usize>,
    /// Island of each body (`NONE` if it was in none).
    island_of_body: Vec<usize>,
}

impl WarmStarts {
    /// The previous island with exactly these bodies and `nc` contacts, and
    /// its basis (taken: used once).
    pub fn take(&mut self, bodies: &[usize], nc: usize) -> (Option<usize>, Option<Vec<bool>>) {
        let p = self.matching(bodies, nc);
        (p, p.and_then(|p| self.basis[p].take()))
    }

    /// Whether previous island `p`'s answer left the warm basis it started
    /// from (it pivoted from it; a cold start's pivots do not count): its
    /// contacts were changing, where on most steps of a resting island the
    /// basis stands.
    pub fn moved(&self, p: usize) -> bool {
        self.moved[p]
    }

    /// The physical impulses of previous island `p` (as [`WarmStarts::take`] gave it).
    pub fn impulses(&self, p: usize) -> &[f64] {
        &self.impulses[self.impulse_start[p]..self.impulse_start[p + 1]]
    }

    /// The previous island with exactly these bodies and `nc` contacts.
    fn matching(&self, bodies: &[usize], nc: usize) -> Option<usize> {
        let p = *self.island_of_body.get(*bodies.first()?)?;
        (p != NONE && self.contacts[p] == nc && self.bodies[self.start[p]..self.start[p + 1]] == *bodies).then_some(p)
    }

    /// Forgets every island (a step without contacts).
    pub fn clear(&mut self) {
        for &b in &self.bodies {
            self.island_of_body[b] = NONE;
        }
        self.bodies.clear();
        self.start.clear();
        self.contacts.clear();
        self.basis.clear();
        self.moved.clear();
        self.impulses.clear();
        self.impulse_start.clear();
    }

    /// Keeps this step's islands and moves their final bases out of `solved`.
    pub fn store(&mut self, islands: &Islands, solved: &mut [IslandLcp], body_count: usize) {
        self.clear();
        self.island_of_body.resize(body_count, NONE);
        self.start.push(0);
        self.impulse_start.push(0);
        for (i, isl) in solved.iter_mut().enumerate().take(islands.len()) {
            for &b in islands.bodies_of(i) {
                self.island_of_body[b] = i;
            }
            self.bodies.extend_from_slice(islands.bodies_of(i));
            self.start.push(self.bodies.len());
            self.contacts.push(isl.contacts.len());
            self.moved.push(isl.warmed && isl.sol.as_ref().is_some_and(|s| s.pivots > 0));
            self.basis.push(isl.sol.as_mut().and_then(|s| s.basis.take()));
            self.impulses.extend_from_slice(&isl.z);
            self.impulse_start.push(self.impulses.len());
        }
    }
}
