//! Shared pieces of the benchmarks: loading corpus meshes as flat triangle
//! arrays, and running meshoptimizer on them the way its users do.

use wildlod_mesh::{shapes, Mesh};

/// Positions and triangle indices of every mesh of a file, flattened with
/// node transforms and fan-triangulated.
pub fn load_triangles(
    path: &std::path::Path,
) -> Result<(Vec<[f32; 3]>, Vec<u32>), wildlod_io::Error> {
    let doc = wildlod_io::read(path)?;
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for (m, world) in doc.scene.instances() {
        let mesh: Mesh = shapes::triangulate(&wildlod_mesh::transform::transformed(
            &doc.scene.meshes[m as usize],
            &world,
        ));
        let base = positions.len() as u32;
        positions.extend_from_slice(&mesh.positions);
        indices.extend(mesh.faces.indices.iter().map(|&v| v + base));
    }
    Ok((positions, indices))
}

/// meshoptimizer's `simplify` to `target` triangles with no error limit,
/// as the wildlod comparison uses it: returns the index buffer.
pub fn meshopt_simplify(
    positions: &[[f32; 3]],
    indices: &[u32],
    target: usize,
    lock_border: bool,
) -> Vec<u32> {
    let bytes: &[u8] = meshopt::typed_to_bytes(positions);
    let adapter = match meshopt::VertexDataAdapter::new(bytes, 12, 0) {
        Ok(a) => a,
        Err(_) => return indices.to_vec(),
    };
    let options = if lock_border {
        meshopt::SimplifyOptions::LockBorder
    } else {
        meshopt::SimplifyOptions::None
    };
    meshopt::simplify(indices, &adapter, target * 3, f32::MAX, options, None)
}
