//! Sharp creases held like borders (`Metric::crease_weight`) on a real CAD
//! part of the corpus.

use wildlod_eval::{compare, CompareOptions, EvalMesh};
use wildlod_simplify::{simplify_mesh, Options, Target};
use wildlod_testkit::corpus;

#[test]
fn a_cad_plates_creases_held_keep_its_surface_closer() {
    // `wild/1002_tray_bottom.stl`: a 3 mm plate 355 mm across with holes,
    // finely tessellated, so its rim is walls of long thin triangles whose
    // planes weigh little. At half its triangles, with the creases held,
    // the mean distance measures 0.42 times that without (1.0e-7 against
    // 2.4e-7 of the diagonal; 0.53 when only the crease planes held them,
    // before the crease area term).
    let Some(root) = corpus("a_cad_plates_creases_held_keep_its_surface_closer") else {
        return;
    };
    let doc = wildlod_io::read(root.join("wild/1002_tray_bottom.stl")).unwrap();
    let mesh = &doc.scene.meshes[0];
    let reference = EvalMesh::from_mesh(mesh);
    let cmp = CompareOptions {
        samples: 50_000,
        ..CompareOptions::default()
    };
    let chamfer = |crease_weight: f64, crease_area_weight: f64| {
        let mut o = Options {
            target: Target {
                ratio: Some(0.5),
                ..Target::default()
            },
            ..Options::default()
        };
        o.metric.crease_weight = crease_weight;
        o.metric.crease_area_weight = crease_area_weight;
        let (out, report) = simplify_mesh(mesh, &o).unwrap();
        assert!(report.output_triangles <= report.target_triangles + 1);
        compare(&reference, &EvalMesh::from_mesh(&out), &cmp).chamfer_mean
    };
    let m = Options::default().metric;
    assert!(m.crease_weight > 0.0);
    // Free: neither the crease planes nor the crease area term (which
    // also holds creases, since it was added after this test) hold them.
    let (held, free) = (
        chamfer(m.crease_weight, m.crease_area_weight),
        chamfer(0.0, 0.0),
    );
    eprintln!("Chamfer with creases held {held:e}, without {free:e}");
    assert!(
        held < 0.8 * free,
        "Chamfer with creases held {held:e}, without {free:e}"
    );
}
