//! One module per command.

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

/// A library error as the command line says it: settings are named by
/// their flags (`uv_weight` is `--uv-weight`).
pub(crate) fn with_flag_names(e: wildlod_pipeline::Error) -> anyhow::Error {
    match e {
        wildlod_pipeline::Error::Setting {
            name,
            expected,
            value,
        } => anyhow::anyhow!(
            "--{} must be {expected}, got {value}",
            name.replace('_', "-")
        ),
        e => e.into(),
    }
}
