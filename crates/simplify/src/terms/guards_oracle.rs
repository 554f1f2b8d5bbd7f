//! The guards as first written, each reading the whole star of both
//! endpoints: the reference the local versions in `guards` must agree with
//! (same verdicts, same witness faces), checked on random complexes in
//! `guards::tests`. Test-only. (The pinch test's whole-star version is in
//! `guards` itself: it is the faster one for ordinary stars.)

use glam::DVec3;

use super::guards::vanishes;
use crate::prepare::complex::Complex;
use crate::prepare::geometry::polygon_normal;

pub(super) fn flipped_face(
    c: &Complex,
    star: &[u32],
    i: u32,
    j: u32,
    x: DVec3,
    min_cos: f64,
) -> Option<u32> {
    let mut old_p: smallvec::SmallVec<[DVec3; 8]> = smallvec::SmallVec::new();
    let mut new_p: smallvec::SmallVec<[DVec3; 8]> = smallvec::SmallVec::new();
    for &f in star {
        let face = c.face(f);
        let (old, new) = if let [a, b, d] = *face {
            // A triangle holding both endpoints vanishes: nothing to judge.
            let has = |v: u32| a == v || b == v || d == v;
            if has(i) && has(j) {
                continue;
            }
            let p = |v: u32| c.pos[v as usize];
            let m = |v: u32| {
                if v == i || v == j {
                    x
                } else {
                    c.pos[v as usize]
                }
            };
            (
                (p(b) - p(a)).cross(p(d) - p(a)),
                (m(b) - m(a)).cross(m(d) - m(a)),
            )
        } else {
            old_p.clear();
            new_p.clear();
            for &v in face {
                let p = c.pos[v as usize];
                old_p.push(p);
                new_p.push(if v == i || v == j { x } else { p });
            }
            (polygon_normal(&old_p), polygon_normal(&new_p))
        };
        let (lo, ln) = (old.length_squared(), new.length_squared());
        // Areas below ~1e-15 of the unit-diagonal mesh are numerical dust.
        if lo <= 1e-30 || ln <= 1e-30 {
            continue;
        }
        if old.dot(new) < min_cos * (lo * ln).sqrt() {
            return Some(f);
        }
    }
    None
}

pub(super) fn flattens_a_face(c: &Complex, star: &[u32], i: u32, j: u32, x: DVec3) -> Option<u32> {
    let mut old_p: smallvec::SmallVec<[DVec3; 8]> = smallvec::SmallVec::new();
    let mut new_p: smallvec::SmallVec<[DVec3; 8]> = smallvec::SmallVec::new();
    for &f in star {
        let face = c.face(f);
        if vanishes(face, i, j) {
            continue;
        }
        old_p.clear();
        new_p.clear();
        for &v in face {
            let p = c.pos[v as usize];
            old_p.push(p);
            new_p.push(if v == i || v == j { x } else { p });
        }
        let (lo, ln) = (
            polygon_normal(&old_p).length_squared(),
            polygon_normal(&new_p).length_squared(),
        );
        if lo > 1e-30 && ln <= 1e-24 * lo {
            return Some(f);
        }
        // A corner brought onto another: every pair of a merged corner and
        // a kept one, to 1e-7 of their distance before.
        for (k, &m) in face.iter().enumerate() {
            if m != i && m != j {
                continue;
            }
            for (l, &v) in face.iter().enumerate() {
                if v == i || v == j {
                    continue;
                }
                let before = old_p[k].distance(old_p[l]);
                if before > 0.0 && new_p[k].distance(new_p[l]) <= 1e-7 * before {
                    return Some(f);
                }
            }
        }
    }
    None
}

pub(super) fn keeps_topology(c: &Complex, i: u32, j: u32) -> bool {
    let faces_on_edge = c.edge_face_count(i, j);
    if faces_on_edge > 2 {
        return false;
    }
    // Common neighbors through edges.
    let ni: Vec<u32> = c.vert_edges[i as usize]
        .iter()
        .map(|&e| c.other(e, i))
        .collect();
    for &e in &c.vert_edges[j as usize] {
        let k = c.other(e, j);
        if k == i || !ni.contains(&k) {
            continue;
        }
        let closes = c.vert_faces[i as usize].iter().any(|&f| {
            let face = c.face(f);
            face.len() == 3 && face.contains(&j) && face.contains(&k)
        });
        if !closes {
            return false;
        }
    }
    // Sides of faces of i (not holding j) and of j (not holding i).
    if shares_a_far_side(c, i, j) {
        return false;
    }
    let (bi, bj) = (c.on_boundary(i), c.on_boundary(j));
    if bi && bj && c.edge_face_count(i, j) != 1 {
        return false;
    }
    // An isolated triangle on the edge would vanish with its component.
    for &f in &c.vert_faces[i as usize] {
        let face = c.face(f);
        if face.len() == 3 && face.contains(&j) {
            let isolated = (0..3).all(|k| c.edge_face_count(face[k], face[(k + 1) % 3]) == 1);
            if isolated {
                return false;
            }
        }
    }
    true
}

fn far_sides(c: &Complex, v: u32, other: u32) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for &f in &c.vert_faces[v as usize] {
        let face = c.face(f);
        if face.contains(&other) {
            continue;
        }
        let n = face.len();
        for k in 0..n {
            let (a, b) = (face[k], face[(k + 1) % n]);
            if a != v && b != v {
                out.push((a.min(b), a.max(b)));
            }
        }
    }
    out.sort_unstable();
    out
}

fn shares_a_far_side(c: &Complex, i: u32, j: u32) -> bool {
    let si = far_sides(c, i, j);
    far_sides(c, j, i)
        .iter()
        .any(|s| si.binary_search(s).is_ok())
}
