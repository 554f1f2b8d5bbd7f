//! The off reader and the whole pipeline after it (see wildlod_fuzz::check_file).
#![no_main]

use libfuzzer_sys::fuzz_target;
use wildlod_fuzz::{check_file, InputFormat};

fuzz_target!(|data: &[u8]| check_file(InputFormat::Off, data));
