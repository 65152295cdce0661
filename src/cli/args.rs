//! The command line as clap reads it: every subcommand with its options.
//! The doc comments here are the `--help` text.

use std::path::PathBuf;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "hypercontact",
    // The build (version and source hash, see build.rs), as cache entries
    // record it.
    version = env!("HYPERCONTACT_BUILD"),
    about = "Reruns a rough-surface contact study of hyperelastic rubber end to end",
    long_about = "Reruns a rough-surface contact study of hyperelastic rubber end to end: \
                  tensile tests → hyperelastic fit, interferometer tiles → height map → PSD → \
                  truncation → incremental contact model → report, as a cached YAML pipeline."
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(clap::Args, Clone)]
pub struct RunArgs {
    /// The pipeline file (YAML).
    pub pipeline: PathBuf,
    /// Output folder [default: runs/<pipeline name>/ for `run`,
    /// runs/<pipeline name>/study/ for `study`].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Cache folder [default: .hypercontact/cache next to the pipeline file].
    #[arg(long)]
    pub cache: Option<PathBuf>,
    /// Override a parameter: STAGE.PARAM=VALUE (VALUE is YAML). Repeatable.
    #[arg(long = "set", value_name = "STAGE.PARAM=VALUE")]
    pub set: Vec<String>,
    /// Print what would run and why, then stop.
    #[arg(long)]
    pub dry_run: bool,
    /// No progress bars and no summary.
    #[arg(long, short)]
    pub quiet: bool,
    /// Keep going after a stage fails or cannot read its input file (the
    /// default, as Slurm jobs do; errors in the pipeline itself stop the
    /// plan): every stage that does not depend on a failed one still runs and is
    /// cached and exported; then the summary, each failure with its cause,
    /// the stages not run because of it, and a non-zero exit code.
    #[arg(long, conflicts_with = "fail_fast")]
    pub keep_going: bool,
    /// Stop at the first stage that fails (with the local executor; Slurm
    /// jobs are scheduled at once and always keep going).
    #[arg(long)]
    pub fail_fast: bool,
    /// Where stages run: here, or as Slurm batch jobs on a cluster sharing
    /// the cache folder (see README, "Running on a Slurm cluster").
    #[arg(long, value_enum, default_value_t = Executor::Local)]
    pub executor: Executor,
    /// With `--executor slurm`: submit, print the job ids and return;
    /// `hypercontact status` follows them, the same command again collects
    /// the outputs once they are done.
    #[arg(long)]
    pub detach: bool,
    /// The site's Slurm profile (partition, account, module loads)
    /// [default: $HYPERCONTACT_SLURM_PROFILE, else
    /// ~/.config/hypercontact/slurm.yaml if present].
    #[arg(long, value_name = "FILE")]
    pub slurm_profile: Option<PathBuf>,
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Executor {
    /// Every stage in this process.
    Local,
    /// Every stage a Slurm job (`sbatch`), chained by dependencies.
    Slurm,
}

/// `hypercontact graph`'s arguments.
#[derive(clap::Args, Clone)]
pub struct GraphArgs {
    /// The pipeline file (YAML).
    pub pipeline: PathBuf,
    /// Mermaid (`flowchart LR`) or Graphviz (`dot -Tsvg`).
    #[arg(long, value_enum, default_value_t = GraphFormatArg::Mermaid)]
    pub format: GraphFormatArg,
    /// Output folder whose last run explains why a stage is stale
    /// [default: runs/<pipeline name>/].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Cache folder [default: .hypercontact/cache next to the pipeline file].
    #[arg(long)]
    pub cache: Option<PathBuf>,
    /// Override a parameter: STAGE.PARAM=VALUE (VALUE is YAML). Repeatable.
    #[arg(long = "set", value_name = "STAGE.PARAM=VALUE")]
    pub set: Vec<String>,
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum GraphFormatArg {
    Mermaid,
    Dot,
}

/// `hypercontact export`'s arguments.
#[derive(clap::Args, Clone)]
pub struct ExportArgs {
    /// A finished run's output folder [e.g. runs/paper].
    pub run_dir: PathBuf,
    /// `vtk`: every field (.npy with its grid, and the .npy maps a files
    /// index lists with their spacing) as VTK ImageData (.vti, raw
    /// little-endian float64, NaN kept), the array named `QUANTITY [UNIT]`.
    /// `csv`: every Parquet table as CSV, a first line of column names and a
    /// second of units: the unit the stage declares for the column, else
    /// the one its name's suffix gives (`_m` m, `_um` µm, `_pa` Pa, `_mpa`
    /// MPa, `_n` N, `_s` s, `_hz` Hz, `_deg` deg, `_rad` rad, `_px` px,
    /// `_mb` MB; none: empty).
    #[arg(long, value_enum)]
    pub format: ExportFormat,
    /// Where to write [default: RUN_DIR/export-vtk or RUN_DIR/export-csv],
    /// one folder per stage; not inside a cache, nor the run folder itself
    /// or a stage's folder in it.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ExportFormat {
    Vtk,
    Csv,
}

#[derive(Subcommand)]
pub enum Command {
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
        /// After the run, where its time went: every stage longest first,
        /// the totals per kind, the run's wall time and peak memory (as
        /// `hypercontact timings` prints them).
        #[arg(long)]
        timings: bool,
    },
    /// Where a finished run's time went, from its provenance.json: every
    /// stage longest first, totals per kind, wall time and peak memory.
    Timings {
        /// The run's output folder [e.g. runs/paper].
        run_dir: PathBuf,
    },
    /// Run the pipeline's `study:` sweep and gather the chosen tables.
    Study {
        #[command(flatten)]
        args: RunArgs,
    },
    /// The pipeline as a graph on stdout (Mermaid or Graphviz dot): stages
    /// with their kind, edges labelled `output → input`, and each stage
    /// marked cached, stale (would run, and why) or temporary (not needed),
    /// as `run --dry-run` plans it against the cache.
    Graph {
        #[command(flatten)]
        args: GraphArgs,
    },
    /// Export a finished run's fields to VTK (.vti, for ParaView) or its
    /// tables to CSV with a units line.
    Export {
        #[command(flatten)]
        args: ExportArgs,
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
        /// Output folder of the run or study [default: runs/<pipeline
        /// name>/, or runs/<pipeline name>/study/ where only a study was
        /// submitted].
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
pub struct CacheWhere {
    /// A pipeline whose cache to use (its .hypercontact/cache).
    #[arg(long, conflicts_with = "cache")]
    pub pipeline: Option<PathBuf>,
    /// The cache folder [default: pipelines/.hypercontact/cache].
    #[arg(long)]
    pub cache: Option<PathBuf>,
}

#[derive(Subcommand)]
pub enum CacheAction {
    /// List entries: key, kind, stage, size, the build that made it, last use.
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
        // A negative number reaches parse_days, which names the range,
        // rather than clap's "unexpected argument '-3'" (#31, 15).
        #[arg(long, value_parser = parse_days, allow_negative_numbers = true)]
        older_than_days: Option<f64>,
    },
    /// Hash every file of every entry against its manifest; list corrupt
    /// entries (exit 1 if any; `gc` removes unreadable ones, a run
    /// recomputes the others).
    Verify {
        #[command(flatten)]
        at: CacheWhere,
        /// Instead, list the entries another build of hypercontact made
        /// (or one too old to say), without hashing anything; exit 0.
        #[arg(long)]
        producer: bool,
    },
    /// Remove the whole cache.
    Clean {
        #[command(flatten)]
        at: CacheWhere,
    },
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

#[cfg(test)]
mod tests {
    use std::time::Duration;

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
}
