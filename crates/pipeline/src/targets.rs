//! The target of every mesh of a file, from the file-wide limits.

use wildlod_mesh::{Mesh, Scene};
use wildlod_simplify::Target;

/// The target of every stored mesh: the same ratio for all; a triangle
/// budget (`faces`) of drawn triangles shared in proportion to the
/// triangles each mesh draws (its own times the nodes that show it; largest
/// remainders, so the shares sum to the budget), each a count of drawn
/// triangles too (see `InputData::face_instances`); an `error` limit
/// relative to the file's diagonal converted to each mesh's own.
///
/// Every mesh keeps at least one triangle, whatever the targets: a mesh
/// simplified to nothing would leave its nodes, skins and instances
/// pointing at an empty mesh, and a ratio of 0 would write a file with no
/// geometry and succeed. "As small as possible" is what a user asking for
/// 0 wants; one triangle per mesh is the smallest valid result.
pub fn targets_for(
    scene: &Scene,
    ratio: Option<f64>,
    faces: Option<usize>,
    error: Option<f64>,
) -> Vec<Target> {
    let tris: Vec<usize> = scene.meshes.iter().map(|m| m.triangle_count()).collect();
    let instances = scene.instance_counts();
    let drawn: Vec<usize> = tris.iter().zip(&instances).map(|(t, k)| t * k).collect();
    let shares = faces.map(|n| share_budget(n, &drawn));
    let file_diag = scene_diagonal(scene);
    tris.iter()
        .enumerate()
        .map(|(m, _)| Target {
            ratio,
            triangles: Some(
                shares
                    .as_ref()
                    .map_or(MIN_TRIANGLES, |s| s[m].max(MIN_TRIANGLES)),
            ),
            error: error.map(|e| {
                let d = world_diagonal(scene, m);
                if d > 0.0 && file_diag > 0.0 {
                    e * file_diag / d
                } else {
                    e
                }
            }),
        })
        .collect()
}

/// Every stored mesh's target as the drawn triangles it has in `meshes`,
/// the same file's meshes simplified under one budget (`instances`: the
/// nodes showing each): how a re-bake reaches, mesh by mesh, what a run
/// over the whole file spent where (W's budget is one for the scene, §1).
/// A mesh the file's run removed gets 0 triangles: it goes in the re-bake
/// too (see `rebake_scene`).
///
/// `file_target`, the triangles that run aimed for: a run reaches its
/// target within a triangle (two where a collapse takes a face and its
/// twin), so a re-bake aiming at the counts it reached would add its own
/// slack to that run's. Counts that fall short of the file's target are
/// raised to it (the shortfall shared in proportion to the counts, largest
/// remainders), so the re-bake aims where the file's run did.
pub fn drawn_targets(meshes: &[Mesh], instances: &[usize], file_target: usize) -> Vec<Target> {
    let counts: Vec<usize> = meshes
        .iter()
        .enumerate()
        .map(|(m, mesh)| mesh.triangle_count() * instances.get(m).copied().unwrap_or(1))
        .collect();
    raise_to(&counts, file_target)
        .into_iter()
        .map(|n| Target {
            triangles: Some(n),
            ..Target::default()
        })
        .collect()
}

/// `counts` raised to sum to `total` where they sum to less, the
/// shortfall shared in proportion to them (a zero stays zero); unchanged
/// otherwise.
fn raise_to(counts: &[usize], total: usize) -> Vec<usize> {
    let sum: usize = counts.iter().sum();
    if sum == 0 || sum >= total {
        return counts.to_vec();
    }
    let extra = share_budget(total - sum, counts);
    counts.iter().zip(extra).map(|(c, e)| c + e).collect()
}

/// Triangles every mesh keeps (see [`targets_for`]).
pub const MIN_TRIANGLES: usize = 1;

/// Splits `n` among items in proportion to `weights`, summing to `n`
/// (or less when the weights sum to less).
pub fn share_budget(n: usize, weights: &[usize]) -> Vec<usize> {
    let total: usize = weights.iter().sum();
    if total == 0 {
        return vec![0; weights.len()];
    }
    let n = n.min(total);
    let exact: Vec<f64> = weights
        .iter()
        .map(|&w| n as f64 * w as f64 / total as f64)
        .collect();
    let mut out: Vec<usize> = exact.iter().map(|x| x.floor() as usize).collect();
    let mut rest = n - out.iter().sum::<usize>();
    let mut order: Vec<usize> = (0..weights.len()).collect();
    order.sort_by(|&a, &b| {
        (exact[b] - exact[b].floor())
            .total_cmp(&(exact[a] - exact[a].floor()))
            .then(a.cmp(&b))
    });
    for i in order {
        if rest == 0 {
            break;
        }
        out[i] += 1;
        rest -= 1;
    }
    out
}

/// Bounding-box diagonal of everything the scene shows, in world space.
pub fn scene_diagonal(scene: &Scene) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for (m, world) in scene.instances() {
        for p in &scene.meshes[m as usize].positions {
            let q = wildlod_mesh::transform::apply_point(&world, *p);
            for k in 0..3 {
                lo[k] = lo[k].min(q[k] as f64);
                hi[k] = hi[k].max(q[k] as f64);
            }
        }
    }
    diag(lo, hi)
}

/// Diagonal of mesh `m` as its first instance shows it (0 for a mesh that
/// does not exist or has no position).
pub fn world_diagonal(scene: &Scene, m: usize) -> f64 {
    let Some(mesh) = scene.meshes.get(m) else {
        return 0.0;
    };
    let world = scene
        .instances()
        .into_iter()
        .find(|(i, _)| *i as usize == m)
        .map(|(_, w)| w)
        .unwrap_or(wildlod_mesh::IDENTITY);
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &mesh.positions {
        let q = wildlod_mesh::transform::apply_point(&world, *p);
        for k in 0..3 {
            lo[k] = lo[k].min(q[k] as f64);
            hi[k] = hi[k].max(q[k] as f64);
        }
    }
    diag(lo, hi)
}

fn diag(lo: [f64; 3], hi: [f64; 3]) -> f64 {
    if lo[0] > hi[0] {
        return 0.0;
    }
    (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budget_shares_sum_to_the_budget_in_proportion() {
        assert_eq!(share_budget(10, &[50, 30, 20]), vec![5, 3, 2]);
        assert_eq!(share_budget(10, &[10, 10, 10]), vec![4, 3, 3]);
        // A budget above the total keeps every triangle.
        assert_eq!(share_budget(10, &[1, 1, 1]), vec![1, 1, 1]);
        assert_eq!(share_budget(100, &[3, 4]), vec![3, 4]);
        assert_eq!(share_budget(5, &[0, 0]), vec![0, 0]);
    }

    #[test]
    fn a_rebake_aims_where_the_files_run_aimed() {
        // The file's run aimed for 100 and reached 99 (within a
        // triangle): the re-bake aims for 100 again, the shortfall going
        // to the mesh with the larger remainder; a removed mesh stays at 0.
        assert_eq!(raise_to(&[66, 33, 0], 100), vec![67, 33, 0]);
        assert_eq!(raise_to(&[60, 38], 100), vec![61, 39]);
        // Reached or above the target (an error limit, nothing left to
        // collapse): the counts as they are.
        assert_eq!(raise_to(&[60, 40], 100), vec![60, 40]);
        assert_eq!(raise_to(&[80, 40], 100), vec![80, 40]);
        assert_eq!(raise_to(&[0, 0], 100), vec![0, 0]);
        // Drawn counts: a cube shown twice (24) and once (12), 36 for 37:
        // the triangle short goes to the one drawing two thirds.
        let meshes = [wildlod_mesh::shapes::cube(), wildlod_mesh::shapes::cube()];
        let t = drawn_targets(&meshes, &[2, 1], 37);
        assert_eq!((t[0].triangles, t[1].triangles), (Some(25), Some(12)));
    }

    #[test]
    fn a_per_mesh_budget_is_of_drawn_triangles() {
        // Two cubes of 12 triangles, the first shown by three nodes: the
        // file draws 48. Of a budget of 24 drawn triangles the first gets
        // 18 (three quarters: 6 per instance), the second 6.
        let mut scene = Scene::from_mesh(wildlod_mesh::shapes::cube());
        scene.meshes.push(wildlod_mesh::shapes::cube());
        for m in [0, 0, 1] {
            scene.nodes.push(wildlod_mesh::Node {
                mesh: Some(m),
                ..Default::default()
            });
            scene.roots.push(scene.nodes.len() as u32 - 1);
        }
        let t = targets_for(&scene, None, Some(24), None);
        assert_eq!(t[0].triangles, Some(18));
        assert_eq!(t[1].triangles, Some(6));
    }
}
