//! Height fields (static terrain on a grid) against analytic answers: a box
//! on a flat field rests as on the plane, a ball rolls down a field ramp at
//! 5/7 g sin θ across the grid's cells, bad grids are refused naming the field.

mod common;
use common::*;
use sim::math::Vec3;
use sim::{BodyDesc, SimError, World, WorldParams};

/// A field of `nrow × ncol` heights `f(x, y)` over [−hx, hx] × [−hy, hy].
fn field(nrow: usize, ncol: usize, hx: f64, hy: f64, f: impl Fn(f64, f64) -> f64) -> BodyDesc {
    let mut h = Vec::with_capacity(nrow * ncol);
    for r in 0..nrow {
        for c in 0..ncol {
            let x = -hx + 2.0 * hx * c as f64 / (ncol - 1) as f64;
            let y = -hy + 2.0 * hy * r as f64 / (nrow - 1) as f64;
            h.push(f(x, y));
        }
    }
    BodyDesc::heightfield(nrow, ncol, hx, hy, &h).unwrap()
}

#[test]
fn box_rests_on_a_flat_heightfield_as_on_the_plane() {
    let rest = |ground: Option<BodyDesc>| {
        let mut w = World::new(WorldParams::default()).unwrap();
        match ground {
            Some(g) => w.add_body(g.mu(0.5)).unwrap(),
            None => w.add_ground(0.5).unwrap(),
        };
        let start = Vec3::new(0.3, -0.2, 0.25);
        let id = w.add_body(BodyDesc::cuboid(Vec3::new(0.5, 0.4, 0.25)).mass(2.0).position(start)).unwrap();
        let r = run_ok(&mut w, 1000);
        let b = w.body(id).unwrap();
        ((b.position() - start).norm(), b.velocity().norm(), r.z[..r.contacts.len()].iter().sum::<f64>())
    };
    let (drift, speed, load) = rest(Some(field(9, 11, 3.0, 2.0, |_, _| 0.0)));
    let (pdrift, _, pload) = rest(None);
    eprintln!("field: drift {drift:e}, speed {speed:e}, load {load}; plane: drift {pdrift:e}, load {pload}");
    assert!(drift < 1e-9 && speed < 1e-9, "drift {drift:e} m, speed {speed:e}");
    assert!(rel(load, 2.0 * G * 1e-3) < 1e-9 && rel(load, pload) < 1e-9);
}

#[test]
fn ball_rolls_down_a_heightfield_ramp_at_five_sevenths_g_sin_theta() {
    let (angle, mu, steps) = (20.0f64, 0.5, 1000);
    let (th, expect) = (angle.to_radians(), 5.0 / 7.0 * G * angle.to_radians().sin());
    // Ramps falling towards +x and towards +y (rows and columns the right way round),
    // 13 × 7 points over 6 × 4 m (or 4 × 6): the ball crosses cells and their diagonals.
    for along_y in [false, true] {
        let (ramp, n, down, across) = if along_y {
            let ramp = field(13, 7, 2.0, 3.0, |_, y| -y * th.tan());
            (ramp, Vec3::new(0.0, th.sin(), th.cos()), Vec3::new(0.0, th.cos(), -th.sin()), Vec3::X)
        } else {
            let ramp = field(7, 13, 3.0, 2.0, |x, _| -x * th.tan());
            (ramp, Vec3::new(th.sin(), 0.0, th.cos()), Vec3::new(th.cos(), 0.0, -th.sin()), Vec3::Y)
        };
        let mut w = World::new(WorldParams::default()).unwrap();
        w.add_body(ramp.mu(mu)).unwrap();
        let start = down * -2.0 + across * 0.3 + n * 0.5;
        let id = w.add_body(BodyDesc::sphere(0.5).position(start).mu(mu)).unwrap();
        run_ok(&mut w, steps);
        let b = w.body(id).unwrap();
        let a = b.velocity().dot(down) / (steps as f64 * w.params().dt);
        eprintln!("along y {along_y}: a {a}, expected {expect}, rel {:e}", rel(a, expect));
        assert!(rel(a, expect) < 1e-2, "a {a} vs 5/7 g sin θ = {expect}");
        let p = b.position() - across * 0.3;
        assert!(
            (p.dot(n) - 0.5).abs() < 1e-6 && (b.position() - start).dot(across).abs() < 1e-9,
            "left the ramp: {p:?}"
        );
    }
}

#[test]
fn bad_heightfields_are_refused_naming_the_field() {
    let err = |r: Result<BodyDesc, SimError>| r.err().map(|e| e.to_string()).unwrap_or_default();
    assert!(err(BodyDesc::heightfield(1, 3, 1.0, 1.0, &[0.0; 3])).starts_with("nrow must be at least 2, got 1"));
    assert!(err(BodyDesc::heightfield(2, 2, 1.0, 1.0, &[0.0; 3]))
        .contains("heights has 3 values, expected nrow × ncol = 4"));
    assert!(err(BodyDesc::heightfield(2, 2, -1.0, 1.0, &[0.0; 4])).contains("half_x must be > 0, got -1"));
    assert!(err(BodyDesc::heightfield(2, 2, 1.0, 1.0, &[0.0, f64::NAN, 0.0, 0.0])).contains("heights must be finite"));
    assert!(err(BodyDesc::heightfield(usize::MAX, 2, 1.0, 1.0, &[])).contains("more than the limit"));
    // Static only.
    let mut w = World::new(WorldParams::default()).unwrap();
    let e = w.add_body(field(2, 2, 1.0, 1.0, |_, _| 0.0).fixed(false)).unwrap_err();
    assert_eq!(e.to_string(), "a hfield must be static");
}
