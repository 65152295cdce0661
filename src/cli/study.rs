//! `hypercontact study`: every variant of the pipeline's `study:` sweep,
//! here or as Slurm jobs, and the tables gathered from them, in the
//! study's own folder (`runs/<name>/study/`).

use anyhow::{Result, bail};
use hypercontact_core::Registry;
use hypercontact_runner::slurm::PipelineRun;
use hypercontact_runner::study::StudyReport;
use hypercontact_runner::{PlanOptions, RunError};

use super::args::{Executor, RunArgs};
use super::prepare::prepare_study;
use super::say::say_text;
use super::slurm::on_slurm;

pub fn study(args: &RunArgs, registry: &Registry) -> Result<()> {
    let (pipeline, mut options) = prepare_study(args, registry)?;
    if args.executor == Executor::Slurm {
        let variants = hypercontact_runner::study::variant_pipelines(&pipeline)?;
        let runs: Vec<PipelineRun> = variants
            .iter()
            .map(|(values, p)| PipelineRun {
                pipeline: p,
                sets: args.set.clone(),
                values: values.iter().map(|(k, v)| (k.clone(), v.clone())).collect(),
                plan: PlanOptions::default(),
            })
            .collect();
        let Some(remote) = on_slurm(args, &options, &runs)? else {
            return Ok(());
        };
        options.remote = remote;
    }
    let (report, failed) = match hypercontact_runner::study::run_study(&pipeline, &options) {
        Ok(report) => (report, None),
        Err(RunError::StudyFailed(report)) => {
            let text = report.failure_text();
            (*report, Some(text))
        }
        Err(e) => return Err(e.into()),
    };
    say_variants(&report, args);
    if !args.quiet {
        for (target, path) in &report.tables {
            say!("{target} → {}", path.display());
        }
    }
    match failed {
        Some(text) => bail!("{text}"),
        None => Ok(()),
    }
}

/// The study's plan (a dry run: an entry computed by an earlier variant
/// shows as shared), or each variant's values with its counts.
fn say_variants(report: &StudyReport, args: &RunArgs) {
    if args.dry_run {
        say_text(report.describe());
        return;
    }
    if args.quiet {
        return;
    }
    let n = report.runs.len();
    for (i, (variant, run)) in report.runs.iter().enumerate() {
        let values: Vec<String> = variant.iter().map(|(p, v)| format!("{p}={v}")).collect();
        let failed = match (run.failures.len(), run.blocked.len()) {
            (0, _) => String::new(),
            (f, 0) => format!(", {f} failed"),
            (f, b) => format!(", {f} failed, {b} not run"),
        };
        say!(
            "variant {}/{n}: {:<50} {} ran, {} cached{failed}",
            i + 1,
            values.join(" "),
            run.computed(),
            run.hits()
        );
    }
}
