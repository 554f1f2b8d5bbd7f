//! Skinned levels of detail judged as they are drawn: posed (issue 31,
//! decision 8).
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

mod support;

use std::process::Command;

use support::{npm_tool, posed_hausdorff, s, wildlod};
use wildlod_testkit::scenes;

#[test]
fn a_bent_arm_keeps_its_elbow_in_every_frame_of_the_bend() {
    // A tube bent by 90° at its middle joint over 31 frames, at 10%: the
    // rest pose is a straight cylinder whose middle rings cost nothing
    // there; posed, they are the elbow. Against gltfpack (meshoptimizer's
    // glTF tool) at the same ratio, frame by frame.
    let Some(tool) = npm_tool("gltfpack", "gltfpack") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("tube.glb");
    wildlod_io::write(
        &wildlod_io::Document::from_scene(scenes::bent_tube()),
        &input,
        &wildlod_io::WriteOptions::default(),
    )
    .unwrap();
    let ours = dir.path().join("ours.glb");
    let o = wildlod(&["simplify", s(&input), "-o", s(&ours), "--ratio", "0.1"]);
    assert!(o.status.success(), "{}", support::stderr(&o));
    let theirs = dir.path().join("gltfpack.glb");
    let o = Command::new(tool.join("node_modules/.bin/gltfpack"))
        .args(["-i", s(&input), "-o", s(&theirs), "-si", "0.1"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{o:?}");
    let (a, b) = (
        posed_hausdorff(&input, &ours, &["--frames", "31"]),
        posed_hausdorff(&input, &theirs, &["--frames", "31"]),
    );
    assert_eq!(a.len(), 31);
    for (frame, (x, y)) in a.iter().zip(&b).enumerate() {
        assert!(
            x <= y,
            "frame {frame}: posed Hausdorff {x} against gltfpack's {y}\n{a:?}\n{b:?}"
        );
    }
}
