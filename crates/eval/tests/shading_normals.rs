//! The shading-normal Chamfer distance against hand-computed frames: a
//! constant normal map on a flat quad tilts the shading normal by exactly
//! the map's tilt, in the MikkTSpace frame glTF defines.

use glam::DVec3;
use wildlod_eval::{compare, CompareOptions, EvalMesh};
use wildlod_mesh::{
    shapes, Attribute, ComponentFormat, Faces, Image, ImageSource, Material, Mesh, Scene, Semantic,
    Texture, TextureRef,
};

/// The unit square in z = 0 facing +z, as two triangles, with glTF UVs
/// (`u = x`, `v = 1 − y`: the image's top row at y = 1, not mirrored):
///
/// ```text
///  3 ─── 2    (0,0) ─── (1,0)   uv
///  │  ╱  │      │         │
///  0 ─── 1    (0,1) ─── (1,1)
/// ```
fn gltf_quad() -> Mesh {
    let positions = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let mut m = Mesh::from_polygons(
        positions.clone(),
        Faces::from_triangles(&[0, 1, 2, 0, 2, 3]),
    );
    let uv: Vec<f32> = positions.iter().flat_map(|p| [p[0], 1.0 - p[1]]).collect();
    let indices = m.faces.indices.clone();
    m.attributes.push(Attribute {
        semantic: Semantic::TexCoord(0),
        components: 2,
        values: uv,
        indices,
        format: ComponentFormat::F32,
    });
    m
}

/// `mesh` with one material; with a normal map (texture 0) when `mapped`.
fn scene(mut mesh: Mesh, mapped: bool) -> Scene {
    mesh.parts[0].material = Some(0);
    let mut s = Scene::from_mesh(mesh);
    s.materials.push(Material {
        normal_texture: mapped.then_some(TextureRef {
            texture: 0,
            tex_coord: 0,
        }),
        ..Material::default()
    });
    s.textures.push(Texture {
        name: "normal".into(),
        source: ImageSource::Path("normal.png".into()),
        sampler: Default::default(),
    });
    s
}

/// A normal-map texel holding the tangent-space vector `n`.
fn encoded(n: DVec3) -> [f32; 4] {
    let e = (0.5 * (n.normalize() + DVec3::ONE)).as_vec3();
    [e.x, e.y, e.z, 1.0]
}

fn map_of(n: DVec3) -> [Option<Image>; 1] {
    [Some(Image::filled(4, 4, encoded(n)))]
}

fn options() -> CompareOptions {
    CompareOptions {
        samples: 1_000,
        texture_samples: 2_000,
        ..CompareOptions::default()
    }
}

#[test]
fn a_constant_tilted_map_on_a_flat_quad_gives_the_tilted_normal() {
    // Tangent space (0.3, −0.4, √0.75): with T = +x, B = +y, N = +z the
    // shading normal is the same vector in world space.
    let n = DVec3::new(0.3, -0.4, 0.75f64.sqrt());
    let images = map_of(n);
    let s = scene(gltf_quad(), true);
    let e = EvalMesh::from_scene(&s, &images);
    assert!(e.has_normal_map());
    for (t, bary) in [(0, [0.2, 0.3, 0.5]), (1, [1.0 / 3.0; 3])] {
        let got = e.shading_normal_at(t, bary);
        assert!((got - n).length() < 1e-6, "{got} vs {n}");
        assert_eq!(e.normal_at(t, bary), DVec3::Z);
    }
    // Against the same quad without a map: every sample is off by the
    // tilt, acos(√0.75) = 30°, in both directions; the vertex normals
    // agree, and the constant normals leave no sampling floor.
    let plain = scene(gltf_quad(), false);
    let c = compare(&e, &EvalMesh::from_scene(&plain, &images), &options());
    for v in [
        c.shading_normal_chamfer,
        c.shading_normal_chamfer_ref_to_cand,
        c.shading_normal_chamfer_cand_to_ref,
    ] {
        let v = v.expect("both have area");
        assert!((v - 30.0).abs() < 1e-4, "{c:?}");
    }
    assert_eq!(c.normal_chamfer, Some(0.0));
    assert!(c.shading_normal_chamfer_floor.expect("area") < 1e-4);
}

#[test]
fn a_flat_map_is_no_map() {
    // (0.5, 0.5, 1) decodes to (0, 0, 1): the vertex normal.
    let images = [Some(Image::filled(2, 2, [0.5, 0.5, 1.0, 1.0]))];
    let e = EvalMesh::from_scene(&scene(gltf_quad(), true), &images);
    assert_eq!(e.shading_normal_at(0, [0.1, 0.6, 0.3]), DVec3::Z);
    let plain = EvalMesh::from_scene(&scene(gltf_quad(), false), &images);
    assert!(!plain.has_normal_map());
    let c = compare(&e, &plain, &options());
    assert_eq!(c.shading_normal_chamfer, Some(0.0), "{c:?}");
}

#[test]
fn mirrored_uvs_flip_the_bitangent_as_mikktspace_says() {
    // quad_grid maps v = y: the image's top row lies at y = 0, so "up the
    // image" is −y and MikkTSpace's handedness is −1: a map's +y tilts the
    // normal toward −y, its x toward +x as before.
    let n = DVec3::new(0.3, 0.4, 0.75f64.sqrt());
    let images = map_of(n);
    let e = EvalMesh::from_scene(&scene(shapes::quad_grid(2, 2), true), &images);
    let got = e.shading_normal_at(3, [0.3, 0.3, 0.4]);
    let want = DVec3::new(0.3, -0.4, 0.75f64.sqrt());
    assert!((got - want).length() < 1e-6, "{got} vs {want}");
}

#[test]
fn meshes_without_normal_maps_have_equal_normal_and_shading_normal_chamfer() {
    let a = shapes::quad_sphere(6);
    let b = shapes::quad_sphere(3);
    let c = compare(
        &EvalMesh::from_mesh(&a),
        &EvalMesh::from_mesh(&b),
        &options(),
    );
    assert!(c.normal_chamfer.expect("area") > 1.0);
    assert_eq!(c.shading_normal_chamfer, c.normal_chamfer);
    assert_eq!(c.shading_normal_chamfer_floor, c.normal_chamfer_floor);
}
