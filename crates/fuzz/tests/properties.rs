//! The fuzz targets as bounded property tests, so that `cargo test` (and
//! with it CI) checks them on every change: the seeds generated in code,
//! mutated by proptest-chosen edits, through the whole read → simplify →
//! write → read-back pipeline; and arbitrary small meshes with arbitrary
//! options through `simplify_mesh`. Plus every input a campaign ever
//! found, kept in `regressions/`.
//!
//! `WILDLOD_FUZZ_CASES` sets the cases per target (default 600); a long
//! campaign is libFuzzer's job (see docs/robustness.md).

use std::path::Path;
use std::sync::OnceLock;

use arbitrary::{Arbitrary, Unstructured};
use proptest::collection::vec;
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use wildlod_fuzz::mutate::{apply, Mutation, TOKENS, WORDS};
use wildlod_fuzz::seeds::seeds;
use wildlod_fuzz::{check_file, check_simplify, InputFormat, SimplifyCase};

fn cases() -> u32 {
    std::env::var("WILDLOD_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(600)
}

/// A fixed seed, so that CI runs are reproducible (`WILDLOD_FUZZ_SEED`
/// picks another; exploring is the long campaign's job).
fn runner() -> TestRunner {
    let seed = std::env::var("WILDLOD_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(13);
    TestRunner::new(Config {
        cases: cases(),
        failure_persistence: None,
        rng_algorithm: proptest::test_runner::RngAlgorithm::ChaCha,
        rng_seed: proptest::test_runner::RngSeed::Fixed(seed),
        ..Config::default()
    })
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), 0u8..8).prop_map(|(at, bit)| Mutation::FlipBit { at, bit }),
        (any::<usize>(), any::<u8>()).prop_map(|(at, value)| Mutation::SetByte { at, value }),
        (any::<usize>(), vec(any::<u8>(), 1..8))
            .prop_map(|(at, bytes)| Mutation::Insert { at, bytes }),
        (any::<usize>(), 1usize..64).prop_map(|(at, len)| Mutation::Delete { at, len }),
        (any::<usize>(), 1usize..256, any::<usize>())
            .prop_map(|(from, len, to)| Mutation::Duplicate { from, len, to }),
        (any::<usize>(), 0..TOKENS.len()).prop_map(|(at, which)| Mutation::Token { at, which }),
        (any::<usize>(), 0..WORDS.len()).prop_map(|(at, which)| Mutation::Word { at, which }),
        any::<usize>().prop_map(|at| Mutation::Truncate { at }),
    ]
}

fn all_seeds() -> &'static Vec<(InputFormat, Vec<Vec<u8>>)> {
    static SEEDS: OnceLock<Vec<(InputFormat, Vec<Vec<u8>>)>> = OnceLock::new();
    SEEDS.get_or_init(|| InputFormat::ALL.iter().map(|&f| (f, seeds(f))).collect())
}

fn fuzz_format(format: InputFormat) {
    let seeds = &all_seeds()
        .iter()
        .find(|(f, _)| *f == format)
        .expect("every format has seeds")
        .1;
    let strategy = (0..seeds.len(), vec(mutation(), 0..6));
    let result = runner().run(&strategy, |(k, mutations)| {
        check_file(format, &apply(&seeds[k], &mutations));
        Ok(())
    });
    if let Err(e) = result {
        panic!("{format:?}: {e}");
    }
}

#[test]
fn obj_and_mtl_inputs_keep_the_pipeline_properties() {
    fuzz_format(InputFormat::Obj);
}

#[test]
fn ply_inputs_keep_the_pipeline_properties() {
    fuzz_format(InputFormat::Ply);
}

#[test]
fn stl_inputs_keep_the_pipeline_properties() {
    fuzz_format(InputFormat::Stl);
}

#[test]
fn off_inputs_keep_the_pipeline_properties() {
    fuzz_format(InputFormat::Off);
}

#[test]
fn gltf_inputs_keep_the_pipeline_properties() {
    fuzz_format(InputFormat::Gltf);
}

#[test]
fn glb_inputs_keep_the_pipeline_properties() {
    fuzz_format(InputFormat::Glb);
}

#[test]
fn arbitrary_meshes_and_options_keep_the_simplifier_properties() {
    let result = runner().run(&vec(any::<u8>(), 0..4096), |bytes| {
        if let Ok(case) = SimplifyCase::arbitrary(&mut Unstructured::new(&bytes)) {
            check_simplify(&case);
        }
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// Inputs that once broke a property, as the campaign found them
/// (`regressions/<target>/<name>`, target as in `fuzz/fuzz_targets/`).
#[test]
fn inputs_found_by_campaigns_keep_the_properties() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("regressions");
    let Ok(targets) = std::fs::read_dir(&root) else {
        return;
    };
    let mut checked = 0;
    for target in targets.flatten() {
        let name = target.file_name().to_string_lossy().into_owned();
        let format = InputFormat::ALL.into_iter().find(|f| f.extension() == name);
        for file in std::fs::read_dir(target.path())
            .into_iter()
            .flatten()
            .flatten()
        {
            let data = std::fs::read(file.path()).expect("regression input readable");
            match format {
                Some(f) => check_file(f, &data),
                None if name == "simplify" => {
                    if let Ok(case) = SimplifyCase::arbitrary(&mut Unstructured::new(&data)) {
                        check_simplify(&case);
                    }
                }
                None => panic!("regressions/{name}: no such fuzz target"),
            }
            checked += 1;
        }
    }
    assert!(checked > 0 || !root.exists(), "regressions/ holds no input");
}
