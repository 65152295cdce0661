//! Pipelines and studies run from another language, with the CLI's own
//! path: the pipeline loaded and its `--set` assignments applied in order,
//! the default folders of `hypercontact run` (`runs/<name>/`, the cache
//! beside the pipeline file), the same runner and cache. Products are read
//! back from the run folder by the caller (the Python `load`), so a run and
//! a reload give the same thing.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use hypercontact_core::Registry;
use hypercontact_runner::{Pipeline, PlanOptions, RunOptions};

/// What to run, as `hypercontact run` takes it.
#[derive(Clone, Debug, Default)]
pub struct RunRequest {
    pub pipeline: PathBuf,
    /// `--out`; `runs/<name>/` under the current folder when absent.
    pub out: Option<PathBuf>,
    /// `--cache`; `.hypercontact/cache` beside the pipeline when absent.
    pub cache: Option<PathBuf>,
    /// `--set STAGE.PARAM=VALUE`, applied in order.
    pub sets: Vec<String>,
    /// `--force STAGE`.
    pub force: Vec<String>,
    /// `--only STAGE`.
    pub only: Option<String>,
    /// Progress bars and notes on stderr (indicatif hides the bars where
    /// stderr is not a terminal).
    pub progress: bool,
}

/// A finished run: where its products are and the CLI's summary lines.
#[derive(Clone, Debug)]
pub struct RunOutcome {
    pub out_dir: PathBuf,
    pub summary: String,
    pub computed: usize,
    pub cached: usize,
}

/// A finished study: its folder (`runs/<name>/study/` by default, with
/// `study.json` and the variants' folders) and the gathered tables,
/// `stage.output` → file.
#[derive(Clone, Debug)]
pub struct StudyOutcome {
    pub out_dir: PathBuf,
    pub tables: Vec<(String, PathBuf)>,
}

/// A failed run's message with every cause, as the CLI prints the chain.
fn chain(error: &dyn std::error::Error) -> String {
    hypercontact_runner::error::said_once(hypercontact_runner::error::chain(error))
}

fn prepare(registry: &Registry, request: &RunRequest) -> Result<(Pipeline, RunOptions), String> {
    let pipeline = Pipeline::load_with_sets(&request.pipeline, &request.sets, registry)
        .map_err(|e| chain(&e))?;
    let mut options =
        RunOptions::for_pipeline_in(&pipeline, request.out.as_deref(), request.cache.as_deref());
    options.quiet = !request.progress;
    options.overrides = request.sets.clone();
    Ok((pipeline, options))
}

/// Runs a pipeline as `hypercontact run` does; the error is the CLI's
/// message.
pub fn run_pipeline(
    registry: &Registry,
    request: &RunRequest,
    cancel: Option<Arc<AtomicBool>>,
) -> Result<RunOutcome, String> {
    let (pipeline, mut options) = prepare(registry, request)?;
    options.cancel = cancel;
    options.plan = PlanOptions {
        force: request.force.clone(),
        only: request.only.clone(),
        prune: false,
    };
    let report = hypercontact_runner::run(&pipeline, &options).map_err(|e| chain(&e))?;
    Ok(RunOutcome {
        out_dir: absolute(&options.out_dir),
        summary: report.summary(),
        computed: report.computed(),
        cached: report.hits(),
    })
}

/// Runs a pipeline's `study:` sweep as `hypercontact study` does.
pub fn run_study(
    registry: &Registry,
    request: &RunRequest,
    cancel: Option<Arc<AtomicBool>>,
) -> Result<StudyOutcome, String> {
    let (pipeline, mut options) = prepare(registry, request)?;
    options.cancel = cancel;
    if request.out.is_none() {
        options.out_dir = hypercontact_runner::study::default_dir(&pipeline);
    }
    let report =
        hypercontact_runner::study::run_study(&pipeline, &options).map_err(|e| chain(&e))?;
    Ok(StudyOutcome {
        out_dir: absolute(&report.dir),
        tables: report.tables,
    })
}

/// The folder as the caller will open it, wherever its working directory
/// moves afterwards.
fn absolute(path: &Path) -> PathBuf {
    std::path::absolute(path).unwrap_or_else(|_| path.to_owned())
}

/// A stage as declared: name, kind, parameters as given (JSON text).
pub type DeclaredStage = (String, String, String);

/// A pipeline's stages as declared, for replaying one outside the runner:
/// the pipeline's folder (where relative paths resolve) and, per stage, its
/// name, kind and parameters as given (`with_file:`, `with:`, `--set`).
pub fn pipeline_stages(
    registry: &Registry,
    file: &Path,
    sets: &[String],
) -> Result<(PathBuf, Vec<DeclaredStage>), String> {
    let request = RunRequest {
        pipeline: file.to_owned(),
        sets: sets.to_vec(),
        ..RunRequest::default()
    };
    let (pipeline, _) = prepare(registry, &request)?;
    let stages = pipeline
        .stages
        .iter()
        .map(|s| (s.name.clone(), s.kind.clone(), s.raw_params.to_string()))
        .collect();
    Ok((absolute(&pipeline.dir), stages))
}
