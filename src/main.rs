//! The `hypercontact` command line.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, SystemTime};

use anyhow::{Context as _, Result, bail};
use clap::{Parser, Subcommand};
use hypercontact_runner::cache::{Cache, EntryState};
use hypercontact_runner::exec::default_cache_dir;
use hypercontact_runner::slurm::{JobSpec, PipelineRun, SiteProfile, SlurmRun, Submission};
use hypercontact_runner::{Pipeline, PlanOptions, RunOptions};

mod stages;

/// `println!` for what a command reports on stdout, which ends the program
/// quietly once stdout is a closed pipe (`… | head`), as a tool that
/// SIGPIPE stops does, instead of panicking (Rust ignores SIGPIPE, so
/// `println!` panics there).
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout().lock(), $($arg)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
            eprintln!("error: writing to stdout: {e}");
            std::process::exit(1);
        }
    }};
}

#[derive(Parser)]
#[command(
    name = "hypercontact",
    version,
    about = "Reruns a rough-surface contact study of hyperelastic rubber end to end",
    long_about = "Reruns a rough-surface contact study of hyperelastic rubber end to end: \
                  tensile tests → hyperelastic fit, interferometer tiles → height map → PSD → \
                  truncation → incremental contact model → report, as a cached YAML pipeline."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Args, Clone)]
struct RunArgs {
    /// The pipeline file (YAML).
    pipeline: PathBuf,
    /// Output folder [default: runs/<pipeline name>/].
    #[arg(long)]
    out: Option<PathBuf>,
    /// Cache folder [default: .hypercontact/cache next to the pipeline file].
    #[arg(long)]
    cache: Option<PathBuf>,
    /// Override a parameter: STAGE.PARAM=VALUE (VALUE is YAML). Repeatable.
    #[arg(long = "set", value_name = "STAGE.PARAM=VALUE")]
    set: Vec<String>,
    /// Print what would run and why, then stop.
    #[arg(long)]
    dry_run: bool,
    /// No progress bars and no summary.
    #[arg(long, short)]
    quiet: bool,
    /// Where stages run: here, or as Slurm batch jobs on a cluster sharing
    /// the cache folder (see README, "Running on a Slurm cluster").
    #[arg(long, value_enum, default_value_t = Executor::Local)]
    executor: Executor,
    /// With `--executor slurm`: submit, print the job ids and return;
    /// `hypercontact status` follows them, the same command again collects
    /// the outputs once they are done.
    #[arg(long)]
    detach: bool,
    /// The site's Slurm profile (partition, account, module loads)
    /// [default: $HYPERCONTACT_SLURM_PROFILE, else
    /// ~/.config/hypercontact/slurm.yaml if present].
    #[arg(long, value_name = "FILE")]
    slurm_profile: Option<PathBuf>,
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Executor {
    /// Every stage in this process.
    Local,
    /// Every stage a Slurm job (`sbatch`), chained by dependencies.
    Slurm,
}

#[derive(Subcommand)]
enum Command {
    /// Run a pipeline, reusing every cached stage whose inputs are unchanged.
    Run {
        #[command(flatten)]
        args: RunArgs,
        /// Recompute this stage even if cached. Repeatable.
        #[arg(long, value_name = "STAGE")]
        force: Vec<String>,
        /// Run only this stage and the stages it needs.
        #[arg(long, value_name = "STAGE")]
        only: Option<String>,
    },
    /// Run the pipeline's `study:` sweep and gather the chosen tables.
    Study {
        #[command(flatten)]
        args: RunArgs,
    },
    /// Describe the stage kinds: parameters (defaults, units), inputs, outputs.
    Stages {
        /// Only this kind, with its full documentation.
        kind: Option<String>,
        /// Machine-readable output.
        #[arg(long)]
        json: bool,
    },
    /// The Slurm jobs of a pipeline's last submission (`--executor slurm`):
    /// state, entry, log.
    Status {
        /// The pipeline file (YAML).
        pipeline: PathBuf,
        /// Output folder of the run or study [default: runs/<pipeline name>/].
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Compute one stage of a submitted plan into the cache: what each
    /// Slurm job runs (`<out>/slurm/jobs/<key>.json`).
    ExecStage {
        /// The job file written at submission.
        job: PathBuf,
    },
    /// Inspect or prune the cache.
    Cache {
        #[command(subcommand)]
        action: CacheAction,
    },
}

#[derive(clap::Args)]
struct CacheWhere {
    /// A pipeline whose cache to use (its .hypercontact/cache).
    #[arg(long, conflicts_with = "cache")]
    pipeline: Option<PathBuf>,
    /// The cache folder [default: pipelines/.hypercontact/cache].
    #[arg(long)]
    cache: Option<PathBuf>,
}

#[derive(Subcommand)]
enum CacheAction {
    /// List entries: key, kind, stage, size, last use.
    Ls {
        #[command(flatten)]
        at: CacheWhere,
    },
    /// Remove entries no longer needed, and debris of interrupted runs.
    Gc {
        #[command(flatten)]
        at: CacheWhere,
        /// Keep every entry these pipelines use now; remove the rest.
        #[arg(long, value_name = "PIPELINE")]
        keep: Vec<PathBuf>,
        /// Remove entries unused for this many days (default 30 without --keep).
        #[arg(long, value_parser = parse_days)]
        older_than_days: Option<f64>,
    },
    /// Hash every file of every entry against its manifest; list corrupt
    /// entries (exit 1 if any; `gc` removes unreadable ones, a run
    /// recomputes the others).
    Verify {
        #[command(flatten)]
        at: CacheWhere,
    },
    /// Remove the whole cache.
    Clean {
        #[command(flatten)]
        at: CacheWhere,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match dispatch(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", error_text(&e));
            ExitCode::FAILURE
        }
    }
}

/// The error and its causes on one line, each said once: a cause whose
/// text the line already holds (a wrapper that quotes its source and also
/// returns it as `source()`) is left out, so no message prints twice.
fn error_text(e: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in e.chain() {
        let said = cause.to_string();
        if text.contains(&said) {
            continue;
        }
        if !text.is_empty() {
            text.push_str(": ");
        }
        text.push_str(&said);
    }
    text
}

fn dispatch(cli: Cli) -> Result<()> {
    let registry = hypercontact::registry();
    match cli.command {
        Command::Run { args, force, only } => {
            let started = std::time::Instant::now();
            let (pipeline, mut options) = prepare(&args, &registry)?;
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
                let Some(remote) = on_slurm(&args, &options, &runs)? else {
                    return Ok(());
                };
                // The jobs computed every entry: what follows exports them.
                options.plan.force.clear();
                options.remote = remote;
            }
            let report = hypercontact_runner::run(&pipeline, &options)?;
            if args.dry_run {
                say_text(report.plan.describe());
            } else if !args.quiet {
                say_text(report.summary());
                let temps = match report.temps_not_needed() {
                    0 => String::new(),
                    n => format!(", {n} temporary not needed"),
                };
                say!(
                    "{} ran, {} cached{temps} in {:.2} s; outputs in {}",
                    report.computed(),
                    report.hits(),
                    // On Slurm, the whole wait, not only the export.
                    started
                        .elapsed()
                        .as_secs_f64()
                        .max(report.provenance.wall_s),
                    options.out_dir.display()
                );
            }
        }
        Command::Study { args } => {
            let (pipeline, mut options) = prepare(&args, &registry)?;
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
                let Some(remote) = on_slurm(&args, &options, &runs)? else {
                    return Ok(());
                };
                options.remote = remote;
            }
            let report = hypercontact_runner::study::run_study(&pipeline, &options)?;
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
            if !args.quiet {
                for (target, path) in &report.tables {
                    say!("{target} → {}", path.display());
                }
            }
        }
        Command::Stages { kind, json } => stages::print(&registry, kind.as_deref(), json)?,
        Command::Status { pipeline, out } => {
            let pipeline = Pipeline::load(&pipeline, &registry)?;
            let out = out.unwrap_or_else(|| RunOptions::for_pipeline(&pipeline).out_dir);
            slurm_status(&out.join("slurm"))?;
        }
        Command::ExecStage { job } => exec_stage(&job, &registry)?,
        Command::Cache { action } => cache_command(action, &registry)?,
    }
    Ok(())
}

fn prepare(
    args: &RunArgs,
    registry: &hypercontact_core::Registry,
) -> Result<(Pipeline, RunOptions)> {
    if args.detach && args.executor != Executor::Slurm {
        bail!("--detach returns while Slurm jobs run: give it with `--executor slurm`");
    }
    let mut pipeline = Pipeline::load(&args.pipeline, registry)?;
    for assignment in &args.set {
        pipeline.set(assignment)?;
    }
    let mut options = RunOptions::for_pipeline(&pipeline);
    if let Some(out) = &args.out {
        options.out_dir = out.clone();
    }
    if let Some(cache) = &args.cache {
        options.cache_dir = cache.clone();
    }
    options.dry_run = args.dry_run;
    options.quiet = args.quiet;
    options.overrides = args.set.clone();
    Ok((pipeline, options))
}

/// A block of lines for stdout, as [`say!`] writes them (nothing for an
/// empty block).
fn say_text(text: String) {
    if !text.is_empty() {
        say!("{}", text.trim_end_matches('\n'));
    }
}

/// Set by Ctrl-C (or SIGTERM) while waiting on Slurm.
static CANCEL: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Submits the plans to Slurm and waits for their jobs. `None` when there
/// is nothing more to do here (a dry run, `--detach`); else the entries the
/// jobs computed (key → job), for the export that follows.
fn on_slurm(
    args: &RunArgs,
    options: &RunOptions,
    runs: &[PipelineRun],
) -> Result<Option<std::collections::BTreeMap<String, String>>> {
    let slurm = SlurmRun {
        cache_dir: options.cache_dir.clone(),
        log_dir: options.out_dir.join("slurm"),
        profile: SiteProfile::find(args.slurm_profile.as_deref())?,
        dry_run: args.dry_run,
        quiet: args.quiet,
    };
    if !args.dry_run && !args.detach {
        // Before submitting: a Ctrl-C from the first job on cancels them all.
        ctrlc::set_handler(|| CANCEL.store(true, std::sync::atomic::Ordering::SeqCst))
            .context("installing the Ctrl-C handler")?;
    }
    let submission = hypercontact_runner::slurm::submit(runs, &slurm)?;
    if args.dry_run {
        say!("would submit {} Slurm jobs:", submission.jobs.len());
        for j in &submission.jobs {
            say!(
                "  {:<20} {:<20} cpus {}, mem {} MiB, time {} min, entry {}",
                j.stage,
                j.kind,
                j.cpus,
                j.mem_mb,
                j.time_min,
                &j.key[..12]
            );
        }
        return Ok(None);
    }
    if args.detach {
        if !args.quiet {
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
    if CANCEL.load(std::sync::atomic::Ordering::SeqCst) {
        bail!("cancelled after the jobs finished: their entries are in the cache, not exported");
    }
    Ok(Some(submission.remote()))
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

/// One Slurm job: rebuild the pipeline as submitted, compute the stage.
fn exec_stage(job_file: &Path, registry: &hypercontact_core::Registry) -> Result<()> {
    let spec = JobSpec::read(job_file)?;
    let mut pipeline = Pipeline::load(&spec.pipeline, registry)?;
    for assignment in &spec.sets {
        pipeline.set(assignment)?;
    }
    for (path, value) in &spec.values {
        pipeline.set_value(
            path,
            value.clone(),
            &format!("study value {path} = {value}"),
        )?;
    }
    let short = &spec.job.key[..spec.job.key.len().min(12)];
    say!(
        "stage `{}` of {}, entry {short}, cache {}",
        spec.job.stage,
        spec.pipeline.display(),
        spec.cache.display()
    );
    match hypercontact_runner::exec::exec_stage(&pipeline, &spec.cache, &spec.job)? {
        hypercontact_runner::exec::JobOutcome::Computed { compute_s } => say!(
            "computed stage `{}` (entry {short}) in {compute_s:.2} s",
            spec.job.stage
        ),
        hypercontact_runner::exec::JobOutcome::AlreadyCached => say!(
            "stage `{}`: entry {short} was already in the cache; nothing to do",
            spec.job.stage
        ),
    }
    Ok(())
}

fn cache_dir(at: &CacheWhere, registry: &hypercontact_core::Registry) -> Result<PathBuf> {
    Ok(match (&at.cache, &at.pipeline) {
        (Some(dir), _) => dir.clone(),
        (None, Some(p)) => default_cache_dir(&Pipeline::load(p, registry)?),
        (None, None) => Path::new("pipelines").join(".hypercontact").join("cache"),
    })
}

fn cache_command(action: CacheAction, registry: &hypercontact_core::Registry) -> Result<()> {
    match action {
        CacheAction::Ls { at } => {
            let dir = cache_dir(&at, registry)?;
            let Some(cache) =
                Cache::open_existing(&dir).with_context(|| format!("opening {}", dir.display()))?
            else {
                say!("no cache at {}", dir.display());
                return Ok(());
            };
            let entries = cache.list()?;
            let mut total = 0;
            for e in &entries {
                total += e.bytes;
                let (kind, stage) = e.manifest.as_ref().map_or(("(unreadable)", ""), |m| {
                    (m.kind.as_str(), m.stage.as_str())
                });
                say!(
                    "{}  {:<16} {:<16} {:>10}  {}",
                    &e.key,
                    kind,
                    stage,
                    human_bytes(e.bytes),
                    e.last_used.map_or("-".into(), ago)
                );
            }
            say!(
                "{} entries, {} in {}",
                entries.len(),
                human_bytes(total),
                dir.display()
            );
        }
        CacheAction::Gc {
            at,
            keep,
            older_than_days,
        } => {
            let dir = cache_dir(&at, registry)?;
            let Some(cache) = Cache::open_existing(&dir)? else {
                say!("no cache at {}: nothing to remove", dir.display());
                return Ok(());
            };
            let mut keys = std::collections::HashSet::new();
            for p in &keep {
                let pipeline = Pipeline::load(p, registry)?;
                let plan = hypercontact_runner::Plan::build(
                    &pipeline,
                    &cache,
                    &PlanOptions::default(),
                    None,
                )?;
                keys.extend(plan.stages.into_iter().map(|s| s.key));
            }
            let max_age = match (older_than_days, keep.is_empty()) {
                (Some(d), _) => Some(Duration::from_secs_f64(d * 86_400.0)),
                (None, true) => Some(Duration::from_secs(30 * 86_400)),
                (None, false) => None,
            };
            let mut removed = 0;
            let mut freed = 0;
            for e in cache.list()? {
                let unused = !keep.is_empty() && !keys.contains(&e.key);
                let old = match (max_age, e.last_used) {
                    (Some(age), Some(t)) => {
                        SystemTime::now().duration_since(t).unwrap_or_default() > age
                    }
                    _ => false,
                };
                if unused || old || e.manifest.is_none() {
                    cache.remove(&e.key)?;
                    removed += 1;
                    freed += e.bytes;
                }
            }
            let debris = cache.clean_debris()?;
            say!(
                "removed {removed} entries ({}) and {debris} leftovers of interrupted runs",
                human_bytes(freed)
            );
        }
        CacheAction::Verify { at } => {
            let dir = cache_dir(&at, registry)?;
            let Some(cache) = Cache::open_existing(&dir)? else {
                say!("no cache at {}", dir.display());
                return Ok(());
            };
            let entries = cache.list()?;
            let mut corrupt = 0;
            for e in &entries {
                match cache.verify(&e.key) {
                    EntryState::Valid(_) => {}
                    EntryState::Corrupt(why) => {
                        corrupt += 1;
                        say!("corrupt  {}  {why}", e.key);
                    }
                    // Removed by a concurrent `gc` or a dropped temporary.
                    EntryState::Missing => {}
                }
            }
            say!(
                "{} entries checked, {corrupt} corrupt, in {}",
                entries.len(),
                dir.display()
            );
            if corrupt > 0 {
                bail!("{corrupt} corrupt cache entries in {}", dir.display());
            }
        }
        CacheAction::Clean { at } => {
            let dir = cache_dir(&at, registry)?;
            if dir.exists() {
                Cache::open(&dir)?.clean()?;
            }
            say!("removed {}", dir.display());
        }
    }
    Ok(())
}

/// A number of days for `--older-than-days`: finite, 0 … 100 years.
fn parse_days(text: &str) -> Result<f64, String> {
    let days: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a number of days"))?;
    if (0.0..=36_525.0).contains(&days) {
        Ok(days)
    } else {
        Err(format!("{text} days: give a number from 0 to 36525"))
    }
}

fn human_bytes(n: u64) -> String {
    const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut v = n as f64;
    let mut u = 0;
    while v >= 1024.0 && u < UNITS.len() - 1 {
        v /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{n} B")
    } else {
        format!("{v:.1} {}", UNITS[u])
    }
}

fn ago(t: SystemTime) -> String {
    let s = SystemTime::now()
        .duration_since(t)
        .unwrap_or_default()
        .as_secs();
    match s {
        0..=119 => format!("{s} s ago"),
        120..=7199 => format!("{} min ago", s / 60),
        7200..=172_799 => format!("{} h ago", s / 3600),
        _ => format!("{} days ago", s / 86_400),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn days_are_finite_and_in_range() {
        // Issue 12: NaN, inf, -1 and 1e300 reached `Duration::from_secs_f64`
        // and panicked.
        for bad in ["NaN", "inf", "-inf", "-1", "1e300", "36526", "x", ""] {
            assert!(parse_days(bad).is_err(), "{bad}");
        }
        for (good, days) in [("0", 0.0), ("0.5", 0.5), ("30", 30.0), ("36525", 36525.0)] {
            assert_eq!(parse_days(good), Ok(days));
            let _ = Duration::from_secs_f64(days * 86_400.0);
        }
    }

    /// Issue 17: a stage error that quoted its cause and also chained it
    /// printed `X: msg: msg`; each text is said once, distinct causes kept.
    #[test]
    fn each_cause_is_said_once() {
        #[derive(Debug, thiserror::Error)]
        #[error("the load range: {0}")]
        struct Quoting(#[from] Inner);
        #[derive(Debug, thiserror::Error)]
        #[error("p_max is below p_min")]
        struct Inner;
        let e = anyhow::Error::from(Quoting(Inner)).context("stage `gw` failed");
        assert_eq!(
            error_text(&e),
            "stage `gw` failed: the load range: p_max is below p_min"
        );
        let e = anyhow::Error::from(Inner).context("stage `gw`");
        assert_eq!(error_text(&e), "stage `gw`: p_max is below p_min");
    }
}
