//! The surface as it is drawn: face planes of a skinned mesh in the poses
//! its animations take, pulled back to the rest pose (issue 31, decision 8).
//!
//! A skinned mesh is never seen at rest. Plane quadrics taken at rest make
//! a straight arm's elbow flat and cheap: its rings go first, and bent at
//! 90° the arm kinks. Here every vertex also carries the planes of its
//! faces in each sampled pose, expressed in rest coordinates: in pose `k`
//! the vertex moves by its linear-blend transform `x ↦ Mₖx + tₖ` (Σ of its
//! joints' skinning matrices, weighted), and a plane quadric `Q` of the
//! posed surface becomes `Q(Mₖx + tₖ)`, a quadric in `x`. Collapsing two
//! vertices then costs what it costs in every pose, measured by each
//! endpoint's own transform (the merged vertex's weights blend theirs).
//!
//! The rest pose and the poses count alike: each vertex's face planes are
//! replaced by their mean over the rest pose and every sampled pose, the
//! other terms (borders, creases, regularization) staying as they are, so
//! a mesh whose poses equal its rest gets its rest quadrics back.

use glam::{DMat3, DMat4, DVec3};
use rayon::prelude::*;

use crate::options::{Metric, Options};
use crate::prepare::complex::Complex;
#[cfg(test)]
use crate::prepare::geometry::face_plane;
use crate::prepare::Prepared;
use crate::terms::cost::plane_weight_factors;
use crate::terms::quadric::Quadric;
use crate::terms::stored::StoredQuadric;

/// `q(m·x + t)` as a quadric in `x`: with `q(y) = yᵀAy + 2bᵀy + c`,
/// `A' = mᵀAm`, `b' = mᵀ(At + b)`, `c' = tᵀAt + 2bᵀt + c`. The weight is
/// kept.
pub(crate) fn pulled_back(q: &Quadric, m: DMat3, t: DVec3) -> Quadric {
    let [xx, xy, xz, yy, yz, zz] = q.a;
    let a = DMat3::from_cols(
        DVec3::new(xx, xy, xz),
        DVec3::new(xy, yy, yz),
        DVec3::new(xz, yz, zz),
    );
    let ma = m.transpose() * a * m;
    let at = a * t;
    let b = m.transpose() * (at + q.b);
    let c = t.dot(at) + 2.0 * q.b.dot(t) + q.c;
    Quadric {
        a: [
            ma.x_axis.x,
            ma.y_axis.x,
            ma.z_axis.x,
            ma.y_axis.y,
            ma.z_axis.y,
            ma.z_axis.z,
        ],
        b,
        c,
        weight: q.weight,
    }
}

/// Every vertex's share of its faces' planes with the complex's vertices
/// at `pos` (area × `factor[f]` / arity of each face; empty `factor`: the
/// area alone), pulled back by each vertex's transform (`None`: it does
/// not move).
fn planes_at(
    c: &Complex,
    pos: &[DVec3],
    moves: &[Option<(DMat3, DVec3)>],
    faces_of: &(dyn Fn(usize) -> Vec<u32> + Sync),
    only: Option<&[bool]>,
    factor: &[f64],
) -> Vec<Quadric> {
    let wanted = |v: usize| only.map_or(true, |o| o[v]);
    let planes: Vec<Option<(DVec3, f64, DVec3)>> = (0..c.faces.len() as u32)
        .into_par_iter()
        .map(|f| {
            if c.faces[f as usize].len == 0 {
                return None;
            }
            let face = c.face(f);
            if !face.iter().any(|&v| wanted(v as usize)) {
                return None;
            }
            // The face with its corners where this pose puts them.
            let corners: Vec<DVec3> = face.iter().map(|&v| pos[v as usize]).collect();
            face_plane_of(&corners)
        })
        .collect();
    (0..c.pos.len())
        .into_par_iter()
        .map(|v| {
            if !wanted(v) {
                return Quadric::ZERO;
            }
            let mut q = Quadric::ZERO;
            for f in faces_of(v) {
                if let Some((n, area, centroid)) = planes[f as usize] {
                    let k = c.face(f).len() as f64;
                    let weight = area * factor.get(f as usize).copied().unwrap_or(1.0);
                    if weight > 0.0 {
                        q += Quadric::plane(n, centroid, weight / k);
                    }
                }
            }
            let q = Quadric { weight: 0.0, ..q };
            match moves[v] {
                Some((m, t)) => pulled_back(&q, m, t),
                None => q,
            }
        })
        .collect()
}

/// Unit normal, area and centroid of a polygon given by its corners.
fn face_plane_of(corners: &[DVec3]) -> Option<(DVec3, f64, DVec3)> {
    let (n2, centroid) = crate::prepare::geometry::newell(corners.iter().copied());
    let len = n2.length();
    (len.is_finite() && len > 0.0).then(|| (n2 / len, 0.5 * len, centroid))
}

/// Where one pose puts each complex vertex: `x ↦ m·x + t` in normalized
/// coordinates, `None` for a vertex the pose leaves still.
type Moves = Vec<Option<(DMat3, DVec3)>>;

/// One pose: its moves, and whether they are local (a morph target moves
/// one region: a vertex none of whose faces it moves has its rest planes in
/// the pose, added as they are instead of computed again, bit for bit the
/// same) or move the whole mesh (a skin pose).
struct Pose {
    moves: Moves,
    local: bool,
}

/// What to add to each vertex's rest quadric so that its face planes are
/// their mean over the rest pose and the `count` poses `pose_of(k)` (see
/// the module documentation): `mean − rest`, per vertex, each face's
/// plane weighed by its area times `factor[f]` in every pose (see
/// [`planes_at`]). The rest planes subtracted must not exceed what the
/// vertex quadric holds: a face the quadric weighs below its area (every
/// face alike, a large face) taken out by its area leaves a negative
/// share of its plane behind, and the quadric, no longer positive,
/// rewards moving off the surface. Every pose counts
/// at every vertex, where it moves nothing with the rest planes: a target
/// weighs against the rest pose by its share of all the poses. (Counting
/// a target only where it acts, as much as the rest pose there, was
/// measured: on a sphere with 52 bumps at 10%, the same posed Hausdorff
/// distance at each target's peak for 3× the rest pose's.) Empty when
/// there is no pose.
fn mean_pose_terms(
    c: &Complex,
    count: usize,
    pose_of: &(dyn Fn(usize) -> Pose + Sync),
    factor: &[f64],
) -> Vec<Quadric> {
    if count == 0 || c.pos.is_empty() {
        return Vec::new();
    }
    let (start, list) = if c.has_adjacency() {
        (Vec::new(), Vec::new())
    } else {
        c.vertex_face_index()
    };
    let faces_of = |v: usize| -> Vec<u32> {
        if c.has_adjacency() {
            c.vert_faces[v].to_vec()
        } else {
            list[start[v] as usize..start[v + 1] as usize].to_vec()
        }
    };
    let n = c.pos.len();
    let still = vec![None; n];
    let rest = planes_at(c, &c.pos, &still, &faces_of, None, factor);
    let mut sum = rest.clone();
    for k in 0..count {
        let Pose { mut moves, local } = pose_of(k);
        // One entry per vertex, whatever the source covered.
        moves.resize(n, None);
        let reached: Option<Vec<bool>> = local.then(|| {
            let mut r = vec![false; n];
            for f in c.live_faces() {
                let face = c.face(f);
                if face.iter().any(|&v| moves[v as usize].is_some()) {
                    for &v in face {
                        r[v as usize] = true;
                    }
                }
            }
            r
        });
        let pos: Vec<DVec3> = c
            .pos
            .iter()
            .zip(&moves)
            .map(|(&x, mv)| mv.map_or(x, |(m, t)| m * x + t))
            .collect();
        let posed = planes_at(c, &pos, &moves, &faces_of, reached.as_deref(), factor);
        match &reached {
            None => sum.par_iter_mut().zip(posed).for_each(|(s, p)| *s += p),
            Some(r) => sum
                .par_iter_mut()
                .zip(posed)
                .zip(&rest)
                .zip(r)
                .for_each(|(((s, p), q), &reached)| *s += if reached { p } else { *q }),
        }
    }
    let n = (count + 1) as f64;
    sum.into_iter()
        .zip(rest)
        .map(|(s, r)| s.scaled(1.0 / n).minus(&r))
        .collect()
}

/// The moves of a skin pose: `pose[j]` is joint `j`'s skinning matrix
/// (world of the joint times its inverse bind matrix, column-major, input
/// units), `joints[v]` the (joint, weight) influences of complex vertex `v`
/// (empty: it does not move), blended linearly; `center` and `scale` the
/// normalization of the complex's positions.
fn skin_moves(pose: &[[f32; 16]], joints: &[&[(u32, f32)]], center: DVec3, scale: f64) -> Moves {
    // Each joint's skinning matrix on normalized positions: the linear
    // part is the same; the translation absorbs the center.
    let matrices: Vec<(DMat3, DVec3)> = pose
        .iter()
        .map(|m| {
            let m = DMat4::from_cols_array(&m.map(f64::from));
            let lin = DMat3::from_mat4(m);
            let t = m.w_axis.truncate();
            (lin, (lin * center + t - center) / scale)
        })
        .collect();
    (0..joints.len())
        .into_par_iter()
        .map(|v| {
            let influences = joints[v];
            let total: f64 = influences.iter().map(|&(_, w)| w as f64).sum();
            if total.is_nan() || total <= 0.0 {
                return None;
            }
            let mut m = DMat3::ZERO;
            let mut t = DVec3::ZERO;
            for &(j, w) in influences {
                let Some((mj, tj)) = matrices.get(j as usize) else {
                    continue;
                };
                let w = w as f64 / total;
                m += *mj * w;
                t += *tj * w;
            }
            Some((m, t))
        })
        .collect()
}

/// The moves of a morph target at full weight: complex vertex `v` moves
/// by `deltas[rep[v]]` (input units, brought to the complex's `scale`); a
/// vertex without a delta, or with a zero or non-finite one, stays.
fn morph_moves(deltas: &[[f32; 3]], rep: &[u32], scale: f64) -> Moves {
    rep.par_iter()
        .map(|&v| {
            let d = DVec3::from(deltas.get(v as usize)?.map(f64::from)) / scale;
            (d.is_finite() && d != DVec3::ZERO).then_some((DMat3::IDENTITY, d))
        })
        .collect()
}

/// [`mean_pose_terms`] over skin poses: `poses[k][j]` is joint `j`'s
/// skinning matrix in pose `k` (see [`skin_moves`]), `joints[v]` the
/// influences of complex vertex `v`.
#[cfg(test)]
pub(crate) fn pose_terms(
    c: &Complex,
    poses: &[Vec<[f32; 16]>],
    joints: &[&[(u32, f32)]],
    center: DVec3,
    scale: f64,
) -> Vec<Quadric> {
    mean_pose_terms(
        c,
        poses.len(),
        &|k| Pose {
            moves: skin_moves(&poses[k], joints, center, scale),
            local: false,
        },
        &[],
    )
}

/// Adds the pose terms ([`mean_pose_terms`]) to a run's vertex quadrics:
/// the skin's poses ([`crate::InputData::skin_poses`], each vertex moving
/// with the influences of its first input vertex,
/// [`crate::InputData::vertex_joints`]) and the morph targets at full
/// weight ([`crate::InputData::morph_targets`]), all counting alike. A
/// face weighs by its area, or less where `metric` weighs it less in the
/// rest quadrics (for the `budget` the run simplifies to, see
/// `cost::plane_weight_factors`), and each vertex's terms are scaled by
/// its weight as its rest quadric is (see `Prepared::weights`).
pub(crate) fn add_pose_terms(
    quadrics: &mut [StoredQuadric],
    p: &Prepared,
    options: &Options,
    metric: &Metric,
    budget: usize,
) {
    let data = &options.data;
    let skin = if data.vertex_joints.is_empty() {
        &[][..]
    } else {
        &data.skin_poses[..]
    };
    let morphs = if options.attributes.morph_poses {
        &data.morph_targets[..]
    } else {
        &[][..]
    };
    if skin.is_empty() && morphs.is_empty() {
        return;
    }
    let none: &[(u32, f32)] = &[];
    let joints: Vec<&[(u32, f32)]> = p
        .rep
        .iter()
        .map(|&v| {
            data.vertex_joints
                .get(v as usize)
                .map_or(none, Vec::as_slice)
        })
        .collect();
    // Poses take over a face's plane at most as far as the rest quadric
    // holds it: by area where the metric weighs by area, less where it
    // weighs a large face less (a smaller area exponent), never more. Not
    // the lift a floor gives small faces either: that ranks collapses at
    // rest so that fine details do not go first, and lifted in every pose
    // as well, a grid with a twisting target and finely spaced columns
    // kept its fine columns for 2.6× the Hausdorff distance in the coarse
    // ones, at rest and posed alike.
    let factor: Vec<f64> = plane_weight_factors(&p.complex, metric, budget, &p.outliers)
        .into_iter()
        .map(|f| f.min(1.0))
        .collect();
    let terms = mean_pose_terms(
        &p.complex,
        skin.len() + morphs.len(),
        &|k| match skin.get(k) {
            Some(pose) => Pose {
                moves: skin_moves(pose, &joints, p.center, p.scale),
                local: false,
            },
            None => Pose {
                moves: morph_moves(&morphs[k - skin.len()], &p.rep, p.scale),
                local: true,
            },
        },
        &factor,
    );
    for (v, ((q, t), &at)) in quadrics
        .iter_mut()
        .zip(terms)
        .zip(&p.complex.pos)
        .enumerate()
    {
        let t = match p.weights.get(v) {
            Some(&w) if w != 1.0 => t.scaled(w),
            _ => t,
        };
        *q = StoredQuadric::new(&(q.quadric(at) + t), at);
    }
}

/// The face plane used by the rest quadrics, for tests that compare.
#[cfg(test)]
fn rest_plane(c: &Complex, f: u32) -> Option<(DVec3, f64, DVec3)> {
    face_plane(c, f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pulled_back_quadric_measures_the_moved_point() {
        // The plane z = 1 (weight 2) and a map that turns by 90° about x
        // and shifts by (0, 0, 3): x ↦ (x, -z, y) + (0, 0, 3).
        let q = Quadric::plane(DVec3::Z, DVec3::new(0.0, 0.0, 1.0), 2.0);
        let m = DMat3::from_cols(DVec3::X, DVec3::Z, -DVec3::Y);
        let t = DVec3::new(0.0, 0.0, 3.0);
        let back = pulled_back(&q, m, t);
        for x in [
            DVec3::ZERO,
            DVec3::new(1.0, -2.0, 0.5),
            DVec3::new(-3.0, 4.0, 7.0),
        ] {
            let y = m * x + t;
            // The moved point's distance to z = 1 is |y.z - 1| = |x.y + 2|.
            let expected = 2.0 * (x.y + 2.0).powi(2);
            assert!((back.eval(x) - expected).abs() < 1e-9, "{x}");
            assert!((q.eval(y) - expected).abs() < 1e-9);
        }
    }

    /// A flat square of two triangles in z = 0, as a complex.
    fn square() -> Complex {
        let pos = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        Complex::new(pos, &[0, 3, 6], &[0, 1, 2, 0, 2, 3]).0
    }

    #[test]
    fn a_local_pose_gives_what_the_whole_mesh_computed_again_gives() {
        // Two squares far apart (vertices 0-3 and 4-7); target A lifts
        // vertex 2, target B vertex 6: computed only where each acts, the
        // terms are those of every vertex's planes computed in each pose.
        let mut pos: Vec<DVec3> = square().pos;
        pos.extend(square().pos.iter().map(|&p| p + DVec3::new(10.0, 0.0, 0.0)));
        let c = Complex::new(
            pos,
            &[0, 3, 6, 9, 12],
            &[0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7],
        )
        .0;
        let rep: Vec<u32> = (0..8).collect();
        let lift = |v: usize| {
            let mut d = vec![[0.0f32; 3]; 8];
            d[v] = [0.0, 0.0, 1.0];
            d
        };
        let (a, b) = (lift(2), lift(6));
        let terms = |local: bool| {
            mean_pose_terms(
                &c,
                2,
                &|k| Pose {
                    moves: morph_moves(if k == 0 { &a } else { &b }, &rep, 1.0),
                    local,
                },
                &[],
            )
        };
        assert_eq!(terms(true), terms(false));
        assert!(terms(true)[2].a.iter().any(|x| x.abs() > 1e-6));
    }

    #[test]
    fn a_morph_that_moves_the_surface_rigidly_adds_nothing() {
        // Every vertex up by 2: the posed planes, pulled back by the same
        // shift, are the rest planes.
        let c = square();
        let up = vec![[0.0f32, 0.0, 2.0]; 4];
        let rep = [0u32, 1, 2, 3];
        let terms = mean_pose_terms(
            &c,
            1,
            &|_| Pose {
                moves: morph_moves(&up, &rep, 1.0),
                local: true,
            },
            &[],
        );
        for t in terms {
            assert!(t.a.iter().all(|x| x.abs() < 1e-12), "{t:?}");
            assert!(t.c.abs() < 1e-12 && t.b.length() < 1e-12);
        }
    }

    #[test]
    fn a_morph_that_lifts_a_corner_costs_what_flattening_it_would() {
        // Corner 2 of the square rises by 1 in the target. At rest moving
        // it onto corner 0 is free (the square is flat); in the pose the
        // vertex sits at corner 0's place plus corner 2's delta, off the
        // posed faces: the pulled-back planes measure that.
        let c = square();
        let mut lift = vec![[0.0f32; 3]; 4];
        lift[2] = [0.0, 0.0, 1.0];
        let rep = [0u32, 1, 2, 3];
        let terms = mean_pose_terms(
            &c,
            1,
            &|_| Pose {
                moves: morph_moves(&lift, &rep, 1.0),
                local: true,
            },
            &[],
        );
        // At its own rest position corner 2 costs nothing in either pose.
        let q2 = terms[2];
        let rest_at_2 = DVec3::new(1.0, 1.0, 0.0);
        let rest2 = planes_at(
            &c,
            &c.pos,
            &[None; 4],
            &|v| c.vert_faces[v].to_vec(),
            None,
            &[],
        )[2];
        assert!((q2.eval(rest_at_2) + rest2.eval(rest_at_2)).abs() < 1e-12);
        // Placed at corner 0's rest position and moved by corner 2's
        // delta, the point (0, 0, 1) is off the posed triangle 0-1-2
        // (through (0,0,0), (1,0,0), (1,1,1): the plane z = y) by
        // 1/√2: squared 0.5, times its area share √2/2 / 3, halved (the
        // mean of the rest pose, where it costs 0, and the pose).
        let at0 = DVec3::ZERO;
        let mean = q2.eval(at0) + rest2.eval(at0);
        let area = 0.5 * 2f64.sqrt();
        let want_tri0 = 0.5 * (0.5 * area / 3.0);
        // Triangle 0-2-3 through (0,0,0), (1,1,1), (0,1,0): the plane
        // z = x, which (0, 0, 1) is off by 1/√2 as well.
        let want = 2.0 * want_tri0;
        assert!((mean - want).abs() < 1e-12, "{mean} vs {want}");
    }

    #[test]
    fn poses_equal_to_the_rest_add_nothing() {
        let mesh = wildlod_mesh::shapes::triangulate(&wildlod_mesh::shapes::torus(8, 6, 1.0, 0.3));
        let (c, _) = Complex::new(
            mesh.positions
                .iter()
                .map(|p| DVec3::from(p.map(f64::from)))
                .collect(),
            &mesh.faces.offsets,
            &mesh.faces.indices,
        );
        let identity = vec![[
            1.0f32, 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1.,
        ]];
        let one: Vec<(u32, f32)> = vec![(0, 1.0)];
        let joints: Vec<&[(u32, f32)]> = vec![&one; c.pos.len()];
        let terms = pose_terms(&c, &[identity.clone(), identity], &joints, DVec3::ZERO, 1.0);
        assert_eq!(terms.len(), c.pos.len());
        for t in terms {
            assert!(t.a.iter().all(|x| x.abs() < 1e-15), "{t:?}");
            assert!(t.c.abs() < 1e-15 && t.b.length() < 1e-15);
        }
        assert!(rest_plane(&c, 0).is_some());
    }

    #[test]
    fn a_bent_pose_makes_the_collapse_across_the_bend_cost() {
        // A flat strip along x, its right half turned by 90° about the
        // y axis at x = 1 in the pose: collapsing the middle column's
        // vertex (1, 0) onto (2, 0) is free at rest and costs once posed.
        let positions: Vec<DVec3> = (0..3)
            .flat_map(|i| (0..2).map(move |j| DVec3::new(i as f64, j as f64, 0.0)))
            .collect();
        // Vertex 2i + j at (i, j): quads as two triangles each.
        let indices = [0u32, 2, 3, 0, 3, 1, 2, 4, 5, 2, 5, 3];
        let offsets: Vec<u32> = (0..=4).map(|f| 3 * f).collect();
        let (c, _) = Complex::new(positions, &offsets, &indices);
        // Joint 0 still, joint 1 turns by 90° about the y axis through x = 1.
        let rot = DMat4::from_translation(DVec3::new(1.0, 0.0, 0.0))
            * DMat4::from_rotation_y(std::f64::consts::FRAC_PI_2)
            * DMat4::from_translation(DVec3::new(-1.0, 0.0, 0.0));
        let to_f32 = |m: DMat4| m.to_cols_array().map(|x| x as f32);
        let pose = vec![to_f32(DMat4::IDENTITY), to_f32(rot)];
        let left: Vec<(u32, f32)> = vec![(0, 1.0)];
        let mid: Vec<(u32, f32)> = vec![(0, 0.5), (1, 0.5)];
        let right: Vec<(u32, f32)> = vec![(1, 1.0)];
        let joints: Vec<&[(u32, f32)]> = vec![&left, &left, &mid, &mid, &right, &right];
        let terms = pose_terms(&c, &[pose], &joints, DVec3::ZERO, 1.0);
        // The right column at rest is where vertex 2 would go: at rest the
        // strip is flat, so only the pose term can make it cost.
        let target = DVec3::new(2.0, 0.0, 0.0);
        assert!(terms[2].eval(target) > 1e-3, "{:?}", terms[2]);
        // Staying put costs nothing in any pose.
        assert!(terms[2].eval(DVec3::new(1.0, 0.0, 0.0)).abs() < 1e-12);
    }

    #[test]
    fn pose_terms_take_out_no_more_of_a_plane_than_the_quadric_holds() {
        use crate::terms::cost::{plane_weight_factors, vertex_quadrics};
        use crate::terms::tangent::EdgeImportance;
        // A large triangle (area 10) among eight small ones (0.1 each, far
        // off): weighing every face alike (area exponent 0), the large one
        // weighs the mean, 1.2, where its area is 10.
        let mut pos = vec![
            DVec3::ZERO,
            DVec3::new(10.0, 0.0, 0.0),
            DVec3::new(0.0, 2.0, 0.0),
        ];
        let mut idx = vec![0u32, 1, 2];
        for k in 0..8 {
            let o = DVec3::new(20.0 + 2.0 * k as f64, 0.0, 0.0);
            let n = pos.len() as u32;
            pos.extend([
                o,
                o + DVec3::new(0.2, 0.0, 0.0),
                o + DVec3::new(0.0, 1.0, 0.0),
            ]);
            idx.extend([n, n + 1, n + 2]);
        }
        let offsets: Vec<u32> = (0..=9).map(|f| 3 * f).collect();
        let c = Complex::new(pos, &offsets, &idx).0;
        let metric = Metric {
            area_exponent: 0.0,
            face_weight_floor: 0.0,
            regularization: 0.0,
            border_weight: 0.0,
            crease_weight: 0.0,
            ..Metric::default()
        };
        let rest = vertex_quadrics(&c, &metric, &[], EdgeImportance::default());
        let factor = plane_weight_factors(&c, &metric, usize::MAX, &[]);
        assert!((factor[0] - 0.12).abs() < 1e-12 && (factor[1] - 12.0).abs() < 1e-9);
        // A target lifts the large triangle's far corner: the triangle
        // tilts about its edge 0-2.
        let mut lift = vec![[0.0f32; 3]; c.pos.len()];
        lift[1] = [0.0, 0.0, 5.0];
        let rep: Vec<u32> = (0..c.pos.len() as u32).collect();
        let terms = |factor: &[f64]| {
            mean_pose_terms(
                &c,
                1,
                &|_| Pose {
                    moves: morph_moves(&lift, &rep, 1.0),
                    local: true,
                },
                factor,
            )
        };
        // Vertex 0 holds the large triangle's plane only: with the faces
        // weighed alike, half of it at rest and half tilted, both at 1.2/3;
        // a point on the tilted plane costs half the rest plane's share.
        let on_tilted = DVec3::new(2.0, 0.0, 1.0);
        let q = rest[0] + terms(&factor)[0];
        let half_rest = 0.5 * 0.4 * on_tilted.z * on_tilted.z;
        assert!(
            (q.eval(on_tilted) - half_rest).abs() < 1e-9,
            "{}",
            q.eval(on_tilted)
        );
        // Nowhere negative.
        for p in [
            DVec3::new(3.0, -1.0, 0.6),
            DVec3::new(-4.0, 2.0, -0.8),
            on_tilted,
        ] {
            assert!(q.eval(p) >= -1e-12, "{p}: {}", q.eval(p));
        }
        // Subtracting the rest plane by its area instead (10/3, where the
        // quadric holds 1.2/3) leaves a negative share of it: the quadric
        // then pays for leaving the surface.
        let wrong = rest[0] + terms(&[])[0];
        assert!(wrong.eval(on_tilted) < -0.1, "{}", wrong.eval(on_tilted));
    }
}
