//! Node transforms: world matrices of mesh instances, and meshes moved by
//! them (for writing a scene graph into formats that have none).

use crate::attribute::Semantic;
use crate::mesh::Mesh;
use crate::scene::{Scene, IDENTITY};

/// Product `a · b` of column-major 4×4 matrices.
pub fn mul(a: &[f32; 16], b: &[f32; 16]) -> [f32; 16] {
    let mut out = [0.0f32; 16];
    for c in 0..4 {
        for r in 0..4 {
            out[c * 4 + r] = (0..4).map(|k| a[k * 4 + r] * b[c * 4 + k]).sum();
        }
    }
    out
}

/// Applies a column-major affine matrix to a point.
pub fn apply_point(m: &[f32; 16], p: [f32; 3]) -> [f32; 3] {
    let mut out = [0.0; 3];
    for (r, o) in out.iter_mut().enumerate() {
        *o = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
    }
    out
}

impl Scene {
    /// Every (mesh, world matrix) pair the node tree instances, in
    /// depth-first order from the roots. Meshes no node reaches are listed
    /// once with the identity, so that no stored geometry is dropped.
    pub fn instances(&self) -> Vec<(u32, [f32; 16])> {
        let mut out = Vec::new();
        let mut reached = vec![false; self.meshes.len()];
        let mut stack: Vec<(u32, [f32; 16])> =
            self.roots.iter().rev().map(|&r| (r, IDENTITY)).collect();
        let mut budget = self.nodes.len().saturating_mul(self.nodes.len().max(1)) + 1;
        while let Some((n, parent)) = stack.pop() {
            if budget == 0 {
                break;
            }
            budget -= 1;
            let Some(node) = self.nodes.get(n as usize) else {
                continue;
            };
            let world = mul(&parent, &node.matrix);
            if let Some(m) = node.mesh.filter(|&m| (m as usize) < self.meshes.len()) {
                reached[m as usize] = true;
                out.push((m, world));
            }
            for &c in node.children.iter().rev() {
                stack.push((c, world));
            }
        }
        for (m, r) in reached.iter().enumerate() {
            if !r {
                out.push((m as u32, IDENTITY));
            }
        }
        out
    }
}

/// A copy of `mesh` moved by `m`: positions transformed, normals by the
/// inverse transpose (renormalized), tangent directions by the linear part;
/// face winding is reversed when `m` mirrors, so faces keep facing out.
pub fn transformed(mesh: &Mesh, m: &[f32; 16]) -> Mesh {
    let mut out = mesh.clone();
    if *m == IDENTITY {
        return out;
    }
    for p in &mut out.positions {
        *p = apply_point(m, *p);
    }
    let lin = |v: [f32; 3], a: &[[f32; 3]; 3]| {
        let mut r = [0.0f32; 3];
        for (i, ri) in r.iter_mut().enumerate() {
            *ri = a[0][i] * v[0] + a[1][i] * v[1] + a[2][i] * v[2];
        }
        r
    };
    // Columns of the linear part.
    let a = [[m[0], m[1], m[2]], [m[4], m[5], m[6]], [m[8], m[9], m[10]]];
    let det = a[0][0] * (a[1][1] * a[2][2] - a[2][1] * a[1][2])
        - a[1][0] * (a[0][1] * a[2][2] - a[2][1] * a[0][2])
        + a[2][0] * (a[0][1] * a[1][2] - a[1][1] * a[0][2]);
    // Inverse transpose up to scale: the cofactor matrix, whose columns
    // are cross products of the columns of `a`.
    let cross = |u: [f32; 3], v: [f32; 3]| {
        [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]
    };
    let cof = [cross(a[1], a[2]), cross(a[2], a[0]), cross(a[0], a[1])];
    let normalize = |v: [f32; 3]| {
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if l > 0.0 {
            v.map(|x| x / l)
        } else {
            v
        }
    };
    for attr in &mut out.attributes {
        match attr.semantic {
            Semantic::Normal if attr.components == 3 => {
                for v in attr.values.chunks_mut(3) {
                    let n = normalize(lin([v[0], v[1], v[2]], &cof));
                    v.copy_from_slice(&n);
                }
            }
            Semantic::Tangent if attr.components >= 3 => {
                let c = attr.components as usize;
                for v in attr.values.chunks_mut(c) {
                    let t = normalize(lin([v[0], v[1], v[2]], &a));
                    v[..3].copy_from_slice(&t);
                    if c == 4 && det < 0.0 {
                        v[3] = -v[3];
                    }
                }
            }
            _ => {}
        }
    }
    if det < 0.0 {
        reverse_winding(&mut out);
    }
    out
}

/// Reverses the corner order of every face, and of the per-corner streams
/// with it.
fn reverse_winding(mesh: &mut Mesh) {
    for f in 0..mesh.faces.len() {
        let r = mesh.faces.corner_range(f);
        mesh.faces.indices[r.clone()].reverse();
        for a in &mut mesh.attributes {
            a.indices[r.clone()].reverse();
        }
        if let Some(s) = &mut mesh.skinning {
            s.indices[r.clone()].reverse();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Node;

    fn translate(x: f32) -> [f32; 16] {
        let mut m = IDENTITY;
        m[12] = x;
        m
    }

    #[test]
    fn child_instance_composes_parent_transform() {
        let mut s = Scene::from_mesh(crate::shapes::cube());
        s.nodes[0].matrix = translate(1.0);
        s.nodes[0].mesh = None;
        s.nodes[0].children = vec![1];
        s.nodes.push(Node {
            matrix: translate(2.0),
            mesh: Some(0),
            ..Node::default()
        });
        let inst = s.instances();
        assert_eq!(inst.len(), 1);
        assert_eq!(apply_point(&inst[0].1, [0.0; 3]), [3.0, 0.0, 0.0]);
    }

    #[test]
    fn mirroring_reverses_winding_and_keeps_normals_unit() {
        let mut m = IDENTITY;
        m[0] = -2.0;
        let c = crate::shapes::cube();
        let t = transformed(&c, &m);
        assert_eq!(t.faces.face(0), &[1, 3, 2, 0]);
        assert_eq!(t.positions[1], [-2.0, 0.0, 0.0]);
    }
}
