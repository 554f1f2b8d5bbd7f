//! The parallel first phase on the corpus's large scan: under an error
//! target it keeps making the collapses, as under a ratio.

use wildlod_simplify::{simplify_mesh, Options, StopReason, Target};
use wildlod_testkit::corpus;

#[test]
fn the_dragon_under_an_error_target_is_simplified_mostly_in_parallel() {
    // `large/dragon_vrip.glb`, 871k triangles. After the free collapses of
    // the first round, the cheapest one left was refused, a round removed
    // nothing, and the pass ended there: the global loop then made all the
    // collapses, at 2.5× the time.
    let Some(root) = corpus("the_dragon_under_an_error_target_is_simplified_mostly_in_parallel")
    else {
        return;
    };
    let doc = wildlod_io::read(root.join("large/dragon_vrip.glb")).unwrap();
    let mesh = &doc.scene.meshes[0];
    let o = Options {
        // As `wildlod simplify --error` asks: down to one triangle, within
        // the error.
        target: Target {
            error: Some(0.001),
            triangles: Some(1),
            ..Target::default()
        },
        ..Options::default()
    };
    let (_, rep) = simplify_mesh(mesh, &o).unwrap();
    assert_eq!(rep.stop, Some(StopReason::ErrorLimit));
    assert!(
        rep.parallel_collapses * 10 > rep.collapses * 9,
        "{} of {} collapses in parallel",
        rep.parallel_collapses,
        rep.collapses
    );
}
