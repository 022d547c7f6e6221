//! A box pushed at its centre of mass stays iff F ≤ μmg, with
//! friction exactly −F; above that it slides with a = (F − μmg)/m.

mod common;
use common::*;
use sim::math::Vec3;
use sim::scenes::PushedCube;
use sim::WorldParams;

#[test]
fn source_note_pushed_cube_stays_with_friction_equal_to_the_push() {
    // The source note's case: 1 kg cube, μ = 1, 9.79 N at rest.
    let mut s = PushedCube::new(9.79, 1.0).build(WorldParams::default()).unwrap();
    let h = 1e-3;
    for _ in 0..2000 {
        let r = step_ok(&mut s.world);
        let total = r.total_impulse();
        // Contact impulse on the cube = −push·h horizontally, m g h vertically.
        assert!((total.x + 9.79 * h).abs() < 1e-12, "friction {:e} vs {:e}", total.x, -9.79 * h);
        assert!(total.y.abs() < 1e-12);
        assert!(rel(total.z, G * h) < 1e-12);
        // The load sits on the leading edge (x = +0.5) more than on the trailing one.
        let lead: f64 = (0..r.nc()).filter(|&i| r.contacts[i].point.x > 0.0).map(|i| r.z[i]).sum();
        assert!(lead > 0.5 * G * h);
        assert!(r.lambdas().iter().all(|&l| l.abs() < 1e-9), "λ {:?}", r.lambdas());
    }
    let b = s.world.body(s.body).unwrap();
    assert!(b.velocity().norm() < 1e-9 && b.angular_velocity().norm() < 1e-9);
}

#[test]
fn pushed_box_stays_iff_force_at_most_mu_m_g() {
    for mu in [0.3, 0.7] {
        let f = 0.99 * mu * G;
        let mut s = PushedCube::new(f, mu).build(WorldParams::default()).unwrap();
        for _ in 0..500 {
            let r = step_ok(&mut s.world);
            assert!(rel(-r.total_impulse().x, f * 1e-3) < 1e-9);
        }
        assert!(s.world.body(s.body).unwrap().velocity().norm() < 1e-9);
        // Exactly at μmg it still stays.
        let mut s = PushedCube::new(mu * G, mu).build(WorldParams::default()).unwrap();
        run_ok(&mut s.world, 500);
        assert!(s.world.body(s.body).unwrap().velocity().norm() < 1e-6);
    }
}

#[test]
fn pushed_box_slides_with_a_equal_f_minus_mu_m_g_over_m() {
    for (mu, f) in [(0.3, 1.1 * 0.3 * G), (0.5, 8.0), (0.2, 15.0)] {
        let mut s = PushedCube::new(f, mu).build(WorldParams::default()).unwrap();
        run_ok(&mut s.world, 1000);
        let v = s.world.body(s.body).unwrap().velocity();
        let a = v.x / 1.0;
        let expect = (f - mu * G) / 1.0;
        assert!(rel(a, expect) < 0.01, "μ {mu} F {f}: a {a} vs {expect}");
        assert!(v.y.abs() < 1e-9 && v.z.abs() < 1e-9);
        assert!(s.world.body(s.body).unwrap().angular_velocity().norm() < 1e-9);
    }
    let _ = Vec3::ZERO;
}
