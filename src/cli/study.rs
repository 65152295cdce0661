//! `hypercontact study`: every variant of the pipeline's `study:` sweep,
//! here or as Slurm jobs, and the tables gathered from them.

use anyhow::Result;
use hypercontact_core::Registry;
use hypercontact_runner::PlanOptions;
use hypercontact_runner::slurm::PipelineRun;
use hypercontact_runner::study::StudyReport;

use super::args::{Executor, RunArgs};
use super::prepare::prepare;
use super::say::say_text;
use super::slurm::on_slurm;

pub fn study(args: &RunArgs, registry: &Registry) -> Result<()> {
    let (pipeline, mut options) = prepare(args, registry)?;
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
    let report = hypercontact_runner::study::run_study(&pipeline, &options)?;
    say_variants(&report, args);
    if !args.quiet {
        for (target, path) in &report.tables {
            say!("{target} → {}", path.display());
        }
    }
    Ok(())
}

/// Each variant's values with its plan (a dry run) or its counts.
fn say_variants(report: &StudyReport, args: &RunArgs) {
    for (k, (variant, run)) in report.runs.iter().enumerate() {
        let values: Vec<String> = variant.iter().map(|(p, v)| format!("{p}={v}")).collect();
        if args.dry_run {
            say!("variant {k}: {}", values.join(" "));
            say_text(run.plan.describe());
        } else if !args.quiet {
            say!(
                "variant {k}: {:<50} {} ran, {} cached",
                values.join(" "),
                run.computed(),
                run.hits()
            );
        }
    }
}
