//! Topology statistics of a mesh, as `wildlod info` reports them: computed
//! on welded positions (see [`crate::weld`]) and polygon edges.

use std::collections::{HashMap, HashSet};

use crate::attribute::{Semantic, ABSENT};
use crate::disjoint_sets::DisjointSets;
use crate::mesh::Mesh;
use crate::weld::{position_key, weld_positions, PositionHasher};

/// Topology of one mesh after welding equal positions.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TopologyStats {
    /// Distinct positions used by faces.
    pub welded_vertices: usize,
    /// Connected components (faces sharing a welded vertex are connected).
    pub components: usize,
    /// Edges used by exactly one face corner pair.
    pub boundary_edges: usize,
    /// Edges used three or more times.
    pub nonmanifold_edges: usize,
    /// Faces with a repeated welded vertex.
    pub degenerate_faces: usize,
    /// Faces with the same welded vertex set as an earlier face.
    pub duplicate_faces: usize,
    /// Connected components in UV set 0 (faces sharing a corner with the same
    /// position and UV), or `None` without UVs.
    pub uv_islands: Option<usize>,
}

/// Computes [`TopologyStats`]. Assumes a mesh that passed `validate()`;
/// out-of-range indices are skipped rather than trusted.
pub fn topology(mesh: &Mesh) -> TopologyStats {
    let (weld, _) = weld_positions(&mesh.positions);
    let nv = mesh.positions.len();
    let id = |v: u32| -> Option<u32> { weld.get(v as usize).copied() };

    let mut used = vec![false; nv];
    let mut sets = DisjointSets::new(nv);
    let mut edges: Vec<u64> = Vec::with_capacity(mesh.faces.corner_count());
    let mut degenerate = 0;
    let mut sorted: Vec<u32> = Vec::with_capacity(mesh.faces.corner_count());
    let mut keys: Vec<(usize, usize)> = Vec::with_capacity(mesh.faces.len());
    for face in mesh.faces.iter() {
        let ids: Vec<u32> = face.iter().filter_map(|&v| id(v)).collect();
        let start = sorted.len();
        sorted.extend_from_slice(&ids);
        sorted[start..].sort_unstable();
        let s = &sorted[start..];
        if s.windows(2).any(|w| w[0] == w[1]) {
            degenerate += 1;
        }
        keys.push((start, sorted.len()));
        for (k, &a) in ids.iter().enumerate() {
            used[a as usize] = true;
            let b = ids[(k + 1) % ids.len()];
            sets.union(a, b);
            if a != b {
                edges.push(((a.min(b) as u64) << 32) | a.max(b) as u64);
            }
        }
    }
    edges.sort_unstable();
    let (mut boundary, mut nonmanifold) = (0, 0);
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && edges[j] == edges[i] {
            j += 1;
        }
        match j - i {
            1 => boundary += 1,
            2 => {}
            _ => nonmanifold += 1,
        }
        i = j;
    }
    let mut seen: HashSet<&[u32]> = HashSet::with_capacity(keys.len());
    let duplicate = keys
        .iter()
        .filter(|&&(a, b)| !seen.insert(&sorted[a..b]))
        .count();
    // `used` and `sets` are indexed by welded id.
    let mut roots = HashSet::new();
    let mut welded = 0;
    for (v, _) in used.iter().enumerate().filter(|(_, &u)| u) {
        roots.insert(sets.find(v as u32));
        welded += 1;
    }
    TopologyStats {
        welded_vertices: welded,
        components: roots.len(),
        boundary_edges: boundary,
        nonmanifold_edges: nonmanifold,
        degenerate_faces: degenerate,
        duplicate_faces: duplicate,
        uv_islands: uv_islands(mesh, &weld),
    }
}

/// UV islands of set 0 as [`TopologyStats::uv_islands`] counts them:
/// faces sharing a corner with the same welded position and UV are one
/// island. For every face, its island's id (`0..count`, in order of the
/// islands' first faces; [`ABSENT`] for a face without UVs), and the
/// count; `None` without a UV set.
pub fn uv_island_ids(mesh: &Mesh) -> Option<(Vec<u32>, usize)> {
    let (weld, _) = weld_positions(&mesh.positions);
    uv_island_labels(mesh, &weld)
}

fn uv_islands(mesh: &Mesh, weld: &[u32]) -> Option<usize> {
    uv_island_labels(mesh, weld).map(|(_, count)| count)
}

fn uv_island_labels(mesh: &Mesh, weld: &[u32]) -> Option<(Vec<u32>, usize)> {
    let uv = mesh.attribute(&Semantic::TexCoord(0))?;
    let nf = mesh.faces.len();
    let mut sets = DisjointSets::new(nf);
    let mut first: HashMap<(u32, [u32; 3]), u32, std::hash::BuildHasherDefault<PositionHasher>> =
        HashMap::default();
    let mut has_uv = vec![false; nf];
    for (f, has) in has_uv.iter_mut().enumerate() {
        for c in mesh.faces.corner_range(f) {
            let i = uv.indices[c];
            if i == ABSENT || i as usize >= uv.value_count() {
                continue;
            }
            *has = true;
            let val = uv.value(i);
            let key = position_key(&[val[0], *val.get(1).unwrap_or(&0.0), 0.0]);
            let v = weld[mesh.faces.indices[c] as usize];
            let g = *first.entry((v, key)).or_insert(f as u32);
            sets.union(g, f as u32);
        }
    }
    let mut ids = vec![ABSENT; nf];
    let mut label: HashMap<u32, u32> = HashMap::new();
    for (f, _) in has_uv.iter().enumerate().filter(|(_, &h)| h) {
        let root = sets.find(f as u32);
        let next = label.len() as u32;
        ids[f] = *label.entry(root).or_insert(next);
    }
    Some((ids, label.len()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Attribute, ComponentFormat};

    /// Two unit squares as quads, sharing the edge x = 1:
    /// ```text
    /// 3---4---5
    /// |   |   |
    /// 0---1---2
    /// ```
    fn two_quads() -> Mesh {
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
            [2.0, 1.0, 0.0],
        ];
        let mut f = crate::Faces::new();
        f.push(&[0, 1, 4, 3]);
        f.push(&[1, 2, 5, 4]);
        Mesh::from_polygons(p, f)
    }

    #[test]
    fn two_quads_have_six_boundary_edges_and_one_component() {
        let s = topology(&two_quads());
        assert_eq!(s.boundary_edges, 6);
        assert_eq!(s.nonmanifold_edges, 0);
        assert_eq!(s.components, 1);
        assert_eq!(s.welded_vertices, 6);
        assert_eq!(s.uv_islands, None);
    }

    #[test]
    fn soup_welds_and_duplicates_and_degenerates_are_counted() {
        // Triangle 0-1-2 stored twice with private vertices, plus a
        // degenerate one (3 == 4 after welding) and a far triangle.
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [5.0, 5.0, 5.0],
            [6.0, 5.0, 5.0],
            [5.0, 6.0, 5.0],
        ];
        let m = Mesh::from_triangles(p, &[0, 1, 2, 3, 4, 5, 0, 3, 1, 6, 7, 8]);
        let s = topology(&m);
        assert_eq!(s.welded_vertices, 6);
        assert_eq!(s.duplicate_faces, 1);
        assert_eq!(s.degenerate_faces, 1);
        assert_eq!(s.components, 2);
        // Edge 0-1 is used by the two copies and twice by the degenerate face.
        assert_eq!(s.nonmanifold_edges, 1);
    }

    #[test]
    fn uv_seam_splits_islands() {
        let mut m = two_quads();
        // Corners of the shared edge carry different UVs in the two quads.
        m.attributes.push(Attribute {
            semantic: Semantic::TexCoord(0),
            components: 2,
            values: (0..8).flat_map(|i| [i as f32, 0.0]).collect(),
            indices: vec![0, 1, 2, 3, 4, 5, 6, 7],
            format: ComponentFormat::F32,
        });
        assert_eq!(topology(&m).uv_islands, Some(2));
        assert_eq!(uv_island_ids(&m), Some((vec![0, 1], 2)));
        m.attributes[0].indices = vec![0, 1, 2, 3, 1, 4, 5, 2];
        assert_eq!(topology(&m).uv_islands, Some(1));
        assert_eq!(uv_island_ids(&m), Some((vec![0, 0], 1)));
        // A face without UVs belongs to no island.
        m.attributes[0].indices[4..].fill(ABSENT);
        assert_eq!(uv_island_ids(&m), Some((vec![0, ABSENT], 1)));
    }
}
