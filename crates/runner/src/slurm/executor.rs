//! Submitting a plan to Slurm and waiting for it.
//!
//! Every stage a plan must run becomes one batch job (`sbatch`) running
//! `hypercontact exec-stage JOBFILE`, chained to the jobs of the stages it
//! reads by `--dependency=afterok:…` (with `--kill-on-invalid-dep=yes`, so
//! the dependents of a failed job leave the queue instead of waiting for
//! ever). The jobs of a study's variants are keyed by cache entry: an entry
//! several variants share is one job. Jobs read and write the shared cache
//! with the local executor's lock, staging folder and rename, so a job
//! killed mid-stage leaves its entry absent and the cache valid.
//!
//! The queue is read with `squeue --states=all`, which needs no accounting
//! database (`sacct` does); a job that has left the queue is judged by its
//! entry: present and whole means it succeeded. This is how the cluster
//! executors of Snakemake and Nextflow hand a DAG to the scheduler rather
//! than scheduling themselves.

use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use hypercontact_core::regular_file::{MIB, read_checked};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde::{Deserialize, Serialize};

use super::partition;
use super::settings::{JobResources, SiteProfile};
use crate::cache::{Cache, EntryState, unix_now};
use crate::exec::{RunError, StageJob, open_cache};
use crate::pipeline::Pipeline;
use crate::plan::{Plan, PlanOptions};

/// One pipeline to submit, with how a job rebuilds it from the file.
pub struct PipelineRun<'a> {
    /// The pipeline with every override applied.
    pub pipeline: &'a Pipeline,
    /// `--set STAGE.PARAM=VALUE` assignments, as given.
    pub sets: Vec<String>,
    /// A study variant's values (`stage.param` → value), applied after them.
    pub values: Vec<(String, serde_json::Value)>,
    pub plan: PlanOptions,
}

/// What a job reads to know its work: `<log dir>/jobs/<key>.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JobSpec {
    pub format: u32,
    /// The pipeline file, absolute.
    pub pipeline: PathBuf,
    pub sets: Vec<String>,
    pub values: Vec<(String, serde_json::Value)>,
    /// The cache folder, absolute: on a cluster, on a filesystem every node
    /// mounts at the same path.
    pub cache: PathBuf,
    pub job: StageJob,
}

pub const JOB_FORMAT: u32 = 1;

/// The largest job file read: a job names a pipeline and a few settings.
const JOB_LIMIT_BYTES: u64 = 16 * MIB;

/// The largest `submission.json` read: a line per job, thousands of jobs.
const SUBMISSION_LIMIT_BYTES: u64 = 64 * MIB;

impl JobSpec {
    pub fn read(path: &Path) -> Result<Self, RunError> {
        let bad = |why: String| RunError::Job(format!("job file {}: {why}", path.display()));
        let bytes = read_checked(path, "job files", JOB_LIMIT_BYTES).map_err(|e| bad(e.why))?;
        let spec: JobSpec = serde_json::from_slice(&bytes).map_err(|e| bad(e.to_string()))?;
        if spec.format != JOB_FORMAT {
            return Err(bad(format!(
                "format {} (this hypercontact reads {JOB_FORMAT}); submit again",
                spec.format
            )));
        }
        Ok(spec)
    }
}

/// One submitted job.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SubmittedJob {
    pub stage: String,
    pub kind: String,
    pub key: String,
    pub job_id: String,
    pub log: PathBuf,
    /// Job ids this one waits for (`afterok`).
    pub after: Vec<String>,
    /// The first variant of a study that needs the entry (0 for a run).
    pub variant: usize,
    pub cpus: u32,
    pub mem_mb: u64,
    pub time_min: u64,
}

/// `<log dir>/submission.json`: what a submission sent, for `status`, for
/// a rerun that finds the jobs still queued, and for the tests.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Submission {
    pub format: u32,
    pub pipeline: String,
    pub cache: PathBuf,
    pub submitted_unix_s: u64,
    pub jobs: Vec<SubmittedJob>,
}

impl Submission {
    pub fn path(log_dir: &Path) -> PathBuf {
        log_dir.join("submission.json")
    }

    pub fn read(log_dir: &Path) -> Result<Option<Self>, RunError> {
        let path = Self::path(log_dir);
        match read_checked(&path, "submission records", SUBMISSION_LIMIT_BYTES) {
            Err(e) if e.not_found => Ok(None),
            Err(e) => Err(RunError::Job(e.to_string())),
            Ok(bytes) => serde_json::from_slice(&bytes)
                .map(Some)
                .map_err(|e| RunError::Job(format!("{}: {e}", path.display()))),
        }
    }

    /// Key → job id of every job, as provenance records it.
    pub fn remote(&self) -> BTreeMap<String, String> {
        self.jobs
            .iter()
            .map(|j| (j.key.clone(), format!("slurm {}", j.job_id)))
            .collect()
    }
}

/// Where and how to submit.
#[derive(Clone, Debug)]
pub struct SlurmRun {
    pub cache_dir: PathBuf,
    /// Job files, scripts, logs and `submission.json`.
    pub log_dir: PathBuf,
    pub profile: SiteProfile,
    /// Print what would be submitted; submit nothing.
    pub dry_run: bool,
    pub quiet: bool,
}

impl SlurmRun {
    fn command(&self) -> Result<PathBuf, RunError> {
        match &self.profile.command {
            Some(c) => Ok(c.clone()),
            None => std::env::current_exe()
                .map_err(|e| RunError::Job(format!("cannot find this hypercontact binary: {e}"))),
        }
    }

    pub fn poll(&self) -> Duration {
        Duration::from_secs_f64(self.profile.poll_s.unwrap_or(5.0))
    }
}

/// A job the plan needs, before submission.
struct Pending {
    stage: String,
    kind: String,
    key: String,
    variant: usize,
    after_keys: Vec<String>,
    resources: JobResources,
    spec: JobSpec,
}

/// Plans every variant and submits one job per entry that must be
/// computed, or reuses the job of an earlier submission still in the
/// queue for it. Returns the submission (also written to
/// `<log dir>/submission.json`); with `dry_run`, the jobs it would submit
/// with empty ids.
pub fn submit(variants: &[PipelineRun], run: &SlurmRun) -> Result<Submission, RunError> {
    let cache_dir = absolute(&run.cache_dir)?;
    let log_dir = absolute(&run.log_dir)?;
    let cache = open_cache(&cache_dir)?;
    let pending = pending_jobs(variants, run, &cache, &cache_dir)?;
    let name = variants
        .first()
        .map(|v| v.pipeline.name.clone())
        .unwrap_or_default();
    let mut submission = Submission {
        format: JOB_FORMAT,
        pipeline: name,
        cache: cache_dir.clone(),
        submitted_unix_s: unix_now(),
        jobs: Vec::new(),
    };
    if run.dry_run {
        for p in pending {
            submission
                .jobs
                .push(submitted(p, String::new(), PathBuf::new(), Vec::new()));
        }
        return Ok(submission);
    }
    check_nodes_hold(&pending)?;
    let queued = still_queued(&log_dir, &cache_dir)?;
    submission.jobs = send(pending, queued, &run.command()?, &log_dir, &run.profile)?;
    let bytes = serde_json::to_vec_pretty(&submission).expect("a submission serialises");
    let path = Submission::path(&log_dir);
    crate::write_atomic(&path, &bytes).map_err(|cause| RunError::Output { path, cause })?;
    Ok(submission)
}

/// Refuses, before anything is submitted, a job whose request no node of
/// its partition can hold: Slurm would keep it pending for ever.
fn check_nodes_hold(pending: &[Pending]) -> Result<(), RunError> {
    let mut partitions: HashMap<Option<String>, Option<partition::PartitionNodes>> = HashMap::new();
    for p in pending {
        let wanted = p.resources.partition.clone();
        let nodes = partitions
            .entry(wanted.clone())
            .or_insert_with(|| partition::query(wanted.as_deref()));
        if let Some(nodes) = nodes
            && !nodes.holds(p.resources.cpus, p.resources.mem_mb)
        {
            return Err(RunError::Job(partition::refusal(
                &p.stage,
                &p.kind,
                &p.resources,
                nodes,
            )));
        }
    }
    Ok(())
}

/// The jobs the variants' plans need, one per entry, in an order where
/// each comes after those it waits for.
fn pending_jobs(
    variants: &[PipelineRun],
    run: &SlurmRun,
    cache: &Cache,
    cache_dir: &Path,
) -> Result<Vec<Pending>, RunError> {
    let mut pending: Vec<Pending> = Vec::new();
    let mut seen: HashSet<String> = HashSet::new();
    for (index, v) in variants.iter().enumerate() {
        let plan = Plan::build(v.pipeline, cache, &v.plan, None)?;
        let running: HashSet<&str> = plan
            .stages
            .iter()
            .filter(|s| s.runs)
            .map(|s| s.name.as_str())
            .collect();
        for s in plan.stages.iter().filter(|s| s.runs) {
            if !seen.insert(s.key.clone()) {
                continue;
            }
            let decl = v.pipeline.stage(&s.name).expect("plans name stages");
            pending.push(Pending {
                stage: s.name.clone(),
                kind: s.kind.clone(),
                key: s.key.clone(),
                variant: index,
                after_keys: s
                    .inputs
                    .iter()
                    .filter(|i| running.contains(i.from_stage.as_str()))
                    .map(|i| i.upstream_key.clone())
                    .collect(),
                resources: JobResources::resolve(
                    decl.stage.resources(),
                    &run.profile,
                    &v.pipeline.slurm,
                    &decl.slurm,
                ),
                spec: JobSpec {
                    format: JOB_FORMAT,
                    pipeline: absolute(&v.pipeline.file)?,
                    sets: v.sets.clone(),
                    values: v.values.clone(),
                    cache: cache_dir.to_owned(),
                    job: StageJob {
                        stage: s.name.clone(),
                        key: s.key.clone(),
                        force: v.plan.force.contains(&s.name),
                    },
                },
            });
        }
    }
    Ok(pending)
}

/// Jobs of an earlier submission to the same cache still queued, by entry
/// key: waiting for them beats computing the entry twice. (An unreadable
/// record only costs that: the entry's lock still lets one job compute it.)
fn still_queued(
    log_dir: &Path,
    cache_dir: &Path,
) -> Result<HashMap<String, SubmittedJob>, RunError> {
    let mut queued: HashMap<String, SubmittedJob> = HashMap::new();
    if let Ok(Some(previous)) = Submission::read(log_dir)
        && previous.cache == cache_dir
    {
        let states = squeue(&job_ids(&previous.jobs))?;
        for job in previous.jobs {
            if states
                .get(&job.job_id)
                .is_some_and(|(state, _)| !is_final(state))
            {
                queued.insert(job.key.clone(), job);
            }
        }
    }
    Ok(queued)
}

/// Submits each pending job, chained to the jobs of the entries it reads,
/// or takes the queued job already making its entry. On a refusal, cancels
/// what it submitted: no half-submitted plan stays behind.
fn send(
    pending: Vec<Pending>,
    mut queued: HashMap<String, SubmittedJob>,
    command: &Path,
    log_dir: &Path,
    profile: &SiteProfile,
) -> Result<Vec<SubmittedJob>, RunError> {
    let mut jobs: Vec<SubmittedJob> = Vec::new();
    let mut ids: HashMap<String, String> = HashMap::new();
    for p in pending {
        if let Some(job) = queued.remove(&p.key) {
            ids.insert(p.key.clone(), job.job_id.clone());
            jobs.push(job);
            continue;
        }
        let after: Vec<String> = p
            .after_keys
            .iter()
            .filter_map(|k| ids.get(k).cloned())
            .collect();
        match sbatch(&p, &after, command, log_dir, profile) {
            Ok((id, log)) => {
                ids.insert(p.key.clone(), id.clone());
                jobs.push(submitted(p, id, log, after));
            }
            Err(e) => {
                let _ = scancel(&job_ids(&jobs));
                return Err(e);
            }
        }
    }
    Ok(jobs)
}

fn job_ids<'a>(jobs: impl IntoIterator<Item = &'a SubmittedJob>) -> Vec<String> {
    jobs.into_iter().map(|j| j.job_id.clone()).collect()
}

fn submitted(p: Pending, job_id: String, log: PathBuf, after: Vec<String>) -> SubmittedJob {
    SubmittedJob {
        stage: p.stage,
        kind: p.kind,
        key: p.key,
        job_id,
        log,
        after,
        variant: p.variant,
        cpus: p.resources.cpus,
        mem_mb: p.resources.mem_mb,
        time_min: p.resources.time_min,
    }
}

fn absolute(path: &Path) -> Result<PathBuf, RunError> {
    std::path::absolute(path)
        .map_err(|e| RunError::Job(format!("{}: cannot make it absolute: {e}", path.display())))
}

/// A word for the shell, quoted.
fn sh_quote(text: &str) -> String {
    format!("'{}'", text.replace('\'', r"'\''"))
}

/// Writes the job file and script of one job and submits it.
fn sbatch(
    p: &Pending,
    after: &[String],
    command: &Path,
    log_dir: &Path,
    profile: &SiteProfile,
) -> Result<(String, PathBuf), RunError> {
    let jobs_dir = log_dir.join("jobs");
    let logs_dir = log_dir.join("logs");
    let io = |path: &Path| {
        let path = path.to_owned();
        move |cause| RunError::Output { path, cause }
    };
    std::fs::create_dir_all(&logs_dir).map_err(io(&logs_dir))?;
    let spec_path = jobs_dir.join(format!("{}.json", p.key));
    let bytes = serde_json::to_vec_pretty(&p.spec).expect("a job spec serialises");
    crate::write_atomic(&spec_path, &bytes).map_err(io(&spec_path))?;
    let mut script = format!(
        "#!/bin/bash\n# hypercontact: stage `{}` ({}), cache entry {}\nset -euo pipefail\n",
        p.stage, p.kind, p.key
    );
    for line in &profile.setup {
        script.push_str(line);
        script.push('\n');
    }
    // The stage's parallel work on the CPUs the job was given.
    script.push_str("export RAYON_NUM_THREADS=\"${SLURM_CPUS_PER_TASK:-1}\"\n");
    script.push_str(&format!(
        "exec {} exec-stage {}\n",
        sh_quote(&command.display().to_string()),
        sh_quote(&spec_path.display().to_string())
    ));
    let script_path = jobs_dir.join(format!("{}.sh", p.key));
    crate::write_atomic(&script_path, script.as_bytes()).map_err(io(&script_path))?;

    let cwd = std::env::current_dir().map_err(|e| RunError::Job(format!("current folder: {e}")))?;
    let mut cmd = Command::new("sbatch");
    cmd.arg("--parsable")
        .arg(format!("--job-name=hc-{}", p.stage))
        .arg(format!(
            "--output={}",
            logs_dir.join(format!("{}-%j.log", p.stage)).display()
        ))
        .arg(format!("--chdir={}", cwd.display()))
        .args(p.resources.sbatch_args());
    if !after.is_empty() {
        cmd.arg(format!("--dependency=afterok:{}", after.join(":")))
            .arg("--kill-on-invalid-dep=yes");
    }
    cmd.args(&profile.sbatch_args).arg(&script_path);
    let out = cmd.output().map_err(|e| {
        RunError::Job(format!(
            "cannot run `sbatch` ({e}); the Slurm executor needs Slurm's client commands \
             (sbatch, squeue, scancel) on PATH"
        ))
    })?;
    if !out.status.success() {
        return Err(RunError::Job(format!(
            "sbatch refused the job of stage `{}` ({}): {}",
            p.stage,
            out.status,
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    // `--parsable`: "ID" or "ID;CLUSTER".
    let text = String::from_utf8_lossy(&out.stdout);
    let id = text.trim().split(';').next().unwrap_or_default().to_owned();
    if id.is_empty() || !id.chars().all(|c| c.is_ascii_digit()) {
        return Err(RunError::Job(format!(
            "sbatch answered `{}` for stage `{}`, not a job id",
            text.trim(),
            p.stage
        )));
    }
    let log = logs_dir.join(format!("{}-{id}.log", p.stage));
    Ok((id, log))
}

/// States after which a job does nothing more (`squeue(1)`, JOB STATE
/// CODES); anything else may still run or write.
fn is_final(state: &str) -> bool {
    matches!(
        state,
        "COMPLETED"
            | "FAILED"
            | "CANCELLED"
            | "TIMEOUT"
            | "NODE_FAIL"
            | "PREEMPTED"
            | "BOOT_FAIL"
            | "DEADLINE"
            | "OUT_OF_MEMORY"
            | "REVOKED"
            | "SPECIAL_EXIT"
    )
}

/// Pending reasons (`squeue(1)`, JOB REASON CODES) under which a job
/// does not start until someone changes the request or the cluster.
fn never_starts(reason: &str) -> bool {
    reason.starts_with("Partition")
        || reason.starts_with("Assoc")
        || reason.starts_with("QOS")
        || matches!(
            reason,
            "BadConstraints" | "InvalidAccount" | "InvalidQOS" | "ReqNodeNotAvail" | "NodeDown"
        )
}

/// Job id → (state, reason) for the jobs Slurm still knows of (finished
/// jobs stay known for `MinJobAge`, 300 s by default).
pub fn squeue(ids: &[String]) -> Result<HashMap<String, (String, String)>, RunError> {
    let mut states = HashMap::new();
    for chunk in ids.chunks(200) {
        let out = Command::new("squeue")
            .args(["--noheader", "--states=all", "--format=%i|%T|%r"])
            .arg(format!("--jobs={}", chunk.join(",")))
            .output()
            .map_err(|e| RunError::Job(format!("cannot run `squeue`: {e}")))?;
        let text = String::from_utf8_lossy(&out.stdout);
        if !out.status.success() {
            let err = String::from_utf8_lossy(&out.stderr);
            // Every id of the chunk is gone from the controller's memory.
            if err.contains("Invalid job id") {
                continue;
            }
            return Err(RunError::Job(format!("squeue failed: {}", err.trim())));
        }
        for line in text.lines() {
            let mut parts = line.trim().splitn(3, '|');
            if let (Some(id), Some(state), reason) = (parts.next(), parts.next(), parts.next()) {
                states.insert(
                    id.to_owned(),
                    (state.to_owned(), reason.unwrap_or_default().to_owned()),
                );
            }
        }
    }
    Ok(states)
}

/// Cancels jobs; ids Slurm no longer knows are ignored.
pub fn scancel(ids: &[String]) -> Result<(), RunError> {
    let ids: Vec<&String> = ids.iter().filter(|i| !i.is_empty()).collect();
    if ids.is_empty() {
        return Ok(());
    }
    let out = Command::new("scancel")
        .args(&ids)
        .output()
        .map_err(|e| RunError::Job(format!("cannot run `scancel`: {e}")))?;
    if out.status.success() {
        Ok(())
    } else {
        Err(RunError::Job(format!(
            "scancel failed: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        )))
    }
}

/// Where a job stands, as `status` prints it.
#[derive(Clone, Debug, PartialEq)]
pub struct JobStatus {
    pub job: SubmittedJob,
    /// Slurm's state, or `gone` once it has forgotten the job.
    pub state: String,
    pub reason: String,
    /// The entry is in the cache, whole.
    pub entry: bool,
}

impl JobStatus {
    /// Queued or running: Slurm may still start or finish it.
    pub fn queued(&self) -> bool {
        self.state != "gone" && !is_final(&self.state)
    }
}

/// The state of every job of a submission.
pub fn status(submission: &Submission) -> Result<Vec<JobStatus>, RunError> {
    let cache = open_cache(&submission.cache)?;
    let states = squeue(&job_ids(&submission.jobs))?;
    Ok(submission
        .jobs
        .iter()
        .map(|job| {
            let (state, reason) = states
                .get(&job.job_id)
                .cloned()
                .unwrap_or_else(|| ("gone".into(), String::new()));
            JobStatus {
                entry: matches!(cache.check(&job.key), EntryState::Valid(_)),
                job: job.clone(),
                state,
                reason,
            }
        })
        .collect())
}

/// Job id → (state, reason), as [`squeue`] answers.
type States = HashMap<String, (String, String)>;

/// How the finished jobs of a submission ended, as [`wait`] gathers it.
#[derive(Default)]
struct Outcome<'a> {
    /// A line (and the log's last lines) per job that made no entry.
    failed: Vec<String>,
    /// Stages whose jobs left the queue because a job they wait for failed.
    skipped: Vec<&'a str>,
}

/// Waits until every job of the submission has finished, with a progress
/// bar unless `quiet`; `cancel` (set by Ctrl-C) cancels the jobs still
/// queued or running. Fails naming each failed stage, its job and its log.
pub fn wait(submission: &Submission, run: &SlurmRun, cancel: &AtomicBool) -> Result<(), RunError> {
    let cache = open_cache(&submission.cache)?;
    let bar = jobs_bar(run.quiet, submission.jobs.len());
    let mut open: Vec<&SubmittedJob> = submission.jobs.iter().collect();
    let mut outcome = Outcome::default();
    let mut squeue_errors = 0;
    let mut warned: HashSet<String> = HashSet::new();
    let poll = run.poll();
    while !open.is_empty() {
        if cancel.load(Ordering::SeqCst) {
            bar.finish_and_clear();
            return Err(cancel_jobs(&open));
        }
        let states = match squeue(&job_ids(open.iter().copied())) {
            Ok(s) => {
                squeue_errors = 0;
                s
            }
            // A controller briefly busy or restarting: look again, but not
            // for ever.
            Err(e) if squeue_errors < 60 => {
                squeue_errors += 1;
                bar.set_message(format!("({e}; retrying)"));
                sleep_unless(cancel, poll);
                continue;
            }
            Err(e) => return Err(e),
        };
        warn_never_starting(&open, &states, &mut warned, &bar);
        open = settle_finished(open, &states, &cache, &bar, &mut outcome);
        bar.set_message(queue_message(&open, &states));
        if !open.is_empty() {
            sleep_unless(cancel, poll);
        }
    }
    bar.finish_and_clear();
    outcome.into_result()
}

/// The bar of the jobs done (hidden when quiet).
fn jobs_bar(quiet: bool, jobs: usize) -> ProgressBar {
    if quiet {
        return ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden());
    }
    let bar = ProgressBar::new(jobs as u64);
    bar.set_style(
        ProgressStyle::with_template("{prefix:>14.bold} [{bar:30}] {pos}/{len} {msg}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_prefix("slurm jobs");
    bar
}

/// Cancels the jobs still open; the error that says so.
fn cancel_jobs(open: &[&SubmittedJob]) -> RunError {
    let ids = job_ids(open.iter().copied());
    if let Err(e) = scancel(&ids) {
        return e;
    }
    RunError::Job(format!(
        "cancelled: scancel sent to {} jobs ({}); entries already computed stay in the cache, a \
         rerun submits the rest",
        ids.len(),
        ids.join(" ")
    ))
}

/// A job the cluster will not start as asked: say so once (the user may
/// lower its `slurm:` resources or the site's limits).
fn warn_never_starting(
    open: &[&SubmittedJob],
    states: &States,
    warned: &mut HashSet<String>,
    bar: &ProgressBar,
) {
    for job in open {
        if let Some((state, reason)) = states.get(&job.job_id)
            && state == "PENDING"
            && never_starts(reason)
            && warned.insert(job.job_id.clone())
        {
            bar.suspend(|| {
                eprintln!(
                    "warning: stage `{}` (Slurm job {}) waits: {reason}; it asks {} CPUs, {} MiB, \
                     {} min (lower them with `slurm:` in the pipeline or `limits:` in the site \
                     profile, or Ctrl-C)",
                    job.stage, job.job_id, job.cpus, job.mem_mb, job.time_min
                )
            });
        }
    }
}

/// Judges each job that has left the queue (or reached a final state) by
/// its entry; returns the jobs still open.
fn settle_finished<'a>(
    open: Vec<&'a SubmittedJob>,
    states: &States,
    cache: &Cache,
    bar: &ProgressBar,
    outcome: &mut Outcome<'a>,
) -> Vec<&'a SubmittedJob> {
    let mut still = Vec::new();
    for job in open {
        let (state, reason) = states
            .get(&job.job_id)
            .map(|(s, r)| (s.as_str(), r.as_str()))
            .unwrap_or(("gone", ""));
        if state != "gone" && !is_final(state) {
            still.push(job);
            continue;
        }
        bar.inc(1);
        if matches!(cache.check(&job.key), EntryState::Valid(_)) {
            continue;
        }
        if reason == "DependencyNeverSatisfied" {
            outcome.skipped.push(&job.stage);
            continue;
        }
        outcome.failed.push(failure(job, state));
    }
    still
}

/// "running a b · 3 queued", or "3 queued" while none runs.
fn queue_message(open: &[&SubmittedJob], states: &States) -> String {
    let running: Vec<&str> = open
        .iter()
        .filter(|j| states.get(&j.job_id).is_some_and(|(s, _)| s == "RUNNING"))
        .map(|j| j.stage.as_str())
        .collect();
    match running.len() {
        0 => format!("{} queued", open.len()),
        _ => format!(
            "running {} · {} queued",
            running.join(" "),
            open.len() - running.len()
        ),
    }
}

impl Outcome<'_> {
    /// Ok when no job failed; else one error naming every failure.
    fn into_result(self) -> Result<(), RunError> {
        if self.failed.is_empty() {
            return Ok(());
        }
        let mut message = self.failed.join("\n");
        if !self.skipped.is_empty() {
            message.push_str(&format!(
                "\nnot run, as a stage they read failed: {}",
                self.skipped.join(", ")
            ));
        }
        message.push_str(
            "\nentries that were computed stay in the cache; fix the cause and rerun: only what \
             is missing is submitted",
        );
        Err(RunError::Job(message))
    }
}

/// "stage `x` (kind) failed in Slurm job N (STATE); log: PATH" and the
/// last lines of the log, where the stage's error is.
fn failure(job: &SubmittedJob, state: &str) -> String {
    let mut text = format!(
        "stage `{}` ({}) failed in Slurm job {} ({}); log: {}",
        job.stage,
        job.kind,
        job.job_id,
        match state {
            "gone" => "no longer in the queue, and no entry",
            s => s,
        },
        job.log.display()
    );
    match std::fs::read_to_string(&job.log) {
        Ok(log) => {
            let lines: Vec<&str> = log.lines().filter(|l| !l.trim().is_empty()).collect();
            for line in &lines[lines.len().saturating_sub(3)..] {
                text.push_str(&format!("\n    | {line}"));
            }
        }
        Err(_) => text.push_str(" (not written: the job never started)"),
    }
    text
}

/// Sleeps `total`, waking early when `cancel` is set.
fn sleep_unless(cancel: &AtomicBool, total: Duration) {
    let until = Instant::now() + total;
    while Instant::now() < until && !cancel.load(Ordering::SeqCst) {
        std::thread::sleep(Duration::from_millis(50).min(total));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quoting_survives_quotes_and_spaces() {
        assert_eq!(sh_quote("/a b/c"), "'/a b/c'");
        assert_eq!(sh_quote("it's"), r"'it'\''s'");
    }

    #[test]
    fn final_states() {
        for s in [
            "COMPLETED",
            "FAILED",
            "CANCELLED",
            "TIMEOUT",
            "OUT_OF_MEMORY",
        ] {
            assert!(is_final(s), "{s}");
        }
        for s in [
            "PENDING",
            "RUNNING",
            "COMPLETING",
            "CONFIGURING",
            "SUSPENDED",
        ] {
            assert!(!is_final(s), "{s}");
        }
    }
}
