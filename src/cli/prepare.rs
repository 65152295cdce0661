//! From the command line to a checked pipeline and the options to run it
//! with: the part `run`, `study` and a Slurm job's `exec-stage` share.

use std::path::Path;

use anyhow::{Result, bail};
use hypercontact_core::Registry;
use hypercontact_runner::{Pipeline, RunOptions};

use super::args::{Executor, RunArgs};

/// The pipeline of `args` with its `--set` overrides, and the run options
/// its flags give (the output folder a run's: see [`prepare_study`]).
pub fn prepare(args: &RunArgs, registry: &Registry) -> Result<(Pipeline, RunOptions)> {
    if args.detach && args.executor != Executor::Slurm {
        bail!("--detach returns while Slurm jobs run: give it with `--executor slurm`");
    }
    if args.fail_fast && args.executor == Executor::Slurm {
        bail!(
            "--fail-fast stops a local run at its first failure; Slurm runs every job whose \
             inputs succeeded (drop --fail-fast, or run with `--executor local`)"
        );
    }
    let pipeline = load_with_sets(&args.pipeline, &args.set, registry)?;
    let mut options =
        RunOptions::for_pipeline_in(&pipeline, args.out.as_deref(), args.cache.as_deref());
    options.dry_run = args.dry_run;
    // `--keep-going` says the default aloud; clap refuses it with `--fail-fast`.
    options.keep_going = args.keep_going || !args.fail_fast;
    options.quiet = args.quiet;
    options.overrides = args.set.clone();
    Ok((pipeline, options))
}

/// A pipeline file with `STAGE.PARAM=VALUE` assignments applied in order.
pub fn load_with_sets(file: &Path, sets: &[String], registry: &Registry) -> Result<Pipeline> {
    Ok(Pipeline::load_with_sets(file, sets, registry)?)
}

/// [`prepare`] for a study: its folder is `runs/<name>/study/` unless
/// `--out` names one.
pub fn prepare_study(args: &RunArgs, registry: &Registry) -> Result<(Pipeline, RunOptions)> {
    let (pipeline, mut options) = prepare(args, registry)?;
    if args.out.is_none() {
        options.out_dir = hypercontact_runner::study::default_dir(&pipeline);
    }
    Ok((pipeline, options))
}
