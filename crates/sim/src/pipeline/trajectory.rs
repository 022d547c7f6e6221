//! `Trajectory`: the state after every step of a run, in flat arrays ready
//! for numpy (`(steps, bodies, 3)` and `(steps, bodies, 4)`, row-major).

use crate::math::{Quat, Vec3};
use crate::world::World;
use lcp::Status;

/// States and per-step LCP statistics of a run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trajectory {
    /// Bodies per step.
    pub bodies: usize,
    /// Time after each step (s).
    pub time: Vec<f64>,
    /// Positions, `(steps, bodies, 3)`.
    pub position: Vec<f64>,
    /// Orientations (w, x, y, z), `(steps, bodies, 4)`.
    pub orientation: Vec<f64>,
    /// Linear velocities, `(steps, bodies, 3)`.
    pub velocity: Vec<f64>,
    /// Angular velocities, `(steps, bodies, 3)`.
    pub angular_velocity: Vec<f64>,
    /// Contacts per step.
    pub contacts: Vec<usize>,
    /// LCP size per step (0 without contacts).
    pub lcp_size: Vec<usize>,
    /// Solver status per step (`None` without contacts).
    pub status: Vec<Option<Status>>,
    /// Pivots / iterations per step.
    pub iterations: Vec<usize>,
    /// Natural residual `‖min(z, w)‖∞` in physical units per step.
    pub residual: Vec<f64>,
}

impl Trajectory {
    pub fn with_capacity(steps: usize, bodies: usize) -> Self {
        Trajectory {
            bodies,
            time: Vec::with_capacity(steps),
            position: Vec::with_capacity(steps * bodies * 3),
            orientation: Vec::with_capacity(steps * bodies * 4),
            velocity: Vec::with_capacity(steps * bodies * 3),
            angular_velocity: Vec::with_capacity(steps * bodies * 3),
            contacts: Vec::with_capacity(steps),
            lcp_size: Vec::with_capacity(steps),
            status: Vec::with_capacity(steps),
            iterations: Vec::with_capacity(steps),
            residual: Vec::with_capacity(steps),
        }
    }

    /// Appends the world's current state and its last step record.
    pub fn push(&mut self, world: &World) {
        self.time.push(world.time());
        for b in world.bodies() {
            self.position.extend_from_slice(&b.position().to_array());
            self.orientation.extend_from_slice(&b.orientation().to_array());
            self.velocity.extend_from_slice(&b.velocity().to_array());
            self.angular_velocity.extend_from_slice(&b.angular_velocity().to_array());
        }
        let r = world.last_record();
        self.contacts.push(r.nc());
        self.lcp_size.push(r.lcp_size);
        self.status.push(r.status);
        self.iterations.push(r.iterations);
        self.residual.push(r.residuals.natural);
    }

    /// Steps recorded.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// Position of `body` after step `step`.
    pub fn position_at(&self, step: usize, body: usize) -> Vec3 {
        let i = (step * self.bodies + body) * 3;
        Vec3::new(self.position[i], self.position[i + 1], self.position[i + 2])
    }

    /// Orientation of `body` after step `step`.
    pub fn orientation_at(&self, step: usize, body: usize) -> Quat {
        let i = (step * self.bodies + body) * 4;
        Quat::new(self.orientation[i], self.orientation[i + 1], self.orientation[i + 2], self.orientation[i + 3])
    }

    /// Velocity of `body` after step `step`.
    pub fn velocity_at(&self, step: usize, body: usize) -> Vec3 {
        let i = (step * self.bodies + body) * 3;
        Vec3::new(self.velocity[i], self.velocity[i + 1], self.velocity[i + 2])
    }

    /// Steps whose LCP was not solved.
    pub fn failures(&self) -> usize {
        self.status.iter().filter(|s| matches!(s, Some(st) if *st != Status::Solved)).count()
    }
}
