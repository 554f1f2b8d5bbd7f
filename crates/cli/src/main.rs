//! `wildlod`: levels of detail for real-world meshes.
//!
//! A thin binary: arguments are parsed ([`args`]) into validated settings,
//! then each command runs a pipeline of the library crates.

mod allocator;
mod args;
mod args_assets;
mod commands;
mod flags;
mod progress;
mod stdout;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    allocator::configure();
    let cli = args::Cli::parse();
    match commands::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
