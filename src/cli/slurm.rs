//! `--executor slurm` for `run` and `study`: submit the plans' jobs, then
//! wait for them (Ctrl-C cancels them), or print what would be submitted,
//! or return at once with `--detach`.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context as _, Result, bail};
use hypercontact_runner::RunOptions;
use hypercontact_runner::cache::short_key;
use hypercontact_runner::slurm::{PipelineRun, SiteProfile, SlurmRun, Submission};

use super::args::RunArgs;

/// Set by Ctrl-C (or SIGTERM) while waiting on Slurm.
static CANCEL: AtomicBool = AtomicBool::new(false);

/// Submits the plans to Slurm and waits for their jobs. `None` when there
/// is nothing more to do here (a dry run, `--detach`); else the entries the
/// jobs computed (key → job), for the export that follows.
pub fn on_slurm(
    args: &RunArgs,
    options: &RunOptions,
    runs: &[PipelineRun],
) -> Result<Option<BTreeMap<String, String>>> {
    let slurm = SlurmRun {
        cache_dir: options.cache_dir.clone(),
        log_dir: options.out_dir.join("slurm"),
        profile: SiteProfile::find(args.slurm_profile.as_deref())?,
        dry_run: args.dry_run,
        quiet: args.quiet,
    };
    if !args.dry_run && !args.detach {
        // Before submitting: a Ctrl-C from the first job on cancels them all.
        ctrlc::set_handler(|| CANCEL.store(true, Ordering::SeqCst))
            .context("installing the Ctrl-C handler")?;
    }
    let submission = hypercontact_runner::slurm::submit(runs, &slurm)?;
    if args.dry_run {
        say_would_submit(&submission);
        return Ok(None);
    }
    if args.detach {
        if !args.quiet {
            say_detached(&submission, args);
        }
        return Ok(None);
    }
    if !args.quiet {
        match submission.jobs.len() {
            0 => eprintln!("nothing to submit: every entry the plan needs is in the cache"),
            n => eprintln!(
                "submitted {n} Slurm jobs; logs in {}",
                slurm.log_dir.join("logs").display()
            ),
        }
    }
    hypercontact_runner::slurm::wait(&submission, &slurm, &CANCEL)?;
    if CANCEL.load(Ordering::SeqCst) {
        bail!("cancelled after the jobs finished: their entries are in the cache, not exported");
    }
    Ok(Some(submission.remote()))
}

/// `--dry-run`: the jobs with their resources and entries.
fn say_would_submit(submission: &Submission) {
    say!("would submit {} Slurm jobs:", submission.jobs.len());
    for j in &submission.jobs {
        say!(
            "  {:<20} {:<20} cpus {}, mem {} MiB, time {} min, entry {}",
            j.stage,
            j.kind,
            j.cpus,
            j.mem_mb,
            j.time_min,
            short_key(&j.key)
        );
    }
}

/// `--detach`: the job ids and the commands that follow and collect them.
fn say_detached(submission: &Submission, args: &RunArgs) {
    let ids: Vec<&str> = submission.jobs.iter().map(|j| j.job_id.as_str()).collect();
    say!(
        "submitted {} Slurm jobs ({}); `hypercontact status {}{}` follows them, the \
         same command again collects the outputs",
        ids.len(),
        ids.join(" "),
        args.pipeline.display(),
        args.out
            .as_ref()
            .map(|o| format!(" --out {}", o.display()))
            .unwrap_or_default()
    );
}
