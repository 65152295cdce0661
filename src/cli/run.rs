//! `hypercontact run`: one pipeline, here or as Slurm jobs, then the
//! summary of what ran and what was cached.

use std::path::Path;
use std::time::Instant;

use anyhow::{Result, bail};
use hypercontact_core::Registry;
use hypercontact_runner::provenance::Provenance;
use hypercontact_runner::slurm::PipelineRun;
use hypercontact_runner::{PlanOptions, RunError, RunReport};

use super::args::{Executor, RunArgs};
use super::prepare::prepare;
use super::say::say_text;
use super::slurm::on_slurm;

pub fn run(
    args: &RunArgs,
    force: Vec<String>,
    only: Option<String>,
    timings: bool,
    registry: &Registry,
) -> Result<()> {
    let started = Instant::now();
    let (pipeline, mut options) = prepare(args, registry)?;
    options.plan = PlanOptions {
        force,
        only,
        prune: false,
    };
    if args.executor == Executor::Slurm {
        let runs = [PipelineRun {
            pipeline: &pipeline,
            sets: args.set.clone(),
            values: Vec::new(),
            plan: options.plan.clone(),
        }];
        let Some(remote) = on_slurm(args, &options, &runs)? else {
            return Ok(());
        };
        // The jobs computed every entry: what follows exports them.
        options.plan.force.clear();
        options.remote = remote;
    }
    let (report, failed) = match hypercontact_runner::run(&pipeline, &options) {
        Ok(report) => (report, None),
        Err(RunError::Failed(report)) => {
            let text = report.failure_text();
            (*report, Some(text))
        }
        Err(e) => return Err(e.into()),
    };
    if args.dry_run {
        say_text(report.plan.describe());
    } else if !args.quiet {
        say_summary(&report, started, &options.out_dir);
    }
    if timings && !args.dry_run {
        say!("");
        say_text(hypercontact_runner::timings::table(&report.provenance));
    }
    match failed {
        // The summary first, then every failure with its causes.
        Some(text) => bail!("{text}"),
        None => Ok(()),
    }
}

/// `hypercontact timings RUN_DIR`: the table of a finished run.
pub fn timings(run_dir: &Path) -> Result<()> {
    let provenance = Provenance::load_with_times(&run_dir.join("provenance.json"))?;
    say_text(hypercontact_runner::timings::table(&provenance));
    Ok(())
}

/// One line per stage, then the counts, the time and where the outputs are.
fn say_summary(report: &RunReport, started: Instant, out_dir: &Path) {
    say_text(report.summary());
    let temps = match report.temps_not_needed() {
        0 => String::new(),
        n => format!(", {n} temporary not needed"),
    };
    let failed = match (report.failures.len(), report.blocked.len()) {
        (0, _) => String::new(),
        (f, 0) => format!(", {f} failed"),
        (f, b) => format!(", {f} failed, {b} not run"),
    };
    say!(
        "{} ran, {} cached{temps}{failed} in {:.2} s; outputs in {}",
        report.computed(),
        report.hits(),
        // On Slurm, the whole wait, not only the export.
        started
            .elapsed()
            .as_secs_f64()
            .max(report.provenance.wall_s),
        out_dir.display()
    );
}
