//! Layers stay in front of what they lie on.
//!
//! A decal, a sticker, a road marking or a patch of moss is often modelled
//! as its own sheet a few millimetres in front of a surface, so that it
//! draws over it. Nothing in the collapses ties the two together: once the
//! surface under the sheet has moved by more than the gap (its LOD's error
//! is centimetres where the gap is millimetres), the sheet sinks behind it
//! or pokes through it, and the decal vanishes from the LOD where the
//! geometric error alone would never show.
//!
//! After the collapses, every layer triangle is lifted until it clears the
//! simplified surface under it by the gap the layer had in the input (see
//! [`deficit`]); lifts only ever raise, so no triangle's lift undoes
//! another's. A part is a layer when it is an open sheet facing one way
//! (every face within 60° of its mean normal: a closed part, whose normals
//! span the sphere, never is) and every vertex and every face centre of it
//! lies within [`LAYER_GAP`] of its own extent of another part facing the
//! same way. Face centres are what tell a sheet lying *on* a surface from
//! coplanar tiles that only meet at their edges. Which side of the other
//! part it lies on is not asked: overlapping decals dip a hair under each
//! other. What lies under a layer is every part that is not one, so a
//! decal on a decal keeps its offset from the wall under both. A triangle
//! with a vertex that the collapses merged with the surface's own stays.
//!
//! Not part of either paper: a production need (decals on walls and
//! terrain) measured on a generated wall (`docs/design.md`, "Layers").

use glam::DVec3;
use rayon::prelude::*;
use std::collections::HashMap;
use wildlod_geometry::{closest_point_on_triangle, Aabb, Bvh};
use wildlod_mesh::disjoint_sets::DisjointSets;
use wildlod_mesh::Faces;

use super::Simplified;

/// How far in front of a surface a sheet may lie and still be a layer on
/// it, as a share of the sheet's own bounding-box diagonal: a decal half a
/// metre wide may float up to 2.5 cm off its wall.
pub(crate) const LAYER_GAP: f64 = 0.05;

/// Cosine of the largest angle between a layer's faces and its mean
/// normal, and between a layer and the surface under it (60°).
const FACING: f64 = 0.5;

/// Triangles (polygons fanned) of a set of faces, with a BVH over them.
struct Triangles {
    corners: Vec<[DVec3; 3]>,
    normals: Vec<DVec3>,
    /// The face each triangle belongs to.
    face: Vec<u32>,
    bvh: Bvh,
}

impl Triangles {
    /// The fan triangles of the faces `keep` accepts.
    fn new(positions: &[[f32; 3]], faces: &Faces, keep: impl Fn(u32) -> bool) -> Self {
        let p = |v: u32| DVec3::from(positions[v as usize].map(f64::from));
        let (mut corners, mut normals, mut face) = (Vec::new(), Vec::new(), Vec::new());
        for (f, ids) in faces.iter().enumerate() {
            if !keep(f as u32) {
                continue;
            }
            for k in 1..ids.len().saturating_sub(1) {
                let t = [p(ids[0]), p(ids[k]), p(ids[k + 1])];
                corners.push(t);
                normals.push((t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero());
                face.push(f as u32);
            }
        }
        let boxes: Vec<Aabb> = corners
            .iter()
            .map(|t| Aabb::from_triangle(t[0], t[1], t[2]))
            .collect();
        Triangles {
            corners,
            normals,
            face,
            bvh: Bvh::build(&boxes),
        }
    }

    /// The closest triangle to `p` within `max` that `skip` does not
    /// exclude: its index and closest point.
    fn closest(&self, p: DVec3, max: f64, skip: impl Fn(u32) -> bool) -> Option<(u32, DVec3)> {
        let (t, _) = self.bvh.nearest(p, max * max, |t| {
            if skip(t) {
                return f64::INFINITY;
            }
            let [a, b, c] = self.corners[t as usize];
            closest_point_on_triangle(p, a, b, c).0.distance_squared(p)
        })?;
        let [a, b, c] = self.corners[t as usize];
        Some((t, closest_point_on_triangle(p, a, b, c).0))
    }
}

/// Connected components of the faces (per face, and how many), vertices
/// joined where their positions are equal, as the simplifier welds them.
fn components(positions: &[[f32; 3]], faces: &Faces) -> (Vec<u32>, usize) {
    let mut weld: HashMap<[u32; 3], u32> = HashMap::new();
    let id: Vec<u32> = positions
        .iter()
        .map(|p| {
            let key = p.map(|x| if x == 0.0 { 0 } else { x.to_bits() });
            let next = weld.len() as u32;
            *weld.entry(key).or_insert(next)
        })
        .collect();
    let mut sets = DisjointSets::new(weld.len());
    for ids in faces.iter() {
        for w in ids.windows(2) {
            sets.union(id[w[0] as usize], id[w[1] as usize]);
        }
    }
    let (label, _) = sets.labels();
    let mut renumber: HashMap<u32, u32> = HashMap::new();
    let face_component = faces
        .iter()
        .map(|ids| {
            let l = ids
                .first()
                .map_or(u32::MAX, |&v| label[id[v as usize] as usize]);
            let next = renumber.len() as u32;
            *renumber.entry(l).or_insert(next)
        })
        .collect();
    (face_component, renumber.len())
}

/// What a layer needs to be placed: its mean normal and extent.
#[derive(Clone, Copy, Debug)]
struct Layer {
    part: u32,
    normal: DVec3,
    gap: f64,
}

/// The input's layers, per component `Some` when it is one, and the
/// input's triangles; `None` when no part is a one-way sheet (most files:
/// then no triangle index is built).
fn find_layers(
    positions: &[[f32; 3]],
    faces: &Faces,
    component: &[u32],
    count: usize,
) -> Option<(Vec<Option<Layer>>, Triangles)> {
    let p = |v: u32| DVec3::from(positions[v as usize].map(f64::from));
    let mut normal = vec![DVec3::ZERO; count];
    let mut bounds = vec![Aabb::default(); count];
    for (f, ids) in faces.iter().enumerate() {
        let c = component[f] as usize;
        for k in 1..ids.len().saturating_sub(1) {
            normal[c] += (p(ids[k]) - p(ids[0])).cross(p(ids[k + 1]) - p(ids[0]));
        }
        for &v in ids {
            bounds[c].grow(p(v));
        }
    }
    let normal: Vec<DVec3> = normal.iter().map(|n| n.normalize_or_zero()).collect();
    // One-way sheets: every face within 60° of the mean normal.
    let mut sheet: Vec<bool> = normal.iter().map(|n| *n != DVec3::ZERO).collect();
    for (f, ids) in faces.iter().enumerate() {
        let c = component[f] as usize;
        for k in 1..ids.len().saturating_sub(1) {
            let n = (p(ids[k]) - p(ids[0]))
                .cross(p(ids[k + 1]) - p(ids[0]))
                .normalize_or_zero();
            if n != DVec3::ZERO && n.dot(normal[c]) < FACING {
                sheet[c] = false;
            }
        }
    }
    if !sheet.iter().any(|&s| s) {
        return None;
    }
    let all = Triangles::new(positions, faces, |_| true);
    // Every vertex and face centre within the gap of another part facing
    // the same way.
    let mut points: Vec<Vec<DVec3>> = vec![Vec::new(); count];
    for (f, ids) in faces.iter().enumerate() {
        let c = component[f] as usize;
        if sheet[c] && !ids.is_empty() {
            let centre = ids.iter().map(|&v| p(v)).sum::<DVec3>() / ids.len() as f64;
            points[c].push(centre);
            points[c].extend(ids.iter().map(|&v| p(v)));
        }
    }
    let layers = (0..count)
        .into_par_iter()
        .map(|c| {
            if !sheet[c] {
                return None;
            }
            let gap = LAYER_GAP * bounds[c].diagonal();
            let on = points[c].iter().all(|&x| {
                let own = |t: u32| component[all.face[t as usize] as usize] as usize == c;
                all.closest(x, gap, own)
                    .is_some_and(|(t, _)| all.normals[t as usize].dot(normal[c]) >= FACING)
            });
            on.then_some(Layer {
                part: c as u32,
                normal: normal[c],
                gap,
            })
        })
        .collect();
    Some((layers, all))
}

/// Lifts the vertices of `out` that only layers use until every layer
/// triangle lies its input gap in front of the simplified surface under it
/// (see the module). Returns how many were lifted.
pub(crate) fn keep_layers(positions: &[[f32; 3]], faces: &Faces, out: &mut Simplified) -> usize {
    let (component, count) = components(positions, faces);
    if count < 2 {
        return 0;
    }
    let Some((layers, all)) = find_layers(positions, faces, &component, count) else {
        return 0;
    };
    let layer_of = |input_face: u32| layers[component[input_face as usize] as usize];
    if layers.iter().all(Option::is_none) {
        return 0;
    }
    let under = Triangles::new(positions, faces, |f| layer_of(f).is_none());
    let lod_under = Triangles::new(&out.positions, &out.faces, |f| {
        layer_of(out.face_origin[f as usize]).is_none()
    });
    if lod_under.corners.is_empty() {
        return 0;
    }
    // Vertices only layers use; one the collapses merged with the surface
    // under it cannot lift without lifting that surface.
    let mut shared = vec![false; out.positions.len()];
    for (f, ids) in out.faces.iter().enumerate() {
        if layer_of(out.face_origin[f]).is_none() {
            for &v in ids {
                shared[v as usize] = true;
            }
        }
    }
    let at = |v: u32| DVec3::from(out.positions[v as usize].map(f64::from));
    // The gap each layer vertex had in the input: from the layer's own
    // input surface nearest to it (the LOD vertex has an error of its own,
    // which may be more than the gap) to what lay under it there.
    let gap = |v: u32, layer: &Layer| -> Option<f64> {
        let other = |t: u32| component[all.face[t as usize] as usize] != layer.part;
        let (_, y) = all.closest(at(v), f64::INFINITY, other)?;
        let (i, q) = under.closest(y, layer.gap, |_| false)?;
        let n = under.normals[i as usize];
        (n.dot(layer.normal) >= FACING).then(|| (y - q).dot(n).max(0.0))
    };
    // The layer of every vertex only layers use, and its gap, once each.
    let mut vertex_layer: Vec<Option<Layer>> = vec![None; out.positions.len()];
    for (f, ids) in out.faces.iter().enumerate() {
        if let Some(layer) = layer_of(out.face_origin[f]) {
            for &v in ids {
                if !shared[v as usize] {
                    vertex_layer[v as usize] = Some(layer);
                }
            }
        }
    }
    let gaps: Vec<Option<f64>> = vertex_layer
        .par_iter()
        .enumerate()
        .map(|(v, layer)| layer.and_then(|l| gap(v as u32, &l)))
        .collect();
    // How far simplifying may have moved a surface: a bound on how far off
    // a layer triangle's box a surface point can ask it to lift (a layer
    // as large as the file would otherwise look at the whole file for each
    // of its triangles).
    let moved = 4.0 * out.report.error * all.bvh.bounds().diagonal();
    // Every layer triangle's lift: how far its vertices must move along
    // the layer's normal for it to clear the surface under it by the gap.
    let lifts: Vec<Vec<(u32, f64)>> = (0..out.faces.len())
        .into_par_iter()
        .map(|f| {
            let Some(layer) = layer_of(out.face_origin[f]) else {
                return Vec::new();
            };
            let ids = out.faces.face(f);
            if ids.iter().any(|&v| shared[v as usize]) {
                return Vec::new();
            }
            let Some(g) = ids
                .iter()
                .map(|&v| gaps[v as usize])
                .try_fold(f64::INFINITY, |g, v| v.map(|v| g.min(v)))
            else {
                return Vec::new();
            };
            let mut lifts = Vec::new();
            for k in 1..ids.len().saturating_sub(1) {
                let tri = [ids[0], ids[k], ids[k + 1]];
                let t = tri.map(at);
                let input = (&all, component.as_slice());
                let reach = layer.gap.min(g + moved);
                let Some(deficit) = deficit(&t, &lod_under, &under, input, &layer, g, reach) else {
                    continue;
                };
                let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
                let along = n.dot(layer.normal);
                if deficit > 0.0 && along >= FACING {
                    lifts.extend(tri.map(|v| (v, deficit / along)));
                }
            }
            lifts
        })
        .collect();
    let mut lift = vec![0.0f64; out.positions.len()];
    for &(v, d) in lifts.iter().flatten() {
        lift[v as usize] = lift[v as usize].max(d);
    }
    drop(lifts);
    let mut lifted = 0;
    for (v, &d) in lift.iter().enumerate() {
        if d > 0.0 {
            let n = vertex_layer[v].map_or(DVec3::ZERO, |l| l.normal);
            let x = DVec3::from(out.positions[v].map(f64::from)) + n * d;
            out.positions[v] = x.as_vec3().to_array();
            lifted += 1;
        }
    }
    lifted
}

/// How much the layer triangle `t` lacks of lying `g` in front of the
/// simplified surface `under` (along its own normal), or `None` when it is
/// degenerate. The difference of two piecewise-linear surfaces is largest
/// at a vertex of either or where their edges cross (seen along the
/// normal), so those are the points measured. At each, the layer lacks
/// what it has less than the clearance it had over the input there, up to
/// `g` (the input's surfaces under layers are `input`, the layer's own
/// input surface the faces of its part in `input_all`, whose faces' parts
/// are `component`): a surface as close to the layer in the input (a
/// cushion over a patch, a box standing on a decal) asks for nothing.
/// Only surface triangles within `reach` of the triangle's box are
/// looked at. Returns 0 when nothing is lacking.
fn deficit(
    t: &[DVec3; 3],
    under: &Triangles,
    input: &Triangles,
    (input_all, component): (&Triangles, &[u32]),
    layer: &Layer,
    g: f64,
    reach: f64,
) -> Option<f64> {
    let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
    if n == DVec3::ZERO {
        return None;
    }
    let (u, w) = n.any_orthonormal_pair();
    let flat = |p: DVec3| glam::DVec2::new(p.dot(u), p.dot(w));
    let height = n.dot(t[0]);
    let l2 = t.map(flat);
    let mut worst: f64 = 0.0;
    let mut consider = |w: DVec3| {
        let h = height - n.dot(w);
        if g - h <= worst {
            return;
        }
        // The clearance the layer had over the input's surface here: from
        // the input surface nearest `w` to the layer's own input surface
        // nearest that.
        let Some((_, q)) = input.closest(w, f64::INFINITY, |_| false) else {
            return;
        };
        let other = |t: u32| component[input_all.face[t as usize] as usize] != layer.part;
        let Some((_, y)) = input_all.closest(q, f64::INFINITY, other) else {
            return;
        };
        worst = worst.max(g.min((y - q).dot(n)) - h);
    };
    let bounds = Aabb::from_triangle(t[0], t[1], t[2]);
    // Every triangle under it counts, however steep: a simplified surface
    // can fold into a sliver standing across the layer.
    under.bvh.query_within(&bounds, reach, |b| {
        let c = under.corners[b as usize];
        let c2 = c.map(flat);
        // Its corners over the layer triangle.
        for (k, &q) in c2.iter().enumerate() {
            if barycentric(&l2, q).is_some() {
                consider(c[k]);
            }
        }
        // The layer's corners over it.
        for &q in &l2 {
            if let Some(l) = barycentric(&c2, q) {
                consider(c[0] * l[0] + c[1] * l[1] + c[2] * l[2]);
            }
        }
        // Edges crossing.
        for i in 0..3 {
            let (a0, a1) = (l2[i], l2[(i + 1) % 3]);
            for j in 0..3 {
                let (b0, b1) = (c2[j], c2[(j + 1) % 3]);
                let (da, db) = (a1 - a0, b1 - b0);
                let den = da.perp_dot(db);
                if den.abs() < 1e-300 {
                    continue;
                }
                let s = (b0 - a0).perp_dot(db) / den;
                let r = (b0 - a0).perp_dot(da) / den;
                if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&r) {
                    let (w0, w1) = (c[j], c[(j + 1) % 3]);
                    consider(w0 + (w1 - w0) * r);
                }
            }
        }
    });
    Some(worst)
}

/// Barycentric weights of `q` in the 2D triangle `t`, when it lies in it.
fn barycentric(t: &[glam::DVec2; 3], q: glam::DVec2) -> Option<[f64; 3]> {
    let d = (t[1] - t[0]).perp_dot(t[2] - t[0]);
    if d.abs() < 1e-300 {
        return None;
    }
    let l1 = (q - t[0]).perp_dot(t[2] - t[0]) / d;
    let l2 = (t[1] - t[0]).perp_dot(q - t[0]) / d;
    let l0 = 1.0 - l1 - l2;
    const EDGE: f64 = -1e-12;
    (l0 >= EDGE && l1 >= EDGE && l2 >= EDGE).then_some([l0, l1, l2])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square `size` wide at height `z` (facing +z), as one quad.
    fn square(positions: &mut Vec<[f32; 3]>, faces: &mut Faces, lo: [f32; 2], size: f32, z: f32) {
        let base = positions.len() as u32;
        for (dx, dy) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
            positions.push([lo[0] + dx * size, lo[1] + dy * size, z]);
        }
        faces.push(&[base, base + 1, base + 2, base + 3]);
    }

    /// A closed box over `lo`–`hi` in x and y, from z = 0 to `height`,
    /// its faces facing out ([`wildlod_mesh::shapes::cuboid`]), appended.
    fn closed_box(
        positions: &mut Vec<[f32; 3]>,
        faces: &mut Faces,
        lo: [f32; 2],
        hi: [f32; 2],
        height: f32,
    ) {
        let cube = wildlod_mesh::shapes::cuboid([lo[0], lo[1], 0.0], [hi[0], hi[1], height]);
        let c = positions.len() as u32;
        positions.extend_from_slice(&cube.positions);
        for ids in cube.faces.iter() {
            faces.push(&ids.iter().map(|&v| c + v).collect::<Vec<_>>());
        }
    }

    /// How many of the parts of `faces` are layers.
    fn layer_count(positions: &[[f32; 3]], faces: &Faces) -> usize {
        let (component, count) = components(positions, faces);
        find_layers(positions, faces, &component, count).map_or(0, |(layers, _)| {
            layers.iter().filter(|l| l.is_some()).count()
        })
    }

    /// An output of these faces over `positions`, every face its own
    /// origin, from a run whose collapses erred by up to 1% of the
    /// diagonal (the test surfaces move by less than 4× that).
    fn output(positions: Vec<[f32; 3]>, faces: Faces) -> Simplified {
        let n = faces.len() as u32;
        let mut out = Simplified {
            positions,
            face_origin: (0..n).collect(),
            faces,
            ..Simplified::default()
        };
        out.report.error = 0.01;
        out
    }

    #[test]
    fn a_decal_keeps_its_gap_over_a_surface_that_moved() {
        // A 10 × 10 floor at z = 0 and a 1 × 1 decal 0.01 above it.
        let (mut pos, mut faces) = (Vec::new(), Faces::default());
        square(&mut pos, &mut faces, [0.0, 0.0], 10.0, 0.0);
        square(&mut pos, &mut faces, [4.0, 4.0], 1.0, 0.01);
        // The LOD's floor rose by 0.05: the decal would be 0.04 under it.
        let mut lod_pos = pos.clone();
        for p in &mut lod_pos[..4] {
            p[2] = 0.05;
        }
        let mut out = output(lod_pos, faces.clone());
        assert_eq!(keep_layers(&pos, &faces, &mut out), 4);
        for p in &out.positions[4..] {
            assert!((p[2] - 0.06).abs() < 1e-6, "{p:?}");
        }
        // The floor itself never moves.
        assert!(out.positions[..4].iter().all(|p| p[2] == 0.05));
    }

    /// A 10 × 10 floor at z = 0 as four triangles around a centre vertex
    /// (index 4), and a decal triangle 0.01 above it around the centre.
    fn floor_and_decal() -> (Vec<[f32; 3]>, Faces) {
        let mut pos = vec![
            [0.0, 0.0, 0.0],
            [10.0, 0.0, 0.0],
            [10.0, 10.0, 0.0],
            [0.0, 10.0, 0.0],
            [5.0, 5.0, 0.0],
        ];
        let mut faces = Faces::default();
        for k in 0..4u32 {
            faces.push(&[k, (k + 1) % 4, 4]);
        }
        pos.extend([[4.0, 4.0, 0.01], [6.5, 4.5, 0.01], [4.5, 6.5, 0.01]]);
        faces.push(&[5, 6, 7]);
        (pos, faces)
    }

    #[test]
    fn a_surface_vertex_rising_under_a_layer_lifts_it_by_what_it_lacks() {
        let (pos, faces) = floor_and_decal();
        // The LOD's floor rises to 0.05 at the centre, under the decal's
        // middle: none of the decal's corners sees it.
        let mut lod = pos.clone();
        lod[4][2] = 0.05;
        let mut out = output(lod, faces.clone());
        assert_eq!(keep_layers(&pos, &faces, &mut out), 3);
        for p in &out.positions[5..] {
            assert!((p[2] - 0.06).abs() < 1e-6, "{p:?}");
        }
    }

    #[test]
    fn a_ridge_crossing_under_a_layer_lifts_it_over_the_ridge() {
        // Two floor triangles split along the diagonal (0,0)–(10,10), the
        // diagonal's ends raised to 0.1 in the LOD: a ridge whose highest
        // points under the decal are where it crosses the decal's edges,
        // higher than the floor under any of the decal's corners (0.095 at
        // most).
        let mut pos = vec![
            [0.0, 0.0, 0.0],
            [10.0, 0.0, 0.0],
            [10.0, 10.0, 0.0],
            [0.0, 10.0, 0.0],
        ];
        let mut faces = Faces::default();
        faces.push(&[0, 1, 2]);
        faces.push(&[0, 2, 3]);
        pos.extend([[4.0, 4.5, 0.01], [6.0, 4.5, 0.01], [5.0, 6.0, 0.01]]);
        faces.push(&[4, 5, 6]);
        let mut lod = pos.clone();
        lod[0][2] = 0.1;
        lod[2][2] = 0.1;
        let mut out = output(lod, faces.clone());
        assert_eq!(keep_layers(&pos, &faces, &mut out), 3);
        for p in &out.positions[4..] {
            assert!((p[2] - 0.11).abs() < 1e-6, "{p:?}");
        }
    }

    #[test]
    fn a_surface_already_in_front_of_a_layer_in_the_input_does_not_lift_it() {
        // A closed box stands on the floor over a corner of the decal (a
        // cushion over a patch): its top is 0.02 in front of the decal,
        // in the input as in the LOD. Only what simplifying moved counts.
        let (mut pos, mut faces) = floor_and_decal();
        closed_box(&mut pos, &mut faces, [3.0, 3.0], [4.5, 4.5], 0.03);
        let mut out = output(pos.clone(), faces.clone());
        assert_eq!(keep_layers(&pos, &faces, &mut out), 0);
        assert_eq!(out.positions, pos);
    }

    #[test]
    fn tiles_that_only_meet_at_their_edges_are_not_layers() {
        // A 3 × 3 floor of separate coplanar tiles: every corner touches a
        // neighbour, but no tile lies on another.
        let (mut pos, mut faces) = (Vec::new(), Faces::default());
        for j in 0..3 {
            for i in 0..3 {
                square(&mut pos, &mut faces, [i as f32, j as f32], 1.0, 0.0);
            }
        }
        assert_eq!(layer_count(&pos, &faces), 0);
        // One more tile on top of the middle one is.
        square(&mut pos, &mut faces, [1.25, 1.25], 0.5, 0.01);
        assert_eq!(layer_count(&pos, &faces), 1);
    }

    #[test]
    fn a_closed_box_or_a_sheet_facing_away_is_not_a_layer() {
        let (mut pos, mut faces) = (Vec::new(), Faces::default());
        square(&mut pos, &mut faces, [0.0, 0.0], 10.0, 0.0);
        // Facing down, 0.01 above the floor: its back is what shows.
        let b = pos.len() as u32;
        square(&mut pos, &mut faces, [4.0, 4.0], 1.0, 0.01);
        let last = faces.len() - 1;
        let mut flipped = Faces::default();
        for f in 0..last {
            flipped.push(faces.face(f));
        }
        flipped.push(&[b + 3, b + 2, b + 1, b]);
        // A unit cube resting on the floor.
        closed_box(&mut pos, &mut flipped, [6.0, 6.0], [7.0, 7.0], 1.0);
        assert_eq!(layer_count(&pos, &flipped), 0);
        let mut lod = pos.clone();
        for p in &mut lod[..4] {
            p[2] = 0.05;
        }
        let mut out = output(lod.clone(), flipped.clone());
        assert_eq!(keep_layers(&pos, &flipped, &mut out), 0);
        assert_eq!(out.positions, lod);
        // The same sheet facing up is one.
        assert_eq!(layer_count(&pos, &faces), 1);
    }

    #[test]
    fn a_layer_triangle_merged_into_the_surface_stays() {
        // A floor and a decal of two triangles, 0.01 above it.
        let (mut pos, mut faces) = (Vec::new(), Faces::default());
        square(&mut pos, &mut faces, [0.0, 0.0], 10.0, 0.0);
        pos.extend([
            [4.0, 4.0, 0.01],
            [5.0, 4.0, 0.01],
            [5.0, 5.0, 0.01],
            [4.0, 5.0, 0.01],
        ]);
        faces.push(&[4, 5, 6]);
        faces.push(&[4, 6, 7]);
        // In the LOD the floor rose by 0.05 and the collapses merged the
        // decal's corner 5 into the floor's corner 1: the triangle using
        // it cannot lift without lifting the floor.
        let mut lod = pos.clone();
        for p in &mut lod[..4] {
            p[2] = 0.05;
        }
        let mut lod_faces = Faces::default();
        lod_faces.push(&[0, 1, 2, 3]);
        lod_faces.push(&[4, 1, 6]);
        lod_faces.push(&[4, 6, 7]);
        let mut out = output(lod.clone(), lod_faces);
        out.face_origin = vec![0, 1, 2];
        assert_eq!(keep_layers(&pos, &faces, &mut out), 3);
        assert_eq!(out.positions[1], lod[1]);
        for v in [4, 6, 7] {
            assert!((out.positions[v][2] - 0.06).abs() < 1e-6);
        }
    }
}
