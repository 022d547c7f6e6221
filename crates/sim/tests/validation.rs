//! Bad parameters are errors naming the field and the value (Python turns them into ValueError).

use sim::math::{Quat, Vec3};
use sim::scenes::{BoxStack, CubeOnSlope};
use sim::{BodyDesc, BodyId, ConeScale, Plane, Restitution, SimError, Stabilization, World, WorldParams};

fn world() -> World {
    World::new(WorldParams::default()).unwrap()
}

#[test]
fn world_parameters_are_validated() {
    let bad = |p: WorldParams| World::new(p).unwrap_err();
    assert_eq!(bad(WorldParams { dt: 0.0, ..Default::default() }), SimError::NotPositive { field: "dt", value: 0.0 });
    assert_eq!(
        bad(WorldParams { dt: -1e-3, ..Default::default() }),
        SimError::NotPositive { field: "dt", value: -1e-3 }
    );
    assert!(matches!(bad(WorldParams { dt: f64::NAN, ..Default::default() }), SimError::NonFinite { field: "dt", .. }));
    assert!(matches!(
        bad(WorldParams { gravity: Vec3::new(0.0, f64::INFINITY, 0.0), ..Default::default() }),
        SimError::NonFinite { field: "gravity", .. }
    ));
    for k in [0, 1, 3, 7] {
        assert_eq!(bad(WorldParams { friction_dirs: k, ..Default::default() }), SimError::FrictionDirs { k });
    }
    assert!(World::new(WorldParams { friction_dirs: 2, ..Default::default() }).is_ok());
    assert_eq!(
        bad(WorldParams { cone_scale: ConeScale::Value(0.0), ..Default::default() }),
        SimError::NotPositive { field: "cone_scale", value: 0.0 }
    );
    assert_eq!(
        bad(WorldParams { margin: -1.0, ..Default::default() }),
        SimError::Negative { field: "margin", value: -1.0 }
    );
    assert!(matches!(
        bad(WorldParams { stabilization: Stabilization { erp: 1.5, ..Default::default() }, ..Default::default() }),
        SimError::OutOfRange { field: "stabilization.erp", .. }
    ));
    assert!(matches!(
        bad(WorldParams { restitution: Restitution::new(-0.1), ..Default::default() }),
        SimError::OutOfRange { field: "restitution", .. }
    ));
    assert_eq!(
        bad(WorldParams { mu_override: Some(-0.5), ..Default::default() }),
        SimError::Negative { field: "mu_override", value: -0.5 }
    );
    // set_params validates and leaves the world unchanged on error.
    let mut w = world();
    assert!(w.set_params(WorldParams { dt: 0.0, ..Default::default() }).is_err());
    assert_eq!(w.params().dt, 1e-3);
}

#[test]
fn bodies_are_validated() {
    let mut w = world();
    let unit = Vec3::splat(0.5);
    assert_eq!(
        w.add_box(unit, -1.0, Vec3::ZERO, 0.5).unwrap_err(),
        SimError::NotPositive { field: "mass", value: -1.0 }
    );
    assert_eq!(w.add_box(unit, 0.0, Vec3::ZERO, 0.5).unwrap_err(), SimError::NotPositive { field: "mass", value: 0.0 });
    assert_eq!(w.add_box(unit, 1.0, Vec3::ZERO, -0.1).unwrap_err(), SimError::Negative { field: "mu", value: -0.1 });
    assert_eq!(
        w.add_box(Vec3::new(0.5, 0.0, 0.5), 1.0, Vec3::ZERO, 0.5).unwrap_err(),
        SimError::NotPositive { field: "half_extents.y", value: 0.0 }
    );
    assert_eq!(
        w.add_box(Vec3::new(0.5, 0.5, -2.0), 1.0, Vec3::ZERO, 0.5).unwrap_err(),
        SimError::NotPositive { field: "half_extents.z", value: -2.0 }
    );
    assert_eq!(
        w.add_sphere(0.0, 1.0, Vec3::ZERO, 0.5).unwrap_err(),
        SimError::NotPositive { field: "radius", value: 0.0 }
    );
    assert!(matches!(
        w.add_sphere(0.1, 1.0, Vec3::new(f64::NAN, 0.0, 0.0), 0.5).unwrap_err(),
        SimError::NonFinite { field: "position", .. }
    ));
    assert!(matches!(
        w.add_sphere(0.1, f64::INFINITY, Vec3::ZERO, 0.5).unwrap_err(),
        SimError::NonFinite { field: "mass", .. }
    ));
    // Quaternions: normalized when possible, rejected when zero.
    assert_eq!(
        w.add_body(BodyDesc::cuboid(unit).orientation(Quat::new(0.0, 0.0, 0.0, 0.0))).unwrap_err(),
        SimError::ZeroLength { field: "orientation" }
    );
    let id = w.add_body(BodyDesc::cuboid(unit).orientation(Quat::new(2.0, 0.0, 0.0, 0.0))).unwrap();
    assert_eq!(w.body(id).unwrap().orientation(), Quat::IDENTITY);
    assert_eq!(
        w.set_orientation(id, Quat::new(0.0, 0.0, 0.0, 0.0)).unwrap_err(),
        SimError::ZeroLength { field: "orientation" }
    );
    // Inertia must be symmetric positive definite.
    let bad_inertia = sim::math::Mat3::diagonal(Vec3::new(1.0, -1.0, 1.0));
    assert!(matches!(
        w.add_body(BodyDesc::cuboid(unit).inertia(bad_inertia)).unwrap_err(),
        SimError::BadInertia { .. }
    ));
    // Planes: static only, non-zero normal.
    assert_eq!(w.add_body(BodyDesc::plane(Plane::ground()).fixed(false)).unwrap_err(), SimError::DynamicPlane);
    assert_eq!(Plane::new(Vec3::ZERO, 1.0).unwrap_err(), SimError::ZeroLength { field: "normal" });
    assert!(matches!(
        Plane::slope_deg(90.0, sim::Downhill::PlusX).unwrap_err(),
        SimError::OutOfRange { field: "angle", .. }
    ));
    // Nothing invalid was added.
    assert_eq!(w.body_count(), 1);
}

#[test]
fn unknown_and_static_bodies_are_errors() {
    let mut w = world();
    let ground = w.add_ground(0.5).unwrap();
    let cube = w.add_box(Vec3::splat(0.5), 1.0, Vec3::new(0.0, 0.0, 0.5), 0.5).unwrap();
    let missing = BodyId(7);
    assert_eq!(w.body(missing).unwrap_err(), SimError::UnknownBody { index: 7, bodies: 2 });
    assert_eq!(w.apply_force(missing, Vec3::X, None).unwrap_err(), SimError::UnknownBody { index: 7, bodies: 2 });
    assert_eq!(w.set_velocity(missing, Vec3::X).unwrap_err(), SimError::UnknownBody { index: 7, bodies: 2 });
    assert_eq!(w.apply_force(ground, Vec3::X, None).unwrap_err(), SimError::StaticBody { index: 0 });
    assert_eq!(w.set_velocity(ground, Vec3::X).unwrap_err(), SimError::StaticBody { index: 0 });
    assert!(matches!(
        w.apply_force(cube, Vec3::new(f64::NAN, 0.0, 0.0), None).unwrap_err(),
        SimError::NonFinite { field: "force", .. }
    ));
    assert!(matches!(
        w.apply_force(cube, Vec3::X, Some(Vec3::splat(f64::INFINITY))).unwrap_err(),
        SimError::NonFinite { field: "point", .. }
    ));
    assert!(matches!(w.set_mu(cube, -1.0).unwrap_err(), SimError::Negative { field: "mu", .. }));
    assert!(w.applied_forces().is_empty());
}

#[test]
fn scene_parameters_are_validated() {
    assert!(matches!(
        CubeOnSlope::new(30.0, -0.5).build(WorldParams::default()).unwrap_err(),
        SimError::Negative { field: "mu", .. }
    ));
    assert!(matches!(
        CubeOnSlope::new(f64::NAN, 0.5).build(WorldParams::default()).unwrap_err(),
        SimError::NonFinite { field: "angle_deg", .. }
    ));
    let mut c = CubeOnSlope::new(30.0, 0.5);
    c.size = 0.0;
    assert!(matches!(c.build(WorldParams::default()).unwrap_err(), SimError::NotPositive { field: "size", .. }));
    assert!(BoxStack::new(0).build(WorldParams::default()).is_err());
    assert!(sim::scenes::ball_drop(1.0, 1.5).is_err());
}

#[test]
fn errors_display_field_and_value() {
    let e = World::new(WorldParams { dt: -0.5, ..Default::default() }).unwrap_err();
    assert_eq!(e.to_string(), "dt must be > 0, got -0.5");
    assert_eq!(SimError::FrictionDirs { k: 3 }.to_string(), "friction_dirs must be even and >= 2, got 3");
}

#[test]
fn forces_at_a_point_give_torque_and_can_be_cleared() {
    let mut w = World::new(WorldParams { gravity: Vec3::ZERO, ..Default::default() }).unwrap();
    let b = w.add_box(Vec3::splat(0.5), 2.0, Vec3::ZERO, 0.5).unwrap();
    // 1 N along x at the body point (0, 0.5, 0): torque (0, 0.5, 0) × (1, 0, 0) = (0, 0, −0.5).
    w.apply_force(b, Vec3::X, Some(Vec3::new(0.0, 0.5, 0.0))).unwrap();
    w.apply_torque(b, Vec3::new(0.0, 0.0, 0.25)).unwrap();
    w.step().unwrap();
    let body = w.body(b).unwrap();
    let i_zz = 2.0 / 3.0 * 0.5;
    assert!((body.velocity() - Vec3::new(0.5e-3, 0.0, 0.0)).norm() < 1e-15);
    assert!((body.angular_velocity() - Vec3::new(0.0, 0.0, -0.25e-3 / i_zz)).norm() < 1e-15);
    w.clear_forces();
    let v = w.body(b).unwrap().velocity();
    w.step().unwrap();
    assert_eq!(w.body(b).unwrap().velocity(), v);
}

#[test]
fn world_and_records_can_move_between_threads() {
    fn send<T: Send>() {}
    send::<World>();
    send::<sim::StepRecord>();
    send::<sim::Trajectory>();
    send::<sim::OwnedLcp>();
    send::<sim::scenes::Scene>();
}

#[test]
fn a_cloned_world_steps_identically_and_has_no_sink() {
    let mut s = CubeOnSlope::new(40.0, 0.5).build(WorldParams::default()).unwrap();
    s.world.set_sink(Box::new(sim::LcpBuffer::new()));
    s.world.run(10).unwrap();
    let mut copy = s.world.clone();
    assert!(copy.take_sink().is_none());
    s.world.run(10).unwrap();
    copy.run(10).unwrap();
    assert_eq!(s.world.bodies(), copy.bodies());
    assert_eq!(s.world.time(), copy.time());
    assert_eq!(s.world.last_record(), copy.last_record());
}

/// The stages are public: `detect` called on its own (before `forces_stage`
/// has computed free velocities) must not panic.
#[test]
fn detect_alone_does_not_panic() {
    let mut s = sim::scenes::CubeOnSlope::new(30.0, 0.7).build(sim::WorldParams::default()).unwrap();
    s.world.detect();
    s.world.assemble();
    assert!(s.world.step().is_ok());
}
