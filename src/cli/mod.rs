//! The subcommands of `hypercontact`, one file each: this module hands the
//! parsed command line to the one it names.

#[macro_use]
mod say;
mod args;
mod cache;
mod exec_stage;
mod export;
mod graph;
mod prepare;
mod run;
mod slurm;
mod status;
mod study;

use anyhow::Result;

pub use args::Cli;
use args::Command;

/// Runs the command the user gave.
pub fn dispatch(cli: Cli) -> Result<()> {
    hypercontact_runner::producer::set_running(env!("HYPERCONTACT_BUILD"));
    let registry = hypercontact::registry();
    match cli.command {
        Command::Run {
            args,
            force,
            only,
            timings,
        } => run::run(&args, force, only, timings, &registry),
        Command::Timings { run_dir } => run::timings(&run_dir),
        Command::Study { args } => study::study(&args, &registry),
        Command::Graph { args } => graph::graph(&args, &registry),
        Command::Export { args } => export::export(&args),
        Command::Stages { kind, json } => crate::stages::print(&registry, kind.as_deref(), json),
        Command::Status { pipeline, out } => status::status(&pipeline, out, &registry),
        Command::ExecStage { job } => exec_stage::exec_stage(&job, &registry),
        Command::Cache { action } => cache::cache_command(action, &registry),
    }
}
