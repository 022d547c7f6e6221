use sim::scenes::*;
fn main() {
    let mut s = cube_on_slope(30.0, 0.7).unwrap();
    for i in 0..5 {
        let r = s.world.step().unwrap();
        println!("{i} nc={} n={} st={:?} it={} res={:e} fn={:?} lam={:?}", r.nc(), r.lcp_size, r.status, r.iterations, r.residuals.natural, r.normal_impulses(), r.lambdas());
    }
    let b = s.world.body(s.body).unwrap();
    println!("{:?} {:?}", b.position(), b.velocity());
    let mut s = cube_on_slope(40.0, 0.5).unwrap();
    let t = s.world.run(1000).unwrap();
    let b = s.world.body(s.body).unwrap();
    let th = 40f64.to_radians();
    let a = 9.81 * (th.sin() - 0.5 * th.cos());
    println!("slide: pos {:?} vel {:?} |v|={} expect {} failures {}", b.position(), b.velocity(), b.velocity().norm(), a * 1.0, t.failures());
}
