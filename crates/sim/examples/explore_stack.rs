use sim::lcp::{self, Lcp, LemkeOptions, Method, Residuals};
use sim::scenes::BoxStack;
use sim::{LcpBuffer, WorldParams};
fn main() {
    let mut s = BoxStack::new(3).build(WorldParams::default()).unwrap();
    let buf = LcpBuffer::new();
    s.world.set_sink(Box::new(buf.clone()));
    let mut prev: Option<sim::OwnedLcp> = None;
    for i in 0..400 {
        let st = s.world.step().unwrap().status;
        let caps = buf.drain();
        let cap = caps.into_iter().next().unwrap();
        if st != Some(lcp::Status::Solved) {
            println!("step {i} status {st:?} n={} it={}", cap.q.len(), cap.iterations);
            let l = Lcp::new(cap.m.clone(), cap.q.clone()).unwrap();
            if let Some(p) = &prev {
                let (_, r) = Residuals::compute(&l, &p.z);
                println!("  previous z on this LCP: {r:?}");
                let dm = cap.m.iter().zip(&p.m).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
                let dq = cap.q.iter().zip(&p.q).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
                println!("  |ΔM| {dm:e} |Δq| {dq:e}");
            }
            for (name, m) in [("classic", Method::Lemke(LemkeOptions::classic())), ("noequil", Method::Lemke(LemkeOptions { equilibrate: false, ..Default::default() }))] {
                let sol = lcp::solve(&l, &m);
                println!("  {name}: {:?} res {:e}", sol.status, sol.residuals.natural);
            }
            std::fs::write(format!("/tmp/stack3_step{i}.txt"), format!("{:?}\n{:?}\n", cap.m, cap.q)).unwrap();
            break;
        }
        prev = Some(cap);
    }
}
