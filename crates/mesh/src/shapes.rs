//! Small meshes generated in code, for tests, benchmarks and the demo.
//! The corpus is not part of the repository; these are.

use crate::attribute::{Attribute, ComponentFormat, Semantic};
use crate::faces::Faces;
use crate::mesh::Mesh;
// `triangulate` lives with the polygon splitting it is built on; it stays
// reachable here, where the tests and tools that build a shape and
// triangulate it have always found it.
pub use crate::polygon::triangulate;

/// An axis-aligned box from `lo` to `hi` as six outward-facing quads over
/// eight shared vertices: a closed manifold.
pub fn cuboid(lo: [f32; 3], hi: [f32; 3]) -> Mesh {
    let p = |x: usize, y: usize, z: usize| {
        [
            if x == 0 { lo[0] } else { hi[0] },
            if y == 0 { lo[1] } else { hi[1] },
            if z == 0 { lo[2] } else { hi[2] },
        ]
    };
    // Vertex i has coordinates (i & 1, (i >> 1) & 1, (i >> 2) & 1).
    let positions = (0..8)
        .map(|i| p(i & 1, (i >> 1) & 1, (i >> 2) & 1))
        .collect();
    let mut f = Faces::with_capacity(6, 24);
    f.push(&[0, 2, 3, 1]); // z = lo
    f.push(&[4, 5, 7, 6]); // z = hi
    f.push(&[0, 1, 5, 4]); // y = lo
    f.push(&[2, 6, 7, 3]); // y = hi
    f.push(&[0, 4, 6, 2]); // x = lo
    f.push(&[1, 3, 7, 5]); // x = hi
    Mesh::from_polygons(positions, f)
}

/// The unit cube `[0, 1]³` as six quads.
pub fn cube() -> Mesh {
    cuboid([0.0; 3], [1.0; 3])
}

/// A regular grid of `nx × ny` quads on `[0, 1]²` in the plane z = 0, facing
/// +z, with UVs equal to (x, y). An open manifold with a boundary.
pub fn quad_grid(nx: usize, ny: usize) -> Mesh {
    let (nx, ny) = (nx.max(1), ny.max(1));
    let mut positions = Vec::with_capacity((nx + 1) * (ny + 1));
    for j in 0..=ny {
        for i in 0..=nx {
            positions.push([i as f32 / nx as f32, j as f32 / ny as f32, 0.0]);
        }
    }
    let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let mut f = Faces::with_capacity(nx * ny, 4 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            f.push(&[id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mut m = Mesh::from_polygons(positions, f);
    let uv: Vec<f32> = m.positions.iter().flat_map(|p| [p[0], p[1]]).collect();
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

/// A torus around the z axis (major radius `big_r`, tube radius `r`) of
/// `nu × nv` quads: a closed genus-1 manifold.
pub fn torus(nu: usize, nv: usize, big_r: f32, r: f32) -> Mesh {
    let (nu, nv) = (nu.max(3), nv.max(3));
    let tau = std::f32::consts::TAU;
    let mut positions = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        let u = tau * i as f32 / nu as f32;
        for j in 0..nv {
            let v = tau * j as f32 / nv as f32;
            let w = big_r + r * v.cos();
            positions.push([w * u.cos(), w * u.sin(), r * v.sin()]);
        }
    }
    let id = |i: usize, j: usize| ((i % nu) * nv + (j % nv)) as u32;
    let mut f = Faces::with_capacity(nu * nv, 4 * nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            f.push(&[id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Mesh::from_polygons(positions, f)
}

/// A sphere of radius 1 made by projecting an `n × n` quad grid on each cube
/// face: `6 n²` quads, closed, nearly uniform.
pub fn quad_sphere(n: usize) -> Mesh {
    let n = n.max(1);
    let mut positions: Vec<[f32; 3]> = Vec::new();
    let mut index = std::collections::HashMap::new();
    let mut f = Faces::with_capacity(6 * n * n, 24 * n * n);
    // Integer lattice points on the cube surface [0, n]³ are shared between
    // faces by keying them on their coordinates.
    let mut vid = |q: [i64; 3]| -> u32 {
        *index.entry(q).or_insert_with(|| {
            let c = q.map(|x| 2.0 * x as f64 / n as f64 - 1.0);
            let l = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
            positions.push([(c[0] / l) as f32, (c[1] / l) as f32, (c[2] / l) as f32]);
            (positions.len() - 1) as u32
        })
    };
    let n64 = n as i64;
    for axis in 0..3 {
        for side in [0, n64] {
            let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
            for i in 0..n64 {
                for j in 0..n64 {
                    let corner = |di: i64, dj: i64| {
                        let mut q = [0i64; 3];
                        q[axis] = side;
                        q[a] = i + di;
                        q[b] = j + dj;
                        q
                    };
                    let mut quad = [
                        vid(corner(0, 0)),
                        vid(corner(1, 0)),
                        vid(corner(1, 1)),
                        vid(corner(0, 1)),
                    ];
                    // (a, b, axis) is right-handed: counter-clockwise seen
                    // from +axis, so flip on the low side to face outward.
                    if side == 0 {
                        quad.reverse();
                    }
                    f.push(&quad);
                }
            }
        }
    }
    Mesh::from_polygons(positions, f)
}

/// [`quad_sphere`] with smooth bumps (radius `1 + 0.15 sin 3x cos 2y +
/// 0.1 sin 4z` along each direction): the same curved shape at every `n`,
/// for measuring how a result changes with the tessellation alone.
pub fn bumpy_quad_sphere(n: usize) -> Mesh {
    let mut m = quad_sphere(n);
    for p in &mut m.positions {
        let r = 1.0 + 0.15 * (3.0 * p[0]).sin() * (2.0 * p[1]).cos() + 0.1 * (4.0 * p[2]).sin();
        *p = p.map(|c| c * r);
    }
    m
}

/// A box from `lo` to `hi` whose six sides are `n × n` quad grids: a closed
/// manifold with something to simplify.
pub fn box_grid(lo: [f32; 3], hi: [f32; 3], n: usize) -> Mesh {
    let mut m = quad_sphere(n);
    // Push the sphere back onto the cube it was projected from.
    for p in &mut m.positions {
        let s = p.iter().fold(0.0f32, |a, c| a.max(c.abs()));
        for k in 0..3 {
            let t = 0.5 * (p[k] / s + 1.0);
            p[k] = lo[k] + t * (hi[k] - lo[k]);
        }
    }
    m
}

/// Concatenates meshes into one (parts, attributes and skinning are not
/// merged: the result has one part and no attribute). For building wild
/// test inputs from several components.
pub fn merge(meshes: &[Mesh]) -> Mesh {
    let mut positions = Vec::new();
    let mut faces = Faces::new();
    for m in meshes {
        let base = positions.len() as u32;
        positions.extend_from_slice(&m.positions);
        for face in m.faces.iter() {
            let shifted: Vec<u32> = face.iter().map(|&v| v + base).collect();
            faces.push(&shifted);
        }
    }
    Mesh::from_polygons(positions, faces)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::topology;

    #[test]
    fn generated_shapes_are_valid_closed_manifolds() {
        for (m, comps) in [
            (cube(), 1),
            (torus(8, 6, 2.0, 0.5), 1),
            (quad_sphere(3), 1),
            (bumpy_quad_sphere(3), 1),
        ] {
            m.validate().unwrap();
            let s = topology(&m);
            assert_eq!(s.boundary_edges, 0);
            assert_eq!(s.nonmanifold_edges, 0);
            assert_eq!(s.components, comps);
        }
        // Euler characteristic: sphere 2, torus 0.
        let q = quad_sphere(3);
        assert_eq!(
            q.positions.len() as i64 - 2 * q.faces.len() as i64 + q.faces.len() as i64,
            2
        );
        let t = torus(8, 6, 2.0, 0.5);
        assert_eq!(
            t.positions.len() as i64 - 2 * t.faces.len() as i64 + t.faces.len() as i64,
            0
        );
    }

    #[test]
    fn cube_faces_point_outward() {
        let m = cube();
        for face in m.faces.iter() {
            let p: Vec<[f32; 3]> = face.iter().map(|&v| m.positions[v as usize]).collect();
            let (a, b) = (sub(p[1], p[0]), sub(p[2], p[0]));
            let n = [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ];
            let c = p
                .iter()
                .fold([0.0; 3], |s, q| [s[0] + q[0], s[1] + q[1], s[2] + q[2]]);
            let out = sub(c.map(|x| x / 4.0), [0.5; 3]);
            assert!(n[0] * out[0] + n[1] * out[1] + n[2] * out[2] > 0.0);
        }
        fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
            [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
        }
    }
}
