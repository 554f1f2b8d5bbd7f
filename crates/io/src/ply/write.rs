//! A scene → binary little-endian PLY.
//!
//! PLY attributes are per vertex while the model's are per corner: a vertex
//! is written for every distinct (position, UV, normal, color) combination
//! the corners use. When every stream is already indexed like the positions
//! (a mesh read from PLY, or one without attributes) the positions are
//! written as stored, unused ones included. Texture v goes back to PLY's
//! bottom-left origin bit-exactly: `t` is a 32-bit float when that can give
//! every written v back, else a 64-bit one (see `v_fits_f32`). Positions
//! are 64-bit when a mesh lies far from the origin (survey coordinates,
//! see `crate::far`), else 32-bit.

use std::collections::{BTreeSet, HashMap};
use std::hash::BuildHasherDefault;
use std::path::Path;

use wildlod_mesh::weld::PositionHasher;
use wildlod_mesh::{Attribute, ComponentFormat, Mesh, Scene, Semantic, ABSENT};

use crate::obj::text::{v_fits_f32, v_to_f32};
use crate::{ErrorKind, OutputFiles};

/// The streams PLY vertices can carry, in key order.
const UV: usize = 1;
const NORMAL: usize = 2;
const COLOR: usize = 3;

/// One mesh's output vertices and the vertex of every corner.
struct VertexMap {
    /// Per output vertex: its position and the UV, normal and color value
    /// indices of the first corner that uses it (`ABSENT`: no value).
    vertices: Vec<[u32; 4]>,
    corners: Vec<u32>,
}

/// The streams of `mesh` that PLY writes: UV set 0, normals, color set 0.
fn streams(mesh: &Mesh) -> [Option<&Attribute>; 4] {
    let find = |s: Semantic, min: u8| {
        mesh.attributes
            .iter()
            .find(|a| a.semantic == s && a.components >= min)
    };
    [
        None,
        find(Semantic::TexCoord(0), 2),
        find(Semantic::Normal, 3).filter(|a| a.components == 3),
        find(Semantic::Color(0), 3),
    ]
}

fn vertex_map(mesh: &Mesh) -> VertexMap {
    let s = streams(mesh);
    let n = mesh.positions.len();
    let direct = s
        .iter()
        .flatten()
        .all(|a| a.value_count() >= n && a.indices.iter().eq(mesh.faces.indices.iter()));
    if direct {
        let key = |v: u32| {
            let mut k = [v; 4];
            for (slot, a) in k.iter_mut().zip(&s).skip(1) {
                if a.is_none() {
                    *slot = ABSENT;
                }
            }
            k
        };
        return VertexMap {
            vertices: (0..n as u32).map(key).collect(),
            corners: mesh.faces.indices.clone(),
        };
    }
    // Keyed by position index and attribute *values*: corners that repeat
    // a value under another index still share a vertex.
    let mut ids: HashMap<[u32; 10], u32, BuildHasherDefault<PositionHasher>> =
        HashMap::with_capacity_and_hasher(n, Default::default());
    let mut vertices = Vec::with_capacity(n);
    let corners = (0..mesh.faces.indices.len())
        .map(|c| {
            let mut k = [mesh.faces.indices[c], ABSENT, ABSENT, ABSENT];
            for (slot, a) in k.iter_mut().zip(&s).skip(1) {
                if let Some(a) = a {
                    *slot = a.indices.get(c).copied().unwrap_or(ABSENT);
                }
            }
            let mut key = [ABSENT; 10];
            key[0] = k[0];
            let mut at = 1;
            for (i, len) in [(UV, 2), (NORMAL, 3), (COLOR, 4)] {
                if let (Some(a), true) = (s[i], k[i] != ABSENT) {
                    for (j, v) in a.value(k[i]).iter().take(len).enumerate() {
                        key[at + j] = v.to_bits();
                    }
                }
                at += len;
            }
            *ids.entry(key).or_insert_with(|| {
                vertices.push(k);
                (vertices.len() - 1) as u32
            })
        })
        .collect();
    VertexMap { vertices, corners }
}

/// Writes the scene's mesh instances, moved by their world matrices, into
/// one binary PLY.
pub(crate) fn write(scene: &Scene, path: &Path, files: &mut OutputFiles) -> Result<(), ErrorKind> {
    let (meshes, exact) = crate::far::world_meshes(scene);
    // Survey coordinates: every position in f64 once one mesh needs it.
    let p_f64 = exact.iter().any(Option::is_some);
    let mut dropped = BTreeSet::new();
    note_drops(scene, &meshes, &mut dropped);

    let has = |k: usize| meshes.iter().any(|m| streams(m)[k].is_some());
    let (has_uv, has_normal, has_color) = (has(UV), has(NORMAL), has(COLOR));
    let color_components = meshes
        .iter()
        .filter_map(|m| streams(m)[COLOR])
        .map(|a| a.components.min(4))
        .max()
        .unwrap_or(3);
    // Bytes only when every source was bytes: floats would not survive
    // quantization bit-exactly.
    let color_u8 = meshes
        .iter()
        .filter_map(|m| streams(m)[COLOR])
        .all(|a| a.format == ComponentFormat::U8Norm);

    let maps: Vec<VertexMap> = meshes.iter().map(vertex_map).collect();
    // Most v below 0.5 (or outside [0, 1]) read from OBJ text or glTF have
    // no 32-bit t = 1 − v that gives them back; the exact 64-bit one does.
    let t_f64 = meshes.iter().zip(&maps).any(|(m, map)| {
        streams(m)[UV].is_some_and(|a| {
            map.vertices
                .iter()
                .filter(|k| k[UV] != ABSENT)
                .any(|k| a.value(k[UV]).get(1).is_some_and(|&v| !v_fits_f32(v)))
        })
    });
    let vertex_total: u64 = maps.iter().map(|m| m.vertices.len() as u64).sum();
    let face_total: u64 = meshes.iter().map(|m| m.faces.len() as u64).sum();
    if vertex_total > u32::MAX as u64 {
        return Err(ErrorKind::Unsupported(format!(
            "{vertex_total} vertices do not fit 32-bit PLY indices"
        )));
    }
    let max_arity = meshes
        .iter()
        .flat_map(|m| m.faces.iter().map(|f| f.len()))
        .max()
        .unwrap_or(3);
    let wide_count = max_arity > u8::MAX as usize;
    let wide_index = vertex_total > i32::MAX as u64;

    let mut head =
        String::from("ply\nformat binary_little_endian 1.0\ncomment generated by wildlod\n");
    head += &format!("element vertex {vertex_total}\n");
    head += if p_f64 {
        "property double x\nproperty double y\nproperty double z\n"
    } else {
        "property float x\nproperty float y\nproperty float z\n"
    };
    if has_normal {
        head += "property float nx\nproperty float ny\nproperty float nz\n";
    }
    if has_uv {
        head += "property float s\n";
        head += if t_f64 {
            "property double t\n"
        } else {
            "property float t\n"
        };
    }
    let color_type = if color_u8 { "uchar" } else { "float" };
    if has_color {
        for c in ["red", "green", "blue", "alpha"]
            .iter()
            .take(color_components as usize)
        {
            head += &format!("property {color_type} {c}\n");
        }
    }
    head += &format!("element face {face_total}\n");
    head += &format!(
        "property list {} {} vertex_indices\nend_header\n",
        if wide_count { "uint" } else { "uchar" },
        if wide_index { "uint" } else { "int" }
    );

    let mut out = head.into_bytes();
    let mut filled = false;
    for ((mesh, map), exact) in meshes.iter().zip(&maps).zip(&exact) {
        let s = streams(mesh);
        for key in &map.vertices {
            let p = mesh
                .positions
                .get(key[0] as usize)
                .copied()
                .unwrap_or_default();
            if p_f64 {
                let q = exact
                    .as_ref()
                    .and_then(|e| e.get(key[0] as usize).copied())
                    .unwrap_or(p.map(f64::from));
                for c in q {
                    out.extend_from_slice(&c.to_le_bytes());
                }
            } else {
                put(&mut out, &p);
            }
            let mut value = |k: usize, n: usize, out: &mut Vec<u8>, as_u8: bool| {
                let v = s[k].filter(|_| key[k] != ABSENT).map(|a| a.value(key[k]));
                if v.is_none() {
                    filled = true;
                }
                for i in 0..n {
                    // Missing alpha is opaque; other missing values are 0.
                    let default = if k == COLOR && i == 3 { 1.0 } else { 0.0 };
                    let mut x = v.and_then(|v| v.get(i).copied()).unwrap_or(default);
                    if k == UV && i == 1 {
                        if t_f64 {
                            out.extend_from_slice(&(1.0 - x as f64).to_le_bytes());
                            continue;
                        }
                        x = v_to_f32(x);
                    }
                    if as_u8 {
                        out.push((x.clamp(0.0, 1.0) * 255.0).round() as u8);
                    } else {
                        out.extend_from_slice(&x.to_le_bytes());
                    }
                }
            };
            if has_normal {
                value(NORMAL, 3, &mut out, false);
            }
            if has_uv {
                value(UV, 2, &mut out, false);
            }
            if has_color {
                value(COLOR, color_components as usize, &mut out, color_u8);
            }
        }
    }
    let mut base = 0u32;
    for (mesh, map) in meshes.iter().zip(&maps) {
        for f in 0..mesh.faces.len() {
            let r = mesh.faces.corner_range(f);
            if wide_count {
                out.extend_from_slice(&(r.len() as u32).to_le_bytes());
            } else {
                out.push(r.len() as u8);
            }
            for c in r {
                let v = map.corners.get(c).copied().unwrap_or(0) + base;
                // `int` indices are written only when every index fits i32.
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        base += map.vertices.len() as u32;
    }
    files.add(path, out)?;
    if filled {
        files.warn("PLY vertices need every attribute: corners without a UV, normal or color were written with zeros");
    }
    for d in dropped {
        files.warn(format!("PLY cannot hold {d}; dropped"));
    }
    Ok(())
}

fn put(out: &mut Vec<u8>, v: &[f32]) {
    for c in v {
        out.extend_from_slice(&c.to_le_bytes());
    }
}

fn note_drops(scene: &Scene, meshes: &[Mesh], dropped: &mut BTreeSet<String>) {
    let parts: usize = meshes.iter().map(|m| m.parts.len()).sum();
    if parts > 1
        || meshes
            .iter()
            .any(|m| m.parts.iter().any(|p| p.material.is_some()))
    {
        dropped.insert("parts or materials".into());
    }
    for m in meshes {
        let kept = streams(m);
        for a in &m.attributes {
            if kept.iter().flatten().any(|k| std::ptr::eq(*k, a)) {
                continue;
            }
            dropped.insert(match &a.semantic {
                Semantic::TexCoord(_) => "UV sets beyond the first".into(),
                Semantic::Color(_) => "vertex color sets beyond the first".into(),
                Semantic::Normal => "normals without 3 components".into(),
                Semantic::Tangent => "tangents".into(),
                Semantic::Morph { .. } => "morph targets".into(),
                Semantic::Custom(n) => format!("the custom attribute '{n}'"),
            });
        }
        if m.skinning.is_some() {
            dropped.insert("skin weights".into());
        }
    }
    if !scene.animations.is_empty() {
        dropped.insert("animations".into());
    }
    if !scene.skins.is_empty() {
        dropped.insert("skins".into());
    }
}
