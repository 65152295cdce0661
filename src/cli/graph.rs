//! `hypercontact graph`: the pipeline's stages and wiring as a Mermaid or
//! Graphviz graph on stdout, each stage marked with what `run` would do
//! with it (the plan `run --dry-run` prints, against the same cache).

use anyhow::Result;
use hypercontact_core::Registry;
use hypercontact_runner::RunOptions;
use hypercontact_runner::graph::{GraphFormat, render};

use super::args::{GraphArgs, GraphFormatArg};
use super::prepare::load_with_sets;
use super::say::say_text;

pub fn graph(args: &GraphArgs, registry: &Registry) -> Result<()> {
    let pipeline = load_with_sets(&args.pipeline, &args.set, registry)?;
    let mut options =
        RunOptions::for_pipeline_in(&pipeline, args.out.as_deref(), args.cache.as_deref());
    // The dry run plans against the cache and the output folder's last
    // record, as `run --dry-run` does, and runs nothing.
    options.dry_run = true;
    let report = hypercontact_runner::run(&pipeline, &options)?;
    let format = match args.format {
        GraphFormatArg::Mermaid => GraphFormat::Mermaid,
        GraphFormatArg::Dot => GraphFormat::Dot,
    };
    say_text(render(&report.plan, &pipeline.name, format));
    Ok(())
}
