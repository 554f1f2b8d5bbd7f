//! `wildlod report`: one self-contained HTML page with the input and its
//! level(s) of detail side by side, textured, as an error heat map or as
//! a wireframe, with the metrics of `compare` (the page is made by
//! `wildlod_pipeline::report_page`, shared with the Python package).

use std::path::Path;

use anyhow::Context;
use wildlod_io::Document;
use wildlod_pipeline::{Level, ReportOptions};

use super::with_flag_names;
use crate::args_assets::ReportArgs;
use crate::stdout::emit;

/// Runs `report`.
pub fn run(a: &ReportArgs) -> anyhow::Result<()> {
    let options = ReportOptions {
        samples: a.samples,
        ..ReportOptions::default()
    };
    let (report, warnings) = wildlod_pipeline::report_files(
        &a.reference,
        &a.candidate,
        &a.output,
        &options,
        a.overwrite,
    )
    .map_err(with_flag_names)?;
    if !a.quiet {
        for w in &warnings {
            eprintln!("warning: {w}");
        }
    }
    if a.json {
        let text = serde_json::to_string_pretty(&report).context("serializing the report")?;
        emit(&(text + "\n"))?;
    } else if !a.quiet {
        emit(&format!("wrote {}\n", a.output.display()))?;
    }
    Ok(())
}

/// The report of a chain: the input against every level (`lod --report`).
pub(crate) fn write_chain_report(
    doc: &Document,
    input: &Path,
    levels: &[Level],
    path: &Path,
    overwrite: bool,
) -> anyhow::Result<()> {
    wildlod_pipeline::write_chain_report(doc, input, levels, path, overwrite)?;
    Ok(())
}
