//! One module per command.

mod bake;
mod batch;
mod compare;
mod demo;
mod info;
mod lod;
mod report;
mod simplify;

use crate::args::{Cli, Command};

/// Runs the parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Simplify(a) => simplify::run(&simplify::Config::from_args(a)?),
        Command::Info(a) => info::run(&a),
        Command::Compare(a) => compare::run(&a),
        Command::Demo(a) => demo::run(&a),
        Command::Lod(a) => lod::run(a),
        Command::Batch(a) => batch::run(a),
        Command::Report(a) => report::run(&a),
    }
}
