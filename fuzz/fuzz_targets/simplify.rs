//! simplify_mesh on arbitrary small meshes with arbitrary options.
#![no_main]

use libfuzzer_sys::fuzz_target;
use wildlod_fuzz::{check_simplify, SimplifyCase};

fuzz_target!(|case: SimplifyCase| check_simplify(&case));
