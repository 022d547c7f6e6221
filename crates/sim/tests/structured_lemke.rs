//! The structured Lemke (`lcp::structured`) on contact LCPs
//! of the simulator, against the dense assembly and the dense Lemke.

mod common;

use common::settled;
use sim::contact::body_factors::structured_lcp;
use sim::generate::{hard_corpus_item, HardScene};
use sim::lcp::accept::accepts;
use sim::lcp::structured::{self, StructuredOptions};
use sim::lcp::{lemke, LemkeOptions, Status};
use sim::scenes::{BoxPile, BoxStack, CubeHeap};
use sim::{ConeScale, World, WorldParams};

fn worlds(params: &WorldParams) -> Vec<World> {
    vec![
        settled(BoxPile::default().build(params.clone()).unwrap().world, 30),
        settled(BoxStack::new(4).build(params.clone()).unwrap().world, 30),
        settled(CubeHeap { walls: true, ..CubeHeap::new(6, 1) }.build(params.clone()).unwrap().world, 400),
    ]
}

#[test]
fn the_structured_operator_is_the_dense_lcp() {
    for scale in [ConeScale::Unscaled, ConeScale::Value(1e-3)] {
        let params = WorldParams { cone_scale: scale, ..Default::default() };
        for w in worlds(&params) {
            let dense = w.contact_lcp().to_lcp().unwrap();
            let op = structured_lcp(w.contact_lcp(), w.contact_lcp().scale()).unwrap();
            let m = op.to_dense();
            let mmax = dense.m().iter().fold(0.0f64, |a, v| a.max(v.abs()));
            assert_eq!(m.q(), dense.q());
            for (k, (a, b)) in m.m().iter().zip(dense.m()).enumerate() {
                assert!((a - b).abs() <= 1e-13 * mmax, "M[{k}]: structured {a:e}, dense {b:e}");
            }
        }
    }
}

#[test]
fn structured_lemke_solves_what_dense_lemke_solves() {
    let params = WorldParams::default();
    let mut solved = 0;
    for w in worlds(&params) {
        let op = structured_lcp(w.contact_lcp(), w.contact_lcp().scale()).unwrap();
        let dense = w.contact_lcp().to_lcp().unwrap();
        let sol = structured::solve(&op, &StructuredOptions::default(), None);
        let reference = lemke::solve(&dense, &LemkeOptions::default());
        assert!(reference.ok());
        assert_eq!(sol.status, Status::Solved, "n {}: {:?}", op.n(), sol.residuals);
        // The answer solves the dense LCP by the dense rule.
        assert!(accepts(&dense, &sol.z, &dense.w_of(&sol.z), 1e-9), "n {}", op.n());
        solved += 1;
    }
    assert_eq!(solved, 3);
}

#[test]
fn structured_lemke_on_the_hard_corpus() {
    let (mut ok, mut total) = (0, 0);
    for i in 0..200 {
        let (kind, k, seed) = hard_corpus_item(7, i);
        let scene = HardScene::random(kind, k, seed);
        let c = scene.scene.assemble(scene.k, 1.0);
        let op = structured_lcp(&c, 1.0).unwrap();
        let dense = c.to_lcp().unwrap();
        let sol = structured::solve(&op, &StructuredOptions::default(), None);
        total += 1;
        if sol.status == Status::Solved {
            assert!(accepts(&dense, &sol.z, &dense.w_of(&sol.z), 1e-9), "{i}: accepted by the structured rule only");
            ok += 1;
        }
    }
    eprintln!("hard corpus: structured Lemke solved {ok} of {total}");
    assert!(ok * 10 >= total * 9, "{ok} of {total}");
}
