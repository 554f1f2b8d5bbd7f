//! [`EvalMesh`]: a scene flattened to world-space triangles for measuring,
//! with what the texture metric needs (UVs, base color images) and the face
//! counts the quad ratio needs.

use glam::DVec3;
use serde::Serialize;
use wildlod_geometry::Aabb;
use wildlod_mesh::bounds::{robust_bounds, OutlierRule, RobustBounds};
use wildlod_mesh::disjoint_sets::DisjointSets;
use wildlod_mesh::shapes::triangulate;
use wildlod_mesh::tangents::generate_tangents;
use wildlod_mesh::transform::transformed;
use wildlod_mesh::weld::weld_positions;
use wildlod_mesh::{AlphaMode, Attribute, ComponentFormat, Image, Mesh, Scene, Semantic};

/// Face counts as the file has them (before triangulation).
///
/// Serialized with these keys; `triangulated` is the triangle count of the
/// fan-triangulated faces (a quad counts 2, an n-gon n − 2), the count that
/// simplification targets and the quad ratio refer to.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct FaceCounts {
    /// Faces of any arity.
    pub faces: usize,
    /// Faces with three corners.
    pub triangles: usize,
    /// Faces with four corners.
    pub quads: usize,
    /// Faces with five or more corners.
    pub ngons: usize,
    /// Triangles after fan triangulation.
    pub triangulated: usize,
    /// Connected components, after welding equal positions (faces sharing
    /// a position are connected).
    pub components: usize,
    /// Mesh instances these counts add up (1 for a single mesh).
    pub instances: usize,
}

impl FaceCounts {
    fn add(&mut self, o: &FaceCounts) {
        self.faces += o.faces;
        self.triangles += o.triangles;
        self.quads += o.quads;
        self.ngons += o.ngons;
        self.triangulated += o.triangulated;
        self.components += o.components;
        self.instances += o.instances;
    }
}

/// The counts of one mesh instance of a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct InstanceCounts {
    /// Index of the instanced mesh in [`Scene::meshes`].
    pub mesh: u32,
    /// Its face counts (`instances` is 1).
    pub counts: FaceCounts,
}

/// Where the color of a triangle comes from: an optional base color image
/// times the material's base color factor.
#[derive(Clone, Copy)]
struct ColorSource<'a> {
    image: Option<&'a Image>,
    factor: [f32; 4],
    /// The alpha cutoff of an alpha-tested (`MASK`) material.
    cutoff: Option<f32>,
}

impl std::fmt::Debug for ColorSource<'_> {
    // The image by its size: printing megapixels helps nobody.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ColorSource")
            .field("image", &self.image.map(|i| (i.width, i.height)))
            .field("factor", &self.factor)
            .field("cutoff", &self.cutoff)
            .finish()
    }
}

/// Color source of triangles without a material: glTF's default material,
/// white.
const DEFAULT_SOURCE: u32 = 0;

/// Normal map index of a triangle without one.
const NO_NORMAL_MAP: u32 = u32::MAX;

/// What a material reads from the scene: its color source, the UV set of
/// its base color texture, and its normal map (index into
/// `EvalMesh::normal_maps`) with the UV set that map uses.
#[derive(Clone, Copy, Debug)]
struct MaterialSource {
    color: u32,
    color_uv: Option<u32>,
    normal_map: Option<(u32, u32)>,
}

/// The normal-map data of every triangle corner, kept only once some
/// triangle has a normal map (empty otherwise).
#[derive(Clone, Debug, Default)]
struct Shading {
    /// True once some triangle has a normal map: the vectors below then
    /// have an entry for every triangle.
    active: bool,
    /// Normal map of every triangle ([`NO_NORMAL_MAP`] for none).
    maps: Vec<u32>,
    /// UV of every triangle corner in its normal map's set.
    uvs: Vec<[f32; 2]>,
    /// Tangent (xyz, handedness w) of every triangle corner.
    tangents: Vec<[f32; 4]>,
}

/// A world-space triangle set for measuring.
///
/// Every instance of the scene is moved by its world matrix and
/// triangulated (`shapes::triangulate`). Triangles that refer to a missing
/// position or have a non-finite corner are left out (they have no surface
/// to measure); face counts still count them, as the file has them. Skinned meshes are
/// measured as stored (bind pose).
///
/// For the texture metric every triangle corner keeps the UV of the set its
/// material's base color texture uses, and every triangle the image (times
/// the base color factor) to look colors up in. Images are borrowed from
/// the caller, who decodes them.
#[derive(Clone, Debug, Default)]
pub struct EvalMesh<'a> {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    /// UV of every triangle corner (three per triangle); `[0, 0]` where the
    /// corner has none.
    uvs: Vec<[f32; 2]>,
    /// Shading normal of every triangle corner (three per triangle): the
    /// mesh's normal, or the triangle's own where the corner has none.
    normals: Vec<[f32; 3]>,
    /// Color source of every triangle.
    sources: Vec<u32>,
    colors: Vec<ColorSource<'a>>,
    /// Decoded normal maps the materials use.
    normal_maps: Vec<&'a Image>,
    shading: Shading,
    /// Welded vertices used by triangles, one position index each: the
    /// vertex sample points.
    vertices: Vec<u32>,
    counts: FaceCounts,
    instances: Vec<InstanceCounts>,
    /// First position index of every instance: positions of instance `i`
    /// are `instance_first[i]..instance_first[i + 1]`.
    instance_first: Vec<u32>,
}

/// What is computed once per stored mesh, however often it is instanced.
struct MeshInfo {
    counts: FaceCounts,
    /// One position index per welded vertex used by a face.
    vertices: Vec<u32>,
}

fn analyze(mesh: &Mesh) -> MeshInfo {
    let (t, q, n) = mesh.faces.arity_counts();
    let (weld, _) = weld_positions(&mesh.positions);
    let np = mesh.positions.len();
    let mut sets = DisjointSets::new(np);
    let mut used = vec![false; np];
    for face in mesh.faces.iter() {
        let ids: Vec<u32> = face
            .iter()
            .filter(|&&v| (v as usize) < np)
            .map(|&v| weld[v as usize])
            .collect();
        for (k, &a) in ids.iter().enumerate() {
            used[a as usize] = true;
            sets.union(a, ids[(k + 1) % ids.len()]);
        }
    }
    // `weld` maps a position to the first position with its value, so a
    // used welded id is itself a position index.
    let vertices: Vec<u32> = (0..np as u32).filter(|&v| used[v as usize]).collect();
    let mut roots: Vec<u32> = vertices.iter().map(|&v| sets.find(v)).collect();
    roots.sort_unstable();
    roots.dedup();
    MeshInfo {
        counts: FaceCounts {
            faces: mesh.faces.len(),
            triangles: t,
            quads: q,
            ngons: n,
            triangulated: mesh.faces.triangulated_count(),
            components: roots.len(),
            instances: 1,
        },
        vertices,
    }
}

impl<'a> EvalMesh<'a> {
    /// Flattens every mesh instance of `scene` (see [`Scene::instances`]).
    /// `images` holds the decoded image of every texture, indexed like
    /// `scene.textures`; `None` (or a missing entry) for a texture the
    /// caller could not decode, whose triangles then count as untextured.
    pub fn from_scene(scene: &Scene, images: &'a [Option<Image>]) -> EvalMesh<'a> {
        let mut out = EvalMesh {
            colors: vec![ColorSource {
                image: None,
                factor: [1.0; 4],
                cutoff: None,
            }],
            ..EvalMesh::default()
        };
        // Color source, normal map and their UV sets for every material.
        let mut material_source = Vec::with_capacity(scene.materials.len());
        for m in &scene.materials {
            let tex = m.base_color_texture;
            let image = tex.and_then(|t| images.get(t.texture as usize)?.as_ref());
            out.colors.push(ColorSource {
                image,
                factor: m.base_color,
                cutoff: (m.alpha_mode == AlphaMode::Mask).then_some(m.alpha_cutoff),
            });
            let normal_map = m.normal_texture.and_then(|t| {
                let image = images.get(t.texture as usize)?.as_ref()?;
                out.normal_maps.push(image);
                Some((out.normal_maps.len() as u32 - 1, t.tex_coord))
            });
            material_source.push(MaterialSource {
                color: out.colors.len() as u32 - 1,
                color_uv: image.and(tex).map(|t| t.tex_coord),
                normal_map,
            });
        }
        let mut infos: Vec<Option<MeshInfo>> = Vec::new();
        infos.resize_with(scene.meshes.len(), || None);
        for (mi, matrix) in scene.instances() {
            let mesh = &scene.meshes[mi as usize];
            let info = infos[mi as usize].get_or_insert_with(|| analyze(mesh));
            out.counts.add(&info.counts);
            out.instances.push(InstanceCounts {
                mesh: mi,
                counts: info.counts,
            });
            let moved = triangulate(&transformed(mesh, &matrix));
            // Positions placed in f64: a georeferenced file's meshes sit
            // millions of units from the origin, where f32 steps by a
            // quarter of a unit and would swamp the distances measured.
            let m = glam::DMat4::from_cols_array(&matrix.map(f64::from));
            let world: Vec<DVec3> = mesh
                .positions
                .iter()
                .map(|p| m.transform_point3(DVec3::from(p.map(f64::from))))
                .collect();
            out.instance_first.push(out.positions.len() as u32);
            out.push_triangulated(&moved, &world, &info.vertices, &material_source);
        }
        out
    }

    /// A single mesh with identity transform, no material and no texture.
    pub fn from_mesh(mesh: &Mesh) -> EvalMesh<'static> {
        let mut out = EvalMesh {
            colors: vec![ColorSource {
                image: None,
                factor: [1.0; 4],
                cutoff: None,
            }],
            ..EvalMesh::default()
        };
        let info = analyze(mesh);
        out.counts = info.counts;
        out.instances.push(InstanceCounts {
            mesh: 0,
            counts: info.counts,
        });
        out.instance_first.push(0);
        let positions: Vec<DVec3> = mesh
            .positions
            .iter()
            .map(|p| DVec3::from(p.map(f64::from)))
            .collect();
        out.push_triangulated(&triangulate(mesh), &positions, &info.vertices, &[]);
        out
    }

    /// Appends a triangulated, world-space mesh whose positions are
    /// `positions` (in f64: `tri`'s own are rounded to f32). `vertices` are
    /// its vertex sample positions; `material_source` says what each
    /// material reads.
    fn push_triangulated(
        &mut self,
        tri: &Mesh,
        positions: &[DVec3],
        vertices: &[u32],
        material_source: &[MaterialSource],
    ) {
        let base = self.positions.len() as u32;
        let np = tri.positions.len();
        debug_assert_eq!(positions.len(), np);
        self.positions.extend_from_slice(positions);
        let finite = |v: u32| (v as usize) < np && self.positions[(base + v) as usize].is_finite();
        self.vertices
            .extend(vertices.iter().filter(|&&v| finite(v)).map(|&v| base + v));
        let source_of = |part: usize| {
            tri.parts
                .get(part)
                .and_then(|p| material_source.get(p.material? as usize))
        };
        // The UV stream of every part, when its material is textured.
        let part_source: Vec<(u32, Option<&Attribute>)> = (0..tri.parts.len())
            .map(|part| match source_of(part) {
                Some(m) => (
                    m.color,
                    m.color_uv
                        .and_then(|s| tri.attribute(&Semantic::TexCoord(s))),
                ),
                None => (DEFAULT_SOURCE, None),
            })
            .collect();
        let normals = tri
            .attribute(&Semantic::Normal)
            .filter(|a| a.components == 3);
        // Per-corner shading normals: the mesh's, or the face's own (what
        // glTF renderers use without normals).
        let mut corner_normals: Vec<[f32; 3]> = vec![[0.0, 0.0, 1.0]; tri.faces.corner_count()];
        for f in 0..tri.faces.len() {
            let face = tri.faces.face(f);
            if face.len() != 3 || !face.iter().all(|&v| finite(v)) {
                continue;
            }
            let [a, b, c] = [0, 1, 2].map(|k| self.positions[(base + face[k]) as usize]);
            let own = (b - a).cross(c - a).normalize_or_zero();
            for c in tri.faces.corner_range(f) {
                corner_normals[c] = normals
                    .and_then(|a| {
                        let i = *a.indices.get(c)?;
                        let v = (i as usize) < a.value_count();
                        v.then(|| a.value(i))
                    })
                    .filter(|v| v.iter().all(|x| x.is_finite()))
                    .map(|v| [v[0], v[1], v[2]])
                    .unwrap_or([own.x as f32, own.y as f32, own.z as f32]);
            }
        }
        let normal_maps = NormalMapCorners::new(tri, &corner_normals, |part| {
            source_of(part).and_then(|m| m.normal_map)
        });
        if normal_maps.is_some() && !self.shading.active {
            // The first normal map: the triangles before it have none.
            self.shading.active = true;
            let t = self.sources.len();
            self.shading.maps.resize(t, NO_NORMAL_MAP);
            self.shading.uvs.resize(3 * t, [0.0; 2]);
            self.shading.tangents.resize(3 * t, [0.0; 4]);
        }
        let mut tris = Vec::with_capacity(tri.faces.len());
        for f in 0..tri.faces.len() {
            let face = tri.faces.face(f);
            if face.len() != 3 || !face.iter().all(|&v| finite(v)) {
                continue;
            }
            let part = tri.face_parts.get(f).copied().unwrap_or(0) as usize;
            let (source, uv) = part_source
                .get(part)
                .copied()
                .unwrap_or((DEFAULT_SOURCE, None));
            for c in tri.faces.corner_range(f) {
                self.normals.push(corner_normals[c]);
                let value = uv.and_then(|a| {
                    let i = *a.indices.get(c)?;
                    if a.components < 2 || i as usize >= a.value_count() {
                        return None;
                    }
                    let v = a.value(i);
                    Some([v[0], v[1]])
                });
                self.uvs.push(value.unwrap_or([0.0; 2]));
            }
            if self.shading.active {
                let map = normal_maps.as_ref().and_then(|n| n.triangle(tri, f));
                match map {
                    Some((index, corners)) => {
                        self.shading.maps.push(index);
                        for (uv, tangent) in corners {
                            self.shading.uvs.push(uv);
                            self.shading.tangents.push(tangent);
                        }
                    }
                    None => {
                        self.shading.maps.push(NO_NORMAL_MAP);
                        self.shading.uvs.extend([[0.0; 2]; 3]);
                        self.shading.tangents.extend([[0.0; 4]; 3]);
                    }
                }
            }
            tris.push([face[0] + base, face[1] + base, face[2] + base]);
            self.sources.push(source);
        }
        self.triangles.extend(tris);
    }

    /// World-space positions (all positions of all instances, including any
    /// that no kept triangle uses).
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// Triangles kept for measuring, indexing [`EvalMesh::positions`].
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Position indices of the vertex sample points: one per welded vertex
    /// of every instance.
    pub fn vertex_samples(&self) -> &[u32] {
        &self.vertices
    }

    /// Where position `p` comes from: (instance index, stored mesh index,
    /// vertex index in that mesh), or `None` past the positions.
    pub fn locate(&self, p: u32) -> Option<(usize, u32, u32)> {
        if p as usize >= self.positions.len() {
            return None;
        }
        let i = self
            .instance_first
            .partition_point(|&f| f <= p)
            .checked_sub(1)?;
        let mesh = self.instances.get(i)?.mesh;
        Some((i, mesh, p - self.instance_first[i]))
    }

    /// The robust bounds ([`wildlod_mesh::bounds`]) of the vertex samples;
    /// outliers are indices into [`EvalMesh::vertex_samples`].
    pub fn robust_bounds(&self, rule: &OutlierRule) -> RobustBounds {
        robust_bounds(
            self.vertices
                .iter()
                .map(|&v| self.positions[v as usize].to_array()),
            rule,
        )
    }

    /// Face counts of all instances together.
    pub fn counts(&self) -> FaceCounts {
        self.counts
    }

    /// Face counts of every instance, in [`Scene::instances`] order.
    pub fn instances(&self) -> &[InstanceCounts] {
        &self.instances
    }

    /// Bounds of the kept triangles.
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(
            self.triangles
                .iter()
                .flatten()
                .map(|&v| self.positions[v as usize]),
        )
    }

    /// Corners of triangle `t`.
    #[inline]
    pub fn triangle(&self, t: usize) -> [DVec3; 3] {
        self.triangles[t].map(|v| self.positions[v as usize])
    }

    /// Area of triangle `t`.
    #[inline]
    pub fn triangle_area(&self, t: usize) -> f64 {
        let [a, b, c] = self.triangle(t);
        0.5 * (b - a).cross(c - a).length()
    }

    /// Total surface area.
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| self.triangle_area(t))
            .sum()
    }

    /// True when some triangle takes its color from a base color image.
    pub fn has_texture(&self) -> bool {
        self.sources
            .iter()
            .any(|&s| self.colors[s as usize].image.is_some())
    }

    /// Whether some triangle's material is alpha-tested (`MASK`).
    pub fn alpha_tested(&self) -> bool {
        self.sources
            .iter()
            .any(|&s| self.colors[s as usize].cutoff.is_some())
    }

    /// Whether an alpha test draws the point at barycentrics `bary` of
    /// triangle `t`: its alpha (the base color image's, bilinear at the
    /// interpolated UV, times the factor's) at least its material's cutoff.
    /// `None` where the material is not alpha-tested.
    pub fn passes_alpha_test(&self, t: usize, bary: [f64; 3]) -> Option<bool> {
        let src = &self.colors[self.sources[t] as usize];
        let cutoff = src.cutoff?;
        let texel = match src.image {
            Some(img) => img.sample_bilinear(self.uv_at(t, bary))[3],
            None => 1.0,
        };
        Some(texel * src.factor[3] >= cutoff)
    }

    /// The interpolated UV (base color set) at barycentrics `bary` of
    /// triangle `t`.
    fn uv_at(&self, t: usize, bary: [f64; 3]) -> [f32; 2] {
        let uv = &self.uvs[3 * t..3 * t + 3];
        let mut at = [0.0f64; 2];
        for (corner, &w) in uv.iter().zip(&bary) {
            at[0] += w * f64::from(corner[0]);
            at[1] += w * f64::from(corner[1]);
        }
        [at[0] as f32, at[1] as f32]
    }

    /// Color (RGB in [0, 1], sRGB-encoded as images store it) at
    /// barycentrics `bary` of triangle `t`: the base color image looked up
    /// bilinearly at the interpolated UV, times the base color factor.
    /// glTF's factor is linear and its image sRGB, so the product is taken
    /// in linear space and encoded back: what a renderer displays, and the
    /// same number whether a re-baker folded the factor into its image or
    /// not. A factor of 1 leaves the image's values untouched; triangles
    /// without an image have the factor's color (sRGB-encoded).
    pub fn color_at(&self, t: usize, bary: [f64; 3]) -> [f32; 3] {
        let src = &self.colors[self.sources[t] as usize];
        let texel = match src.image {
            Some(img) => img.sample_bilinear(self.uv_at(t, bary)),
            None => [1.0; 4],
        };
        std::array::from_fn(|k| {
            let (t, f) = (texel[k].clamp(0.0, 1.0), src.factor[k]);
            if f == 1.0 {
                t
            } else {
                linear_to_srgb(srgb_to_linear(t) * f.clamp(0.0, 1.0))
            }
        })
    }
}

/// sRGB-encoded value → linear (IEC 61966-2-1).
pub(crate) fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear value in [0, 1] → sRGB-encoded.
pub(crate) fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

impl EvalMesh<'_> {
    /// Vertex normal (unit) at barycentrics `bary` of triangle `t`: the
    /// corners' normals interpolated and normalized (zero where they cancel).
    pub fn normal_at(&self, t: usize, bary: [f64; 3]) -> DVec3 {
        let n = &self.normals[3 * t..3 * t + 3];
        let mut sum = DVec3::ZERO;
        for (corner, &w) in n.iter().zip(&bary) {
            sum += w * DVec3::from(corner.map(f64::from));
        }
        sum.normalize_or_zero()
    }

    /// True when some triangle has a (decoded) normal map.
    pub fn has_normal_map(&self) -> bool {
        self.shading.maps.iter().any(|&m| m != NO_NORMAL_MAP)
    }

    /// Shading normal (unit) at barycentrics `bary` of triangle `t`, as a
    /// glTF renderer lights it: the vertex normal ([`EvalMesh::normal_at`])
    /// where the triangle has no normal map; otherwise the normal map's
    /// texel (bilinear, decoded as `2 · texel − 1`) taken from the tangent
    /// frame built from interpolated data, as glTF's reference shader does:
    /// `N` the interpolated normal, `T` the interpolated tangent made
    /// orthogonal to `N`, `B = (N × T) · w` with `w` the tangent's
    /// handedness, and the normal `T x + B y + N z`. Tangents are the
    /// file's, else MikkTSpace's ([`wildlod_mesh::tangents`]) from the map's
    /// UV set. The material's normal scale is not in the mesh model and
    /// counts as 1. Where the frame is degenerate the vertex normal stays.
    pub fn shading_normal_at(&self, t: usize, bary: [f64; 3]) -> DVec3 {
        let n = self.normal_at(t, bary);
        let Some(&map) = self.shading.maps.get(t) else {
            return n;
        };
        let Some(image) = self.normal_maps.get(map as usize) else {
            return n;
        };
        let corners = 3 * t..3 * t + 3;
        let (mut uv, mut tangent, mut w) = ([0.0f64; 2], DVec3::ZERO, 0.0);
        for ((c_uv, c_t), &b) in self.shading.uvs[corners.clone()]
            .iter()
            .zip(&self.shading.tangents[corners])
            .zip(&bary)
        {
            uv[0] += b * f64::from(c_uv[0]);
            uv[1] += b * f64::from(c_uv[1]);
            tangent += b * DVec3::new(c_t[0].into(), c_t[1].into(), c_t[2].into());
            w += b * f64::from(c_t[3]);
        }
        let Some(tangent) = (tangent - n * n.dot(tangent)).try_normalize() else {
            return n;
        };
        let bitangent = n.cross(tangent) * if w < 0.0 { -1.0 } else { 1.0 };
        let texel = image.sample_bilinear([uv[0] as f32, uv[1] as f32]);
        let [x, y, z] = [0, 1, 2].map(|k| 2.0 * f64::from(texel[k]) - 1.0);
        (tangent * x + bitangent * y + n * z)
            .try_normalize()
            .unwrap_or(n)
    }
}

/// One UV set a normal map reads: its number, its stream, and the tangent
/// of every corner in it.
struct TangentSet<'m> {
    set: u32,
    uvs: &'m Attribute,
    tangents: Vec<Option<[f32; 4]>>,
}

/// The normal-map UV and tangent of one triangle corner.
type MapCorner = ([f32; 2], [f32; 4]);

/// The normal-map UV and tangent of every corner of a triangulated mesh's
/// faces that have a normal map.
struct NormalMapCorners<'m> {
    /// Normal map and UV set of every part (`None`: no map).
    part_maps: Vec<Option<(u32, u32)>>,
    /// Every UV set a part's normal map reads.
    sets: Vec<TangentSet<'m>>,
}

impl<'m> NormalMapCorners<'m> {
    /// `None` when no part of `tri` has a normal map with its UV set.
    /// `corner_normals` are the shading normals MikkTSpace builds the
    /// frames from when the mesh stores no tangents.
    fn new(
        tri: &'m Mesh,
        corner_normals: &[[f32; 3]],
        part_map: impl Fn(usize) -> Option<(u32, u32)>,
    ) -> Option<Self> {
        let part_maps: Vec<Option<(u32, u32)>> = (0..tri.parts.len())
            .map(|p| {
                part_map(p).filter(|&(_, set)| tri.attribute(&Semantic::TexCoord(set)).is_some())
            })
            .collect();
        let mut used: Vec<u32> = part_maps.iter().flatten().map(|&(_, set)| set).collect();
        used.sort_unstable();
        used.dedup();
        if used.is_empty() {
            return None;
        }
        let stored = tri
            .attribute(&Semantic::Tangent)
            .filter(|a| a.components == 4);
        // MikkTSpace on the normals we shade with (flat ones where the file
        // has none, as glTF prescribes), not on the file's stream alone.
        let mut with_normals: Option<Mesh> = None;
        let sets = used
            .into_iter()
            .filter_map(|set| {
                let uvs = tri.attribute(&Semantic::TexCoord(set))?;
                let generated = match stored {
                    Some(_) => None,
                    None => {
                        let m = with_normals.get_or_insert_with(|| {
                            let mut m = tri.clone();
                            m.attributes.retain(|a| a.semantic != Semantic::Normal);
                            m.attributes.push(Attribute {
                                semantic: Semantic::Normal,
                                components: 3,
                                values: corner_normals.iter().flatten().copied().collect(),
                                indices: (0..corner_normals.len() as u32).collect(),
                                format: ComponentFormat::F32,
                            });
                            m
                        });
                        generate_tangents(m, set).ok()
                    }
                };
                let tangents = (0..tri.faces.corner_count())
                    .map(|c| {
                        let a = stored.or(generated.as_ref())?;
                        let v = a.corner_value(c)?;
                        Some([v[0], v[1], v[2], v[3]])
                    })
                    .collect();
                Some(TangentSet { set, uvs, tangents })
            })
            .collect();
        Some(NormalMapCorners { part_maps, sets })
    }

    /// The normal map of face `f` of `tri` and the (UV, tangent) of its
    /// three corners, or `None` when it has no map or a corner misses its
    /// UV or tangent.
    fn triangle(&self, tri: &Mesh, f: usize) -> Option<(u32, [MapCorner; 3])> {
        let part = tri.face_parts.get(f).copied().unwrap_or(0) as usize;
        let (map, set) = (*self.part_maps.get(part)?)?;
        let ts = self.sets.iter().find(|s| s.set == set)?;
        let r = tri.faces.corner_range(f);
        let mut out = [([0.0; 2], [0.0; 4]); 3];
        for (slot, c) in out.iter_mut().zip(r) {
            let uv = ts.uvs.corner_value(c).filter(|v| v.len() >= 2)?;
            *slot = ([uv[0], uv[1]], (*ts.tangents.get(c)?)?);
        }
        Some((map, out))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wildlod_mesh::{
        shapes, Attribute, ComponentFormat, ImageSource, Material, Node, Texture, TextureRef,
        IDENTITY,
    };

    fn translate(x: f32) -> [f32; 16] {
        let mut m = IDENTITY;
        m[12] = x;
        m
    }

    #[test]
    fn instances_are_moved_to_world_space_and_counted_each() {
        let mut s = Scene::from_mesh(shapes::cube());
        s.nodes[0].mesh = None;
        s.nodes[0].children = vec![1, 2];
        for x in [0.0, 3.0] {
            s.nodes.push(Node {
                matrix: translate(x),
                mesh: Some(0),
                ..Node::default()
            });
        }
        let e = EvalMesh::from_scene(&s, &[]);
        let c = e.counts();
        assert_eq!((c.faces, c.quads, c.triangulated), (12, 12, 24));
        assert_eq!((c.components, c.instances), (2, 2));
        assert_eq!(e.instances().len(), 2);
        assert_eq!(e.instances()[1].counts.faces, 6);
        assert_eq!(e.triangles().len(), 24);
        assert_eq!(e.vertex_samples().len(), 16);
        let b = e.bounds();
        assert_eq!((b.min, b.max), (DVec3::ZERO, DVec3::new(4.0, 1.0, 1.0)));
        assert!((e.area() - 12.0).abs() < 1e-12);
    }

    #[test]
    fn colors_use_the_uv_set_of_the_base_color_texture_and_its_factor() {
        // One triangle; UV set 0 puts every corner at u = 0.25 (black
        // texel), set 1 at u = 0.75 (white texel). The material reads set 1.
        let mut m = Mesh::from_triangles(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            &[0, 1, 2],
        );
        m.parts[0].material = Some(0);
        for (set, u) in [(0, 0.25f32), (1, 0.75)] {
            m.attributes.push(Attribute {
                semantic: Semantic::TexCoord(set),
                components: 2,
                values: vec![u, 0.5],
                indices: vec![0, 0, 0],
                format: ComponentFormat::F32,
            });
        }
        let mut s = Scene::from_mesh(m);
        s.materials.push(Material {
            base_color: [0.5, 0.25, 1.0, 1.0],
            base_color_texture: Some(TextureRef {
                texture: 0,
                tex_coord: 1,
            }),
            ..Material::default()
        });
        s.textures.push(Texture {
            name: String::new(),
            source: ImageSource::Path("t.png".into()),
            sampler: Default::default(),
        });
        let mut img = Image::filled(2, 1, [0.0, 0.0, 0.0, 1.0]);
        img.pixels[1] = [1.0; 4];
        let images = [Some(img)];
        let e = EvalMesh::from_scene(&s, &images);
        assert!(e.has_texture());
        // White times the linear factor, displayed in sRGB: linear 0.5 is
        // sRGB 0.7354, 0.25 is 0.5371.
        let c = e.color_at(0, [1.0 / 3.0; 3]);
        let want = [0.735_357, 0.537_098, 1.0];
        assert!((0..3).all(|k| (c[k] - want[k]).abs() < 1e-5), "{c:?}");
        // Without the decoded image the factor alone colors the triangle.
        let none: [Option<Image>; 1] = [None];
        let e = EvalMesh::from_scene(&s, &none);
        assert!(!e.has_texture());
        let c = e.color_at(0, [1.0, 0.0, 0.0]);
        assert!((0..3).all(|k| (c[k] - want[k]).abs() < 1e-5), "{c:?}");
        // A texture index past the images is treated the same way.
        let e = EvalMesh::from_scene(&s, &[]);
        assert!(!e.has_texture());
    }

    #[test]
    fn triangles_without_surface_are_dropped_but_faces_still_counted() {
        let mut m = Mesh::from_triangles(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [f32::NAN, 0.0, 0.0],
            ],
            &[0, 1, 2, 0, 1, 3, 0, 1, 9],
        );
        m.parts[0].material = Some(7); // no such material: default white
        let e = EvalMesh::from_mesh(&m);
        assert_eq!(e.counts().faces, 3);
        assert_eq!(e.triangles(), &[[0, 1, 2]]);
        assert_eq!(e.vertex_samples(), &[0, 1, 2]);
        assert_eq!(e.color_at(0, [1.0, 0.0, 0.0]), [1.0; 3]);
        let s = Scene::from_mesh(m);
        assert_eq!(EvalMesh::from_scene(&s, &[]).triangles().len(), 1);
    }

    #[test]
    fn seam_duplicates_are_one_vertex_sample_and_one_component() {
        // quad_grid's positions are unique; a copy of vertex 0 used by the
        // second quad must weld back to it.
        let mut m = shapes::quad_grid(2, 1);
        m.positions.push(m.positions[1]);
        let last = m.positions.len() as u32 - 1;
        let f1 = m.faces.corner_range(1);
        m.faces.indices[f1.start] = last;
        let e = EvalMesh::from_mesh(&m);
        assert_eq!(e.vertex_samples().len(), 6);
        assert_eq!(e.counts().components, 1);
    }
}
