//! Contact islands. Separate stacks are solved
//! independently (bit for bit as in worlds of their own), the thread count
//! changes nothing, islands match a connected-components reference on random
//! scenes, and each island's LCP is captured with its island id.

use sim::math::Vec3;
use sim::scenes::{BoxPile, SplitMix64};
use sim::{BodyDesc, LcpBuffer, World, WorldParams};
use std::collections::BTreeSet;

/// Ground plus, for each x in `towers`, a tower of `n` unit cubes at (x, 0).
fn towers(params: WorldParams, xs: &[f64], n: usize) -> World {
    let mut w = World::new(params).unwrap();
    w.add_ground(0.5).unwrap();
    for &x in xs {
        for i in 0..n {
            let p = Vec3::new(x, 0.0, 0.5 + i as f64);
            // A small push so that the towers do something other than rest.
            w.add_body(BodyDesc::cuboid(Vec3::splat(0.5)).position(p).velocity(Vec3::new(0.01 * x, 0.0, 0.0))).unwrap();
        }
    }
    w
}

#[test]
fn two_separate_stacks_step_exactly_as_two_worlds() {
    let (n, steps) = (3, 200);
    let mut both = towers(WorldParams::default(), &[0.0, 4.0], n);
    let mut alone = [towers(WorldParams::default(), &[0.0], n), towers(WorldParams::default(), &[4.0], n)];
    for step in 0..steps {
        let r = both.step().unwrap().clone();
        assert_eq!(r.islands.len(), 2, "step {step}");
        let mut pivots = 0;
        for (t, w) in alone.iter_mut().enumerate() {
            let ra = w.step().unwrap();
            assert_eq!(ra.islands.len(), 1);
            // Same LCP outcome per island …
            assert_eq!(r.islands[t].lcp_size, ra.lcp_size);
            assert_eq!(r.islands[t].pivots, ra.pivots, "step {step}, tower {t}");
            assert_eq!(r.islands[t].status, ra.status.unwrap());
            pivots += ra.pivots;
            // … the same impulses in the global contact order …
            let ids = r.island_contacts_of(t);
            for (c, &g) in ids.iter().enumerate() {
                assert_eq!(r.z[g].to_bits(), ra.z[c].to_bits(), "step {step}, tower {t}, fn of contact {c}");
                assert_eq!(r.lambdas()[g].to_bits(), ra.lambdas()[c].to_bits());
                assert_eq!(r.friction_of(g), ra.friction_of(c));
            }
            // … and the same bodies, bit for bit.
            for i in 0..n {
                assert_eq!(both.bodies()[1 + t * n + i], w.bodies()[1 + i], "step {step}, tower {t}, box {i}");
            }
        }
        assert_eq!(r.pivots, pivots);
    }
}

#[test]
fn thread_count_changes_no_bit() {
    // 25 towers of ≥ 12 contacts: Σ n² ≥ 25·120² = 360k, enough work for threads to start.
    let pile = BoxPile { nx: 5, ny: 5, nz: 3, yaw: 0.3, seed: 5, ..Default::default() };
    let run = |threads: usize| {
        let mut s = pile.build(WorldParams { threads, ..Default::default() }).unwrap();
        let traj = s.world.run(30).unwrap();
        (traj, s.world.last_record().clone())
    };
    let (t1, r1) = run(1);
    assert!(t1.islands.iter().all(|&i| i == 25), "25 towers, 25 islands: {:?}", &t1.islands[..5]);
    assert!(t1.lcp_size.iter().all(|&n| n >= 25 * 120));
    for threads in [2, 3, 0] {
        let (t, r) = run(threads);
        assert_eq!(t, t1, "threads {threads}");
        assert_eq!(r, r1, "threads {threads}");
    }
}

#[test]
fn every_island_lcp_is_captured_with_its_island() {
    let mut w = towers(WorldParams::default(), &[0.0, 3.0, 6.0], 2);
    let buf = LcpBuffer::new();
    w.set_sink(Box::new(buf.clone()));
    let r = w.step().unwrap().clone();
    let got = buf.drain();
    assert_eq!(got.len(), 3);
    for (i, l) in got.iter().enumerate() {
        assert_eq!((l.island, l.step), (i, 0));
        assert_eq!(l.contacts, r.island_contacts_of(i).len());
        assert_eq!(l.q.len(), r.islands[i].lcp_size);
    }
}

/// Connected components of the dynamic bodies through the contacts (BFS),
/// as sorted body sets, each with the sorted contacts it owns.
fn components(w: &World) -> Vec<(Vec<usize>, Vec<usize>)> {
    let bodies = w.bodies();
    let dynamic = |b: usize| !bodies[b].is_static();
    let mut seen = vec![false; bodies.len()];
    let mut out = Vec::new();
    for start in (0..bodies.len()).filter(|&b| dynamic(b)) {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        let (mut comp, mut queue) = (BTreeSet::from([start]), vec![start]);
        while let Some(b) = queue.pop() {
            for c in w.contacts() {
                let other = match (c.body_a == b, c.body_b == b) {
                    (true, _) => c.body_b,
                    (_, true) => c.body_a,
                    _ => continue,
                };
                if dynamic(other) && !seen[other] {
                    seen[other] = true;
                    comp.insert(other);
                    queue.push(other);
                }
            }
        }
        let contacts: Vec<usize> = (0..w.contacts().len())
            .filter(|&k| [w.contacts()[k].body_a, w.contacts()[k].body_b].iter().any(|b| comp.contains(b)))
            .collect();
        if !contacts.is_empty() {
            out.push((comp.into_iter().collect(), contacts));
        }
    }
    // Islands are numbered by their first contact.
    out.sort_by_key(|(_, c)| c[0]);
    out
}

#[test]
fn islands_are_the_connected_components_on_random_scenes() {
    let mut multi = 0;
    for seed in 0..40u64 {
        let mut rng = SplitMix64(seed);
        let mut w = World::new(WorldParams::default()).unwrap();
        w.add_ground(0.5).unwrap();
        let n = 10 + (seed as usize % 4) * 15;
        let extent = rng.uniform(3.0, 8.0);
        for _ in 0..n {
            let p = Vec3::new(rng.uniform(0.0, extent), rng.uniform(0.0, extent), rng.uniform(0.2, 2.5));
            let desc = if rng.next_f64() < 0.5 {
                BodyDesc::cuboid(Vec3::new(rng.uniform(0.2, 0.6), rng.uniform(0.2, 0.6), rng.uniform(0.2, 0.6)))
            } else {
                BodyDesc::sphere(rng.uniform(0.2, 0.6))
            };
            w.add_body(desc.position(p).orientation(rng.rotation()).fixed(rng.next_f64() < 0.1)).unwrap();
        }
        w.forces_stage().unwrap();
        w.detect();
        w.islands();
        let isl = w.contact_islands();
        let expect = components(&w);
        assert_eq!(isl.len(), expect.len(), "seed {seed}");
        for (i, (bodies, contacts)) in expect.iter().enumerate() {
            assert_eq!(isl.bodies_of(i), &bodies[..], "seed {seed}, island {i}");
            assert_eq!(isl.contacts_of(i), &contacts[..], "seed {seed}, island {i}");
        }
        multi += usize::from(expect.iter().any(|(b, _)| b.len() > 2));
    }
    // Not vacuous: many scenes have islands of several bodies.
    assert!(multi > 20, "{multi}");
}
