//! Issue 34: a check that did not run says so in the normal `cargo test`
//! output, not only with `--nocapture`.
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

use std::process::Command;

/// Run only by [`a_skipped_check_is_named_in_the_normal_test_output`],
/// in a child process, with the corpus made unreachable.
#[test]
#[ignore = "run by a_skipped_check_is_named_in_the_normal_test_output"]
fn corpus_reader_in_a_child() {
    assert!(wildlod_testkit::corpus("corpus_reader_in_a_child").is_none());
}

#[test]
fn a_skipped_check_is_named_in_the_normal_test_output() {
    let dir = tempfile::tempdir().unwrap();
    // This very test binary, run as `cargo test` runs it: output captured.
    let o = Command::new(std::env::current_exe().unwrap())
        .args(["--ignored", "--exact", "corpus_reader_in_a_child"])
        .env("WILDLOD_CORPUS", dir.path().join("no corpus here"))
        .env_remove("CI")
        .output()
        .unwrap();
    let all = String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{all}");
    assert!(
        all.lines()
            .any(|l| l.starts_with("SKIPPED corpus_reader_in_a_child: ")
                && l.contains("no corpus here")),
        "the skip is not in the normal output:\n{all}"
    );
}
