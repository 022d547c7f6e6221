//! Stage `detect`: the broad phase (`broad_phase`: sweep and prune on
//! bounding spheres and boxes) gives the pairs, then the narrow-phase file of each
//! pair's shapes gives its contacts.
//!
//! Pairs of primitives (box, sphere, plane) go to their hand-written routine;
//! every pair with a capsule, cylinder, convex hull or mesh goes to parry's
//! contact manifolds (`geometry::parry_pair`), with A the lower index unless
//! that is the plane or mesh (always B). `LCPSIM_NARROW=parry` in the
//! environment sends the primitives' pairs to parry as well (to compare the
//! two; read once per process).
//!
//! Pairs that the bodies' collision filters keep apart
//! (`CollisionFilter`, MuJoCo's contype/conaffinity rule), pairs excluded one
//! by one (`World::exclude_pair`) and bodies joined by a joint are skipped
//! before the narrow phase, unless `World::add_contact_pair` made the pair
//! touch (then past the bits and the exclusions, never past a joint).
//!
//! Each contact gets its bodies in the order of the pair function (A = the
//! first shape of its name; for two shapes of one kind, the lower index), the
//! combined μ (the contact pair's own, if it is one), and its friction tangent: the plane's own tangent (downhill on
//! a slope) when B is a plane, otherwise the world x axis projected into the
//! tangent plane (y when the normal is close to x).

use crate::broad_phase::{reach, PairMargin};
use crate::geometry::{
    box_box, box_plane, fixed_tangent, parry_pair, sphere_box, sphere_plane, sphere_sphere, Contact, ParryScratch,
    Shape,
};
use std::sync::OnceLock;

/// Whether `LCPSIM_NARROW=parry` sends the primitives' pairs to parry too.
fn parry_for_primitives() -> bool {
    static ON: OnceLock<bool> = OnceLock::new();
    *ON.get_or_init(|| std::env::var("LCPSIM_NARROW").is_ok_and(|v| v == "parry"))
}
use crate::world::World;

impl World {
    /// Stage `detect`: fills the contact list for this step (broad phase,
    /// then the narrow phase of each pair, in pair order).
    pub fn detect(&mut self) {
        // Called on its own, before this step's `forces_stage`: run it first.
        if !self.free_velocities_ready() {
            self.ws.contacts.clear();
            return;
        }
        let h = self.h();
        let ws = &mut self.ws;
        ws.contacts.clear();
        // How far each body can move within the step (for the velocity margins).
        ws.reach.clear();
        ws.reach.extend(self.bodies.iter().enumerate().map(|(k, b)| reach(b, ws.v_free[k], ws.w_free[k])));
        let margin =
            PairMargin { base: self.params.margin, h, reach: self.params.velocity_margin.then_some(&ws.reach[..]) };
        ws.broad.find(&self.bodies, &margin);
        let mut scratch = ParryScratch::default();
        let all_parry = parry_for_primitives();
        for &(i, j) in ws.broad.pairs() {
            let (bi, bj) = (&self.bodies[i], &self.bodies[j]);
            // A contact pair's own μ; such a pair touches past the bits and the exclusions.
            let pair_mu = self.contact_pairs.get(i, j).copied();
            // MuJoCo's contype/conaffinity rule: a filtered pair gets no contact; nor do
            // pairs excluded one by one.
            if pair_mu.is_none() && (!bi.filter.collides_with(&bj.filter) || self.excluded.contains(i, j)) {
                continue;
            }
            // Bodies joined by a joint do not collide.
            if ws.joints.joins(i, j) {
                continue;
            }
            let margin = margin.of(i, j);
            // Narrow phase, with A/B in the order of the pair function.
            ws.geom.clear();
            let (a, b) = match (&bi.shape, &bj.shape) {
                (Shape::Plane(_), Shape::Plane(_)) => continue,
                (x, y) if all_parry || !(x.is_primitive() && y.is_primitive()) => {
                    if x.is_static_only() && y.is_static_only() {
                        continue;
                    }
                    let (a, b) = if x.is_static_only() { (j, i) } else { (i, j) };
                    let (ba, bb) = (&self.bodies[a], &self.bodies[b]);
                    parry_pair(
                        &ba.shape,
                        &ba.placement(),
                        &bb.shape,
                        &bb.placement(),
                        margin,
                        &mut scratch,
                        &mut ws.geom,
                    );
                    (a, b)
                }
                (Shape::Box(x), Shape::Plane(p)) => {
                    box_plane(x, &bi.placement(), p, margin, &mut ws.geom);
                    (i, j)
                }
                (Shape::Plane(p), Shape::Box(x)) => {
                    box_plane(x, &bj.placement(), p, margin, &mut ws.geom);
                    (j, i)
                }
                (Shape::Sphere { radius }, Shape::Plane(p)) => {
                    sphere_plane(bi.position, *radius, p, margin, &mut ws.geom);
                    (i, j)
                }
                (Shape::Plane(p), Shape::Sphere { radius }) => {
                    sphere_plane(bj.position, *radius, p, margin, &mut ws.geom);
                    (j, i)
                }
                (Shape::Sphere { radius: ra }, Shape::Sphere { radius: rb }) => {
                    sphere_sphere(bi.position, *ra, bj.position, *rb, margin, &mut ws.geom);
                    (i, j)
                }
                (Shape::Sphere { radius }, Shape::Box(x)) => {
                    sphere_box(bi.position, *radius, x, &bj.placement(), margin, &mut ws.geom);
                    (i, j)
                }
                (Shape::Box(x), Shape::Sphere { radius }) => {
                    sphere_box(bj.position, *radius, x, &bi.placement(), margin, &mut ws.geom);
                    (j, i)
                }
                (Shape::Box(x), Shape::Box(y)) => {
                    box_box(x, &bi.placement(), y, &bj.placement(), margin, &mut ws.geom);
                    (i, j)
                }
                _ => continue,
            };
            if ws.geom.is_empty() {
                continue;
            }
            let mu = self
                .params
                .mu_override
                .or(pair_mu)
                .unwrap_or_else(|| self.params.mu_combine.combine(self.bodies[a].mu, self.bodies[b].mu));
            let plane_tangent = match &self.bodies[b].shape {
                Shape::Plane(p) => Some(p.friction_tangent()),
                _ => None,
            };
            for g in &ws.geom {
                let tangent = plane_tangent.unwrap_or_else(|| fixed_tangent(g.normal));
                ws.contacts.push(Contact {
                    body_a: a,
                    body_b: b,
                    point: g.point,
                    normal: g.normal,
                    gap: g.gap,
                    mu,
                    tangent,
                });
            }
        }
        // contacts whose normal the joints hold are not the LCP's; the joint
        // limits this step may reach, as frictionless contacts
        let ws = &mut self.ws;
        ws.joints.drop_held_contacts(&mut ws.contacts, &self.bodies, &ws.inv_inertia);
        // each patch with torsional friction, one more contact
        ws.torsion.push_patches(&mut ws.contacts, &self.bodies);
        self.joint_limit_contacts();
    }

    /// The pairs the last `detect` handed to the narrow phase, sorted by `(i, j)`.
    pub fn broad_pairs(&self) -> &[(usize, usize)] {
        self.ws.broad.pairs()
    }
}
