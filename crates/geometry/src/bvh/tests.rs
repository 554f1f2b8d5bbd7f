//! BVH queries against brute force on seeded random sets.

use glam::DVec3;

use super::Bvh;
use crate::aabb::Aabb;
use crate::testing::Rng;

fn random_boxes(rng: &mut Rng, n: usize, spread: f64, size: f64) -> Vec<Aabb> {
    (0..n)
        .map(|_| {
            let c = DVec3::new(
                rng.range(-spread, spread),
                rng.range(-spread, spread),
                rng.range(-spread, spread),
            );
            let h = DVec3::new(
                rng.range(0.0, size),
                rng.range(0.0, size),
                rng.range(0.0, size),
            );
            Aabb::new(c - h, c + h)
        })
        .collect()
}

/// The sets every query is checked on: random, many identical boxes, a flat
/// set (all z = 0, zero thickness), points on a line, and some empty boxes.
fn test_sets() -> Vec<(&'static str, Vec<Aabb>)> {
    let mut rng = Rng::new(42);
    let random = random_boxes(&mut rng, 700, 1.0, 0.05);
    let mut identical = vec![Aabb::new(DVec3::ZERO, DVec3::ONE); 300];
    identical.extend(random_boxes(&mut rng, 50, 2.0, 0.1));
    let flat: Vec<Aabb> = random_boxes(&mut rng, 500, 1.0, 0.03)
        .into_iter()
        .map(|b| Aabb::new(b.min.with_z(0.0), b.max.with_z(0.0)))
        .collect();
    let line: Vec<Aabb> = (0..400)
        .map(|i| Aabb::from_point(DVec3::new((i % 37) as f64 * 0.01, 0.0, 0.0)))
        .collect();
    let mut holes = random_boxes(&mut rng, 200, 1.0, 0.1);
    for b in holes.iter_mut().step_by(3) {
        *b = Aabb::EMPTY;
    }
    vec![
        ("random", random),
        ("identical", identical),
        ("flat", flat),
        ("line", line),
        ("with empty boxes", holes),
        ("single", vec![Aabb::new(DVec3::ZERO, DVec3::ONE)]),
        ("empty", Vec::new()),
    ]
}

/// Lowest index among the minimal distances within `max`, as `nearest`
/// promises.
fn brute_nearest(boxes: &[Aabb], p: DVec3, max: f64) -> Option<(u32, f64)> {
    let mut best: Option<(u32, f64)> = None;
    for (i, b) in boxes.iter().enumerate() {
        let d = b.distance2_to_point(p);
        if d <= max && best.map_or(true, |(_, bd)| d < bd) {
            best = Some((i as u32, d));
        }
    }
    best
}

#[test]
fn nearest_equals_brute_force_with_lowest_index_on_ties() {
    let mut rng = Rng::new(1);
    for (name, boxes) in test_sets() {
        let bvh = Bvh::build(&boxes);
        assert_eq!(bvh.len(), boxes.len());
        for q in 0..500 {
            let p = DVec3::new(
                rng.range(-1.5, 1.5),
                rng.range(-1.5, 1.5),
                rng.range(-0.5, 0.5),
            );
            let max = if q % 3 == 0 { 0.05 } else { f64::INFINITY };
            let mut calls = 0;
            let got = bvh.nearest(p, max, |i| {
                calls += 1;
                boxes[i as usize].distance2_to_point(p)
            });
            assert_eq!(got, brute_nearest(&boxes, p, max), "{name}, query {q}");
            assert!(calls <= boxes.len());
        }
    }
}

#[test]
fn nearest_prunes_most_primitives_on_a_large_random_set() {
    let mut rng = Rng::new(2);
    let boxes = random_boxes(&mut rng, 20_000, 1.0, 0.01);
    let bvh = Bvh::build(&boxes);
    let mut calls = 0;
    for _ in 0..100 {
        let p = DVec3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        );
        bvh.nearest(p, f64::INFINITY, |i| {
            calls += 1;
            boxes[i as usize].distance2_to_point(p)
        });
    }
    assert!(calls < 100 * 200, "{calls} distance calls for 100 queries");
}

fn brute_pairs(a: &[Aabb], b: &[Aabb], margin: f64) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            let d = x.distance2(y);
            // Empty boxes are infinitely far, even under an infinite margin.
            if d <= margin * margin && d < f64::INFINITY {
                out.push((i as u32, j as u32));
            }
        }
    }
    out
}

#[test]
fn pairs_within_equals_brute_force() {
    let sets = test_sets();
    for margin in [0.0, 0.02, 0.3, f64::INFINITY] {
        for (na, a) in &sets {
            for (nb, b) in sets.iter().take(4) {
                let (ta, tb) = (Bvh::build(a), Bvh::build(b));
                let mut got = Vec::new();
                ta.pairs_within(&tb, margin, |i, j| got.push((i, j)));
                got.sort_unstable();
                let n = got.len();
                got.dedup();
                assert_eq!(n, got.len(), "{na} × {nb}: a pair reported twice");
                assert_eq!(
                    got,
                    brute_pairs(a, b, margin),
                    "{na} × {nb}, margin {margin}"
                );
            }
        }
    }
}

#[test]
fn self_pairs_within_reports_each_unordered_pair_once() {
    for margin in [0.0, 0.02, 0.3, f64::INFINITY] {
        for (name, boxes) in test_sets() {
            let t = Bvh::build(&boxes);
            let mut got = Vec::new();
            t.self_pairs_within(margin, |i, j| {
                assert!(i < j);
                got.push((i, j));
            });
            got.sort_unstable();
            let n = got.len();
            got.dedup();
            assert_eq!(n, got.len(), "{name}: a pair reported twice");
            let want: Vec<(u32, u32)> = brute_pairs(&boxes, &boxes, margin)
                .into_iter()
                .filter(|&(i, j)| i < j)
                .collect();
            assert_eq!(got, want, "{name}, margin {margin}");
        }
    }
}

#[test]
fn pair_walks_stop_when_the_callback_breaks() {
    use std::ops::ControlFlow;
    let boxes = vec![Aabb::new(DVec3::ZERO, DVec3::ONE); 200];
    let t = Bvh::build(&boxes);
    // The first 10 pairs in walk order, then a stop.
    let mut all = Vec::new();
    t.self_pairs_within(0.0, |i, j| all.push((i, j)));
    let mut got = Vec::new();
    let flow = t.self_pairs_within_until(0.0, |i, j| {
        got.push((i, j));
        if got.len() == 10 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    assert_eq!(flow, ControlFlow::Break(()));
    assert_eq!(got, all[..10]);
    // Two trees: a walk that never breaks reports every pair and continues.
    let mut n = 0;
    let flow = t.pairs_within_until(&t, 0.0, |_, _| {
        n += 1;
        ControlFlow::Continue(())
    });
    assert_eq!((flow, n), (ControlFlow::Continue(()), 200 * 200));
    let mut n = 0;
    let flow = t.pairs_within_until(&t, 0.0, |_, _| {
        n += 1;
        if n == 7 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    assert_eq!((flow, n), (ControlFlow::Break(()), 7));
}

#[test]
fn identical_boxes_pair_up_completely() {
    let boxes = vec![Aabb::new(DVec3::ZERO, DVec3::ONE); 200];
    let t = Bvh::build(&boxes);
    let mut n = 0;
    t.self_pairs_within(0.0, |_, _| n += 1);
    assert_eq!(n, 200 * 199 / 2);
    assert!(t.depth() <= 10, "halving keeps identical boxes shallow");
    assert_eq!(
        t.nearest(DVec3::splat(5.0), f64::INFINITY, |i| {
            boxes[i as usize].distance2_to_point(DVec3::splat(5.0))
        }),
        Some((0, 48.0))
    );
}

#[test]
fn parallel_pairs_match_sequential_pairs_in_a_thread_independent_order() {
    let mut rng = Rng::new(8);
    let a = random_boxes(&mut rng, 3000, 1.0, 0.02);
    let b = random_boxes(&mut rng, 2000, 1.0, 0.02);
    let (ta, tb) = (Bvh::build(&a), Bvh::build(&b));
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool");
        pool.install(|| {
            (
                ta.par_self_pairs_within(0.01, |i, j| Some((i, j))),
                ta.par_pairs_within(&tb, 0.01, |i, j| (i % 2 == 0).then_some((i, j))),
            )
        })
    };
    let (self1, cross1) = run(1);
    let (self2, cross2) = run(2);
    assert_eq!(self1, self2);
    assert_eq!(cross1, cross2);
    let mut seq = Vec::new();
    ta.self_pairs_within(0.01, |i, j| seq.push((i, j)));
    let (mut s, mut p) = (seq, self1);
    s.sort_unstable();
    p.sort_unstable();
    assert_eq!(s, p);
    let mut seq = Vec::new();
    ta.pairs_within(&tb, 0.01, |i, j| {
        if i % 2 == 0 {
            seq.push((i, j))
        }
    });
    let mut c = cross1;
    seq.sort_unstable();
    c.sort_unstable();
    assert_eq!(seq, c);
    assert!(!c.is_empty());
}

#[test]
fn query_within_equals_brute_force() {
    let mut rng = Rng::new(4);
    for (name, boxes) in test_sets() {
        let t = Bvh::build(&boxes);
        for _ in 0..100 {
            let q = random_boxes(&mut rng, 1, 1.0, 0.2)[0];
            let margin = rng.range(0.0, 0.1);
            let mut got = Vec::new();
            t.query_within(&q, margin, |i| got.push(i));
            got.sort_unstable();
            let want: Vec<u32> = (0..boxes.len() as u32)
                .filter(|&i| boxes[i as usize].distance2(&q) <= margin * margin)
                .collect();
            assert_eq!(got, want, "{name}");
        }
    }
}

#[test]
fn same_boxes_build_the_same_tree() {
    let mut rng = Rng::new(6);
    let boxes = random_boxes(&mut rng, 5000, 1.0, 0.05);
    let (a, b) = (Bvh::build(&boxes), Bvh::build(&boxes));
    assert_eq!(a.nodes, b.nodes);
    assert_eq!(a.slot_order(), b.slot_order());
    assert!(a.depth() < 40, "depth {}", a.depth());
    assert_eq!(
        a.bounds(),
        boxes.iter().fold(Aabb::EMPTY, |x, y| x.union(y))
    );
}

#[test]
fn negative_or_nan_margins_and_empty_trees_report_nothing() {
    let boxes = vec![Aabb::new(DVec3::ZERO, DVec3::ONE); 10];
    let t = Bvh::build(&boxes);
    let e = Bvh::build(&[]);
    let mut n = 0;
    t.self_pairs_within(-1.0, |_, _| n += 1);
    t.self_pairs_within(f64::NAN, |_, _| n += 1);
    t.pairs_within(&e, 1.0, |_, _| n += 1);
    e.pairs_within(&t, 1.0, |_, _| n += 1);
    e.self_pairs_within(1.0, |_, _| n += 1);
    t.query_within(&boxes[0], -0.5, |_| n += 1);
    assert_eq!(n, 0);
    assert!(e.nearest(DVec3::ZERO, f64::INFINITY, |_| 0.0).is_none());
    assert!(e.bounds().is_empty());
    assert_eq!((e.len(), e.depth()), (0, 0));
    // NaN distances from the caller are ignored, not chosen.
    assert!(t
        .nearest(DVec3::ZERO, f64::INFINITY, |_| f64::NAN)
        .is_none());
}

/// Every primitive sits in exactly one leaf slot, and every node's box
/// contains its children's (or its primitives') boxes.
fn assert_well_formed(t: &Bvh, boxes: &[Aabb]) {
    let mut seen = vec![false; boxes.len()];
    for &p in t.slot_order() {
        assert!(!seen[p as usize], "primitive {p} twice");
        seen[p as usize] = true;
    }
    assert!(seen.iter().all(|&s| s));
    let contains = |outer: &Aabb, inner: &Aabb| {
        inner.is_empty() || (outer.min.cmple(inner.min).all() && outer.max.cmpge(inner.max).all())
    };
    let mut reached = 0;
    let mut stack = vec![0u32];
    while let Some(n) = stack.pop() {
        reached += 1;
        let node = &t.nodes[n as usize];
        if node.is_leaf() {
            for k in node.slots() {
                assert_eq!(t.boxes[k], boxes[t.prims[k] as usize]);
                assert!(contains(&node.bounds, &t.boxes[k]));
            }
        } else {
            for c in [node.start, node.start + 1] {
                assert!(c > n, "children come after their parent");
                assert!(contains(&node.bounds, &t.nodes[c as usize].bounds));
                stack.push(c);
            }
        }
    }
    assert_eq!(reached, t.node_count(), "every node is reachable once");
}

#[test]
fn large_build_is_well_formed_and_independent_of_thread_count() {
    let mut rng = Rng::new(12);
    let boxes = random_boxes(&mut rng, 150_000, 1.0, 0.003);
    let build = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool")
            .install(|| Bvh::build(&boxes))
    };
    let (one, two) = (build(1), build(2));
    assert_eq!(one.nodes, two.nodes);
    assert_eq!(one.prims, two.prims);
    assert_well_formed(&one, &boxes);
    for _ in 0..200 {
        let p = DVec3::new(
            rng.range(-1.2, 1.2),
            rng.range(-1.2, 1.2),
            rng.range(-1.2, 1.2),
        );
        let got = one.nearest(p, f64::INFINITY, |i| {
            boxes[i as usize].distance2_to_point(p)
        });
        assert_eq!(got, brute_nearest(&boxes, p, f64::INFINITY));
    }
}

#[test]
fn small_sets_are_well_formed() {
    for (_, boxes) in test_sets() {
        let t = Bvh::build(&boxes);
        if !boxes.is_empty() {
            assert_well_formed(&t, &boxes);
        }
    }
}

#[test]
fn any_hit_agrees_with_brute_force_on_random_triangles_and_rays() {
    let mut rng = Rng::new(7);
    let tris: Vec<[DVec3; 3]> = (0..600)
        .map(|_| {
            let c = DVec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            let mut corner = || {
                c + DVec3::new(
                    rng.range(-0.3, 0.3),
                    rng.range(-0.3, 0.3),
                    rng.range(-0.3, 0.3),
                )
            };
            [corner(), corner(), corner()]
        })
        .collect();
    let bvh = Bvh::build(
        &tris
            .iter()
            .map(|t| Aabb::from_triangle(t[0], t[1], t[2]))
            .collect::<Vec<_>>(),
    );
    let hits = |o: DVec3, d: DVec3, max_t: f64, i: u32| {
        let t = &tris[i as usize];
        crate::ray_triangle(o, d, t[0], t[1], t[2]).is_some_and(|x| x <= max_t)
    };
    let (mut some, mut none) = (0, 0);
    for k in 0..2000 {
        let o = DVec3::new(
            rng.range(-1.5, 1.5),
            rng.range(-1.5, 1.5),
            rng.range(-1.5, 1.5),
        );
        let mut d = DVec3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        );
        // Some rays run along an axis: infinite slab parameters.
        if k % 5 == 0 {
            d = DVec3::new(d.x, 0.0, 0.0);
        }
        let max_t = rng.range(0.0, 2.0);
        let brute = (0..tris.len() as u32).any(|i| hits(o, d, max_t, i));
        let fast = bvh.any_hit(o, d, max_t, |i| hits(o, d, max_t, i));
        assert_eq!(fast, brute, "ray {k}");
        if brute {
            some += 1;
        } else {
            none += 1;
        }
    }
    // Both answers occur often enough for the comparison to mean something.
    assert!(some > 200 && none > 200, "{some} hits, {none} misses");
}
