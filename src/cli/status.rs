//! `hypercontact status`: the Slurm jobs of a pipeline's last submission,
//! each with its state, whether its entry is in the cache, and its log.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use hypercontact_core::Registry;
use hypercontact_runner::slurm::Submission;
use hypercontact_runner::{Pipeline, RunOptions};

pub fn status(pipeline: &Path, out: Option<PathBuf>, registry: &Registry) -> Result<()> {
    let pipeline = Pipeline::load(pipeline, registry)?;
    let out = out.unwrap_or_else(|| {
        // A run's submission, else a study's (in its own folder).
        let run = RunOptions::for_pipeline(&pipeline).out_dir;
        let study = hypercontact_runner::study::default_dir(&pipeline);
        match Submission::path(&run.join("slurm")).exists() || !study.join("slurm").exists() {
            true => run,
            false => study,
        }
    });
    slurm_status(&out.join("slurm"))
}

fn slurm_status(log_dir: &Path) -> Result<()> {
    let Some(submission) = Submission::read(log_dir)? else {
        bail!(
            "no Slurm submission in {} (run with `--executor slurm` first)",
            log_dir.display()
        );
    };
    let statuses = hypercontact_runner::slurm::status(&submission)?;
    let mut done = 0;
    let mut failed = 0;
    let mut queued = 0;
    for s in &statuses {
        let entry = if s.entry { "entry" } else { "-" };
        say!(
            "{:<20} {:>8}  {:<12} {:<6} {}",
            s.job.stage,
            s.job.job_id,
            s.state,
            entry,
            s.job.log.display()
        );
        match (s.entry, s.queued()) {
            (true, _) => done += 1,
            (false, true) => queued += 1,
            (false, false) => failed += 1,
        }
    }
    say!(
        "{} jobs: {done} done, {queued} queued or running, {failed} failed or cancelled",
        statuses.len()
    );
    if queued == 0 && failed == 0 {
        say!("all entries are in the cache: the same run command again exports them");
    }
    Ok(())
}
