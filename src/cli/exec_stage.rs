//! `hypercontact exec-stage JOBFILE`: what a Slurm job runs. It rebuilds the
//! pipeline as it was submitted and computes the one stage into the cache.

use std::path::Path;

use anyhow::Result;
use hypercontact_core::Registry;
use hypercontact_runner::cache::short_key;
use hypercontact_runner::exec::JobOutcome;
use hypercontact_runner::slurm::JobSpec;

use super::prepare::load_with_sets;

pub fn exec_stage(job_file: &Path, registry: &Registry) -> Result<()> {
    let spec = JobSpec::read(job_file)?;
    let mut pipeline = load_with_sets(&spec.pipeline, &spec.sets, registry)?;
    for (path, value) in &spec.values {
        pipeline.set_value(
            path,
            value.clone(),
            &format!("study value {path} = {value}"),
        )?;
    }
    let short = short_key(&spec.job.key);
    say!(
        "stage `{}` of {}, entry {short}, cache {}",
        spec.job.stage,
        spec.pipeline.display(),
        spec.cache.display()
    );
    match hypercontact_runner::exec::exec_stage(&pipeline, &spec.cache, &spec.job)? {
        JobOutcome::Computed { compute_s } => say!(
            "computed stage `{}` (entry {short}) in {compute_s:.2} s",
            spec.job.stage
        ),
        JobOutcome::AlreadyCached => say!(
            "stage `{}`: entry {short} was already in the cache; nothing to do",
            spec.job.stage
        ),
    }
    Ok(())
}
