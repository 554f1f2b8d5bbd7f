//! The seed corpus, generated in code: small files of every input format,
//! written by wildlod's own writers (so they cover what the writers emit)
//! and by hand (so they cover what other exporters write: polygons,
//! negative indices, groups, materials, ASCII and big-endian PLY, data
//! URIs, a node hierarchy).
//!
//! `cargo run -p wildlod-fuzz --bin seed-corpus -- fuzz/corpus` writes them
//! where `cargo fuzz` looks for them.

use std::path::Path;

use wildlod_io::{Document, WriteOptions};
use wildlod_mesh::{
    shapes, Attribute, ComponentFormat, ImageSource, Material, Mesh, Node, Part, Scene, Semantic,
    Texture, TextureRef, IDENTITY,
};

use crate::{InputFormat, SIDECAR_MARKER};

/// The seeds of one input format (each a complete fuzz input: for OBJ and
/// glTF, main file, [`SIDECAR_MARKER`] and sidecar).
pub fn seeds(format: InputFormat) -> Vec<Vec<u8>> {
    let mut out = written(format);
    out.extend(handwritten(format));
    out
}

/// A small scene with what a writer can express: two meshes (one with
/// quads and UVs, one with a pentagon), two materials sharing a texture, a
/// parent node with a transform and a child instancing both.
pub fn sample_scene() -> Scene {
    let mut grid = shapes::quad_grid(2, 2);
    grid.name = "grid".into();
    grid.parts = vec![
        Part {
            name: "a".into(),
            material: Some(0),
        },
        Part {
            name: "b".into(),
            material: Some(1),
        },
    ];
    grid.face_parts = vec![0, 0, 1, 1];
    let mut cap = Mesh::from_polygons(
        vec![
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.2, 0.8, 1.0],
            [0.5, 1.3, 1.0],
            [-0.2, 0.8, 1.0],
        ],
        {
            let mut f = wildlod_mesh::Faces::new();
            f.push(&[0, 1, 2, 3, 4]);
            f
        },
    );
    cap.name = "cap".into();
    cap.attributes.push(Attribute {
        semantic: Semantic::Normal,
        components: 3,
        values: vec![0.0, 0.0, 1.0],
        indices: vec![0; 5],
        format: ComponentFormat::F32,
    });
    let texture = Some(TextureRef {
        texture: 0,
        tex_coord: 0,
    });
    let mut translate = IDENTITY;
    translate[12] = 2.0;
    Scene {
        meshes: vec![grid, cap],
        materials: vec![
            Material {
                name: "red".into(),
                base_color: [1.0, 0.0, 0.0, 1.0],
                base_color_texture: texture,
                ..Material::default()
            },
            Material {
                name: "blue".into(),
                base_color: [0.0, 0.0, 1.0, 0.5],
                base_color_texture: texture,
                ..Material::default()
            },
        ],
        textures: vec![Texture {
            name: "checker".into(),
            source: ImageSource::Embedded {
                bytes: TINY_PNG.to_vec(),
                mime_type: "image/png".into(),
            },
            sampler: Default::default(),
        }],
        nodes: vec![
            Node {
                name: "parent".into(),
                matrix: translate,
                mesh: Some(0),
                children: vec![1],
                ..Node::default()
            },
            Node {
                name: "child".into(),
                mesh: Some(1),
                ..Node::default()
            },
        ],
        roots: vec![0],
        ..Scene::default()
    }
}

/// A 1×1 PNG, so that image paths of the seeds lead somewhere.
pub const TINY_PNG: &[u8] = &[
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52,
    0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x02, 0x00, 0x00, 0x00, 0x90, 0x77, 0x53,
    0xde, 0x00, 0x00, 0x00, 0x0c, 0x49, 0x44, 0x41, 0x54, 0x08, 0xd7, 0x63, 0xf8, 0xcf, 0xc0, 0x00,
    0x00, 0x03, 0x01, 0x01, 0x00, 0x18, 0xdd, 0x8d, 0xb0, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e,
    0x44, 0xae, 0x42, 0x60, 0x82,
];

/// Seeds written by wildlod's writers.
fn written(format: InputFormat) -> Vec<Vec<u8>> {
    let Ok(dir) = tempfile::tempdir() else {
        return Vec::new();
    };
    let mut scenes = vec![
        sample_scene(),
        Scene::from_mesh(shapes::triangulate(&shapes::torus(6, 4, 1.0, 0.3))),
        Scene::from_mesh(shapes::box_grid([0.0; 3], [1.0, 0.5, 0.25], 2)),
    ];
    // Two touching boxes that share no vertex: virtual edges.
    scenes.push(Scene::from_mesh(shapes::merge(&[
        shapes::cuboid([0.0; 3], [1.0; 3]),
        shapes::cuboid([1.0, 0.0, 0.0], [2.0, 0.5, 0.5]),
    ])));
    let mut out = Vec::new();
    for (k, scene) in scenes.into_iter().enumerate() {
        let sub = dir.path().join(k.to_string());
        if std::fs::create_dir(&sub).is_err() {
            continue;
        }
        if let Some(bytes) = write_one(&Document::from_scene(scene), &sub, format) {
            out.push(bytes);
        }
    }
    out
}

/// Writes `doc` as `in.<ext>` in `dir` and returns the fuzz input: the main
/// file, and for OBJ/glTF the marker and the sidecar the input names.
fn write_one(doc: &Document, dir: &Path, format: InputFormat) -> Option<Vec<u8>> {
    let main = dir.join(format!("in.{}", format.extension()));
    wildlod_io::write(doc, &main, &WriteOptions::default()).ok()?;
    let mut bytes = std::fs::read(&main).ok()?;
    match format {
        InputFormat::Obj => {
            // The writer names its library `in.mtl`; the fuzz input's
            // sidecar is `m.mtl`.
            if let Ok(mtl) = std::fs::read(dir.join("in.mtl")) {
                let text = String::from_utf8_lossy(&bytes).replace("mtllib in.mtl", "mtllib m.mtl");
                bytes = text.into_bytes();
                bytes.extend_from_slice(SIDECAR_MARKER);
                bytes.extend_from_slice(&mtl);
            }
        }
        InputFormat::Gltf => {
            if let Ok(bin) = std::fs::read(dir.join("in.bin")) {
                bytes.extend_from_slice(SIDECAR_MARKER);
                bytes.extend_from_slice(&bin);
            }
        }
        _ => {}
    }
    Some(bytes)
}

/// Seeds in the styles of other exporters.
fn handwritten(format: InputFormat) -> Vec<Vec<u8>> {
    match format {
        InputFormat::Obj => vec![
            [OBJ_MIXED.as_bytes(), SIDECAR_MARKER, MTL_SAMPLE.as_bytes()].concat(),
            OBJ_NEGATIVE.as_bytes().to_vec(),
        ],
        InputFormat::Ply => vec![PLY_ASCII.as_bytes().to_vec(), ply_big_endian()],
        InputFormat::Stl => vec![STL_ASCII.as_bytes().to_vec()],
        InputFormat::Off => vec![OFF_COLORED.as_bytes().to_vec()],
        InputFormat::Gltf => vec![GLTF_DATA_URI.as_bytes().to_vec()],
        InputFormat::Glb => vec![glb_of(GLTF_DATA_URI.as_bytes())],
    }
}

/// OFF as geometry data sets write it: comments, counts on the header
/// line, integer vertex colors, a quad, a face color and a two-vertex face.
const OFF_COLORED: &str = "# a hand-written COFF
COFF 5 4 0
0 0 0 255 0 0 255
1 0 0 0 255 0 255
1 1 0 0 0 255 255
0 1 0 255 255 0 255
0.5 0.5 1 1 1 1 1
4 0 1 2 3
3 0 1 4 0.5 0.5 0.5
3 1 2 4
2 3 4
";

const OBJ_MIXED: &str = "# quads, an n-gon, groups, materials, v/vt/vn
mtllib m.mtl
o body
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0.5 1.5 0
v 0 0 1
v 1 0 1 \\
  0.5 0.5 0.5
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
g front
usemtl red
f 1/1/1 2/2/1 3/3/1 4/4/1
f 4/4 3/3 5/1
g side
usemtl blue
f 1//1 2//1 7//1 6//1
s off
f 1 6 7 2 3 5 4
l 1 2
";

const MTL_SAMPLE: &str = "newmtl red
Kd 1 0 0
Ks 0.5 0.5 0.5
Ns 20
d 1
map_Kd tex.png
newmtl blue
Kd 0 0 1
Tr 0.25
map_Bump -bm 1 normal.png
map_Pr rough.png
";

const OBJ_NEGATIVE: &str = "v -1 -1 0
v 1 -1 0
v 1 1 0
v -1 1 0
f -4 -3 -2 -1
v 0 0 1
f -5 -4 -1
f -4 -3 -1
";

const PLY_ASCII: &str = "ply
format ascii 1.0
comment made by hand
element vertex 5
property float x
property float y
property float z
property float nx
property float ny
property float nz
property uchar red
property uchar green
property uchar blue
property float s
property float t
element face 2
property list uchar int vertex_indices
end_header
0 0 0 0 0 1 255 0 0 0 0
1 0 0 0 0 1 0 255 0 1 0
1 1 0 0 0 1 0 0 255 1 1
0 1 0 0 0 1 255 255 0 0 1
0.5 1.5 0 0 0 1 0 255 255 0.5 1
4 0 1 2 3
3 3 2 4
";

/// A binary big-endian PLY: a quad and a triangle.
fn ply_big_endian() -> Vec<u8> {
    let mut b = b"ply\nformat binary_big_endian 1.0\nelement vertex 5\nproperty float x\n\
property float y\nproperty float z\nelement face 2\nproperty list uchar uint vertex_indices\n\
end_header\n"
        .to_vec();
    let vs = [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 1.5, 0.5],
    ];
    for v in vs {
        for c in v {
            b.extend_from_slice(&c.to_be_bytes());
        }
    }
    for face in [&[0u32, 1, 2, 3][..], &[3, 2, 4]] {
        b.push(face.len() as u8);
        for &i in face {
            b.extend_from_slice(&i.to_be_bytes());
        }
    }
    b
}

const STL_ASCII: &str = "solid hand
facet normal 0 0 1
 outer loop
  vertex 0 0 0
  vertex 1 0 0
  vertex 0 1 0
 endloop
endfacet
facet normal 0 0 -1
 outer loop
  vertex 0 0 0
  vertex 0 1 0
  vertex 1 0 0
 endloop
endfacet
endsolid hand
";

/// A glTF with its buffer in a data URI: one triangle, instanced by a
/// child node under a translated parent, with a material.
const GLTF_DATA_URI: &str = r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
"nodes":[{"name":"root","translation":[1,0,0],"children":[1]},{"name":"leaf","mesh":0,"scale":[1,2,1]}],
"meshes":[{"name":"tri","primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0}]}],
"materials":[{"name":"m","pbrMetallicRoughness":{"baseColorFactor":[1,0.5,0.25,1]}}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}],
"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],
"buffers":[{"byteLength":44,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}]}"#;

/// A GLB holding `json` (its buffers keep their data URIs).
fn glb_of(json: &[u8]) -> Vec<u8> {
    let mut chunk = json.to_vec();
    while chunk.len() % 4 != 0 {
        chunk.push(b' ');
    }
    let total = 12 + 8 + chunk.len();
    let mut b = Vec::with_capacity(total);
    b.extend_from_slice(b"glTF");
    b.extend_from_slice(&2u32.to_le_bytes());
    b.extend_from_slice(&(total as u32).to_le_bytes());
    b.extend_from_slice(&(chunk.len() as u32).to_le_bytes());
    b.extend_from_slice(b"JSON");
    b.extend_from_slice(&chunk);
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_format_has_seeds_that_read() {
        for format in InputFormat::ALL {
            let seeds = seeds(format);
            assert!(seeds.len() >= 3, "{format:?}: {} seeds", seeds.len());
            let dir = tempfile::tempdir().unwrap();
            for (k, seed) in seeds.iter().enumerate() {
                let (main, sidecar) = crate::files::split_sidecar(format, seed);
                let path = dir.path().join(format!("in.{}", format.extension()));
                std::fs::write(&path, main).unwrap();
                if let (Some(name), Some(bytes)) = (format.sidecar(), sidecar) {
                    std::fs::write(dir.path().join(name), bytes).unwrap();
                }
                let doc = wildlod_io::read(&path)
                    .unwrap_or_else(|e| panic!("{format:?} seed {k} does not read: {e}"));
                assert!(
                    doc.scene.meshes.iter().any(|m| !m.faces.is_empty()),
                    "{format:?} seed {k} has no face"
                );
            }
        }
    }
}
