//! Running a plan: cache lookups, locked computation, atomic entries,
//! exported outputs and the provenance record.
//!
//! Caching, timing and progress wrap every stage from the outside; a stage
//! itself only computes.

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Weak};
use std::time::Instant;

use hypercontact_core::{Context, Inputs, Outputs, Product, ProductKind, ProgressSink};
use indicatif::MultiProgress;

use crate::cache::{Cache, EntryState, MANIFEST_FORMAT, Manifest, short_key, unix_now};
use crate::folders;
use crate::outcome::{Blocked, StageFailure, blocked_by};
use crate::pipeline::{Pipeline, PipelineError};
use crate::plan::{Plan, PlanOptions, PlannedStage, Reason, Unreadable};
use crate::progress::{RunBar, TerminalProgress};
use crate::provenance::{CacheUse, FailedRecord, PROVENANCE_FORMAT, Provenance, StageRecord};
use crate::store::{self, OutputRecord, StoreError};
use crate::timings::{History, RunHistory};

/// How to run.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Where outputs land: `<out>/<stage>/<output>.<ext>`.
    pub out_dir: PathBuf,
    pub cache_dir: PathBuf,
    pub plan: PlanOptions,
    /// Print the plan and stop.
    pub dry_run: bool,
    /// No progress bars or summary.
    pub quiet: bool,
    /// `--set` assignments already applied, recorded in provenance.
    pub overrides: Vec<String>,
    /// Export outputs into `out_dir` and write `provenance.json` there.
    pub export: bool,
    /// Keep the entries of temporary stages (a study drops them once every
    /// variant has run, so variants sharing a temporary entry reuse it).
    pub keep_temps: bool,
    /// Entries computed by cluster jobs of this run (key → job id), so
    /// provenance counts them as this run's work.
    pub remote: BTreeMap<String, String>,
    /// After a stage fails, run every stage that does not read it (the
    /// default, as the Slurm executor does), then fail listing every
    /// failure ([`RunError::Failed`]); false stops at the first failure.
    pub keep_going: bool,
    /// Entries that failed earlier in this invocation (a study's earlier
    /// variant), key → cause: not computed again, failed at once.
    pub known_failures: BTreeMap<String, String>,
    /// What the bars and notes of this run are prefixed with (a study's
    /// `variant 3/6`).
    pub label: Option<String>,
    /// Recorded stage times from earlier runs, for the ETAs (the previous
    /// record in `out_dir` is added to it).
    pub history: History,
    /// Set from outside (Python's Ctrl-C, which cannot end the process as
    /// a signal ends the CLI): no stage starts once it is true, and the run
    /// stops with [`RunError::Interrupted`]; the stage under way finishes
    /// and its entry is written whole, as every entry is.
    pub cancel: Option<Arc<AtomicBool>>,
}

impl RunOptions {
    /// Defaults for a pipeline: `runs/<name>/` and the cache next to the
    /// pipeline file.
    pub fn for_pipeline(pipeline: &Pipeline) -> Self {
        Self::in_folders(
            PathBuf::from("runs").join(&pipeline.name),
            default_cache_dir(pipeline),
        )
    }

    /// The pipeline's defaults where `--out` and `--cache` are not given.
    pub fn for_pipeline_in(
        pipeline: &Pipeline,
        out_dir: Option<&Path>,
        cache_dir: Option<&Path>,
    ) -> Self {
        let mut options = Self::for_pipeline(pipeline);
        if let Some(out) = out_dir {
            options.out_dir = out.to_owned();
        }
        if let Some(cache) = cache_dir {
            options.cache_dir = cache.to_owned();
        }
        options
    }

    /// Defaults with the outputs in `out_dir` and the cache in `cache_dir`.
    pub fn in_folders(out_dir: PathBuf, cache_dir: PathBuf) -> Self {
        Self {
            out_dir,
            cache_dir,
            plan: PlanOptions::default(),
            dry_run: false,
            quiet: true,
            overrides: Vec::new(),
            export: true,
            keep_temps: false,
            remote: BTreeMap::new(),
            keep_going: true,
            known_failures: BTreeMap::new(),
            label: None,
            history: History::default(),
            cancel: None,
        }
    }
}

/// `.hypercontact/cache` in the pipeline file's folder.
pub fn default_cache_dir(pipeline: &Pipeline) -> PathBuf {
    pipeline.dir.join(".hypercontact").join("cache")
}

#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Pipeline(#[from] PipelineError),
    // Causes are part of these messages, so they are not also `source()`:
    // the CLI prints the chain, which would repeat them.
    #[error("{file}: stage `{stage}` ({kind}) failed: {cause}", file = file.display())]
    Stage {
        file: PathBuf,
        stage: String,
        kind: String,
        cause: Box<hypercontact_core::StageError>,
    },
    #[error("stage `{stage}` ({kind}) broke its output contract: {message}")]
    Contract {
        stage: String,
        kind: String,
        message: String,
    },
    #[error("cache at {}: {cause}", path.display())]
    Cache {
        path: PathBuf,
        cause: std::io::Error,
    },
    #[error("stage `{stage}`: exporting its outputs: {cause}")]
    Export { stage: String, cause: StoreError },
    #[error("writing {}: {cause}", path.display())]
    Output {
        path: PathBuf,
        cause: std::io::Error,
    },
    #[error(transparent)]
    Store(#[from] StoreError),
    /// A cluster job cannot do what it was submitted for, or a cluster run
    /// failed (the message names the stage, job and log).
    #[error("{0}")]
    Job(String),
    /// The output folder and the cache overlap: exporting would write into
    /// cache entries, or cleaning the cache would take the outputs.
    #[error(
        "the output folder {} and the cache {} overlap ({}): give --out and --cache \
         folders apart from each other",
        out.display(),
        cache.display(),
        if crate::folders::is_within(out, cache) { "the outputs would sit inside the cache" } else { "the cache would sit inside the outputs" }
    )]
    Overlap { out: PathBuf, cache: PathBuf },
    /// The entry of a temporary stage this run planned to read was dropped
    /// by a concurrent run; [`run`] plans again and regenerates it.
    #[error("the entry of temporary stage `{stage}` was removed by another run")]
    TempGone { stage: String },
    /// A run that kept going past failed stages: every stage that did not
    /// read a failed one ran and was exported; the report says which failed
    /// (with their causes) and which were not run because of them.
    #[error("{}", .0.failure_text())]
    Failed(Box<RunReport>),
    /// A study whose variants kept going past failed stages: the tables of
    /// the variants that ran are gathered; the report says what failed.
    #[error("{}", .0.failure_text())]
    StudyFailed(Box<crate::study::StudyReport>),
    /// [`RunOptions::cancel`] was set: `stage` and the stages after it
    /// did not start; every stage finished before it is in the cache.
    #[error("interrupted before stage `{stage}`: the stages finished before it are in the cache")]
    Interrupted { stage: String },
}

/// What a run did.
#[derive(Debug)]
pub struct RunReport {
    pub plan: Plan,
    pub provenance: Provenance,
    /// Stages that failed in this run (kept going past them).
    pub failures: Vec<StageFailure>,
    /// Stages not run because a stage they read (directly or through
    /// others) failed.
    pub blocked: Vec<Blocked>,
}

impl RunReport {
    pub fn hits(&self) -> usize {
        self.count(CacheUse::Hit)
    }

    /// Temporary stages this run did not need (see [`Reason::TempNotNeeded`]).
    pub fn temps_not_needed(&self) -> usize {
        self.plan
            .stages
            .iter()
            .filter(|s| s.reason == Reason::TempNotNeeded)
            .count()
    }

    pub fn computed(&self) -> usize {
        self.count(CacheUse::Miss) + self.count(CacheUse::Forced)
    }

    fn count(&self, what: CacheUse) -> usize {
        self.provenance
            .stages
            .values()
            .filter(|s| s.cache == what)
            .count()
    }

    /// One line per stage: status, time, outputs.
    pub fn summary(&self) -> String {
        let mut out = String::new();
        for s in &self.plan.stages {
            if let Some(line) = self.not_run_line(&s.name, &s.kind) {
                out.push_str(&line);
                continue;
            }
            let Some(r) = self.provenance.stages.get(&s.name) else {
                continue;
            };
            let status = match r.cache {
                CacheUse::Hit => "cached",
                CacheUse::Miss => "ran",
                CacheUse::Forced => "forced",
                CacheUse::Skipped => "skipped",
            };
            let seconds = match r.cache {
                CacheUse::Hit => format!("{:>8.2} s", r.compute_s),
                // Not part of this run: its time is an earlier run's.
                CacheUse::Skipped => format!("{:>10}", "-"),
                // Computed by a cluster job: its own compute time.
                CacheUse::Miss if r.job.is_some() => format!("{:>8.2} s", r.compute_s),
                CacheUse::Miss | CacheUse::Forced => format!("{:>8.2} s", r.wall_s),
            };
            out.push_str(&format!(
                "{status:>8}  {:<16} {:<16} {seconds}  {}\n",
                s.name,
                s.kind,
                r.outputs.keys().cloned().collect::<Vec<_>>().join(" ")
            ));
        }
        out
    }
}

/// A report of the stages run so far (the dry run, the end of a run).
fn report(plan: Plan, provenance: Provenance) -> RunReport {
    RunReport {
        plan,
        provenance,
        failures: Vec::new(),
        blocked: Vec::new(),
    }
}

/// Test hook: called after each file written into a cache entry.
pub type AfterFile<'a> = &'a mut dyn FnMut(&Path);

/// Plans and runs a pipeline.
pub fn run(pipeline: &Pipeline, options: &RunOptions) -> Result<RunReport, RunError> {
    run_with_hook(pipeline, options, &mut |_| {})
}

/// [`run`] with a hook after every cache file written (crash tests).
///
/// A concurrent run may drop a temporary entry between this run's plan and
/// its read; then the run plans again (stages finished meanwhile are cache
/// hits) and regenerates the entry, a few times at most.
pub fn run_with_hook(
    pipeline: &Pipeline,
    options: &RunOptions,
    after_file: AfterFile,
) -> Result<RunReport, RunError> {
    const ATTEMPTS: usize = 4;
    let mut attempt = 1;
    loop {
        match run_once(pipeline, options, after_file) {
            Err(RunError::TempGone { .. }) if attempt < ATTEMPTS => attempt += 1,
            result => return result,
        }
    }
}

fn run_once(
    pipeline: &Pipeline,
    options: &RunOptions,
    after_file: AfterFile,
) -> Result<RunReport, RunError> {
    let started = Instant::now();
    let started_unix_s = unix_now();
    if options.export {
        check_apart(&options.out_dir, &options.cache_dir)?;
    }
    let cache = open_cache(&options.cache_dir)?;
    let provenance_path = options.out_dir.join("provenance.json");
    let previous = Provenance::read(&provenance_path)?;
    let plan = plan_run(pipeline, &cache, options, previous.as_ref())?;
    let provenance = new_provenance(pipeline, options, started_unix_s);
    if options.dry_run {
        return Ok(report(plan, provenance));
    }

    let history = RunHistory::new(&options.history, previous.as_ref());
    let multi = (!options.quiet).then(MultiProgress::new);
    let overall = RunBar::new(multi.as_ref(), &plan, &history, options.label.as_deref());
    let scope = RunScope {
        pipeline,
        plan: &plan,
        cache: &cache,
        options,
        history: &history,
    };
    let mut state = RunState {
        memory: Memory::for_plan(&plan),
        manifests: HashMap::new(),
        dropped: Vec::new(),
        deferred: BTreeMap::new(),
    };
    let mut outcome = report(plan.clone(), provenance);
    for (index, planned) in plan.stages.iter().enumerate() {
        overall.start(index, &planned.name);
        if !matches!(planned.reason, Reason::NotSelected | Reason::TempNotNeeded) {
            if cancelled(options) {
                write_deferred(&scope, &mut state, after_file);
                return Err(RunError::Interrupted {
                    stage: planned.name.clone(),
                });
            }
            match run_or_block(
                &scope,
                planned,
                &mut state,
                &mut outcome,
                multi.as_ref(),
                after_file,
            ) {
                Ok(Some(record)) => {
                    outcome
                        .provenance
                        .stages
                        .insert(planned.name.clone(), record);
                }
                Ok(None) => {}
                Err(e) => {
                    write_deferred(&scope, &mut state, after_file);
                    return Err(e);
                }
            }
            let_go_before_another_kind(pipeline, &plan, index);
        }
        overall.done(index);
    }
    overall.finish();
    let RunReport {
        mut provenance,
        failures,
        blocked,
        ..
    } = outcome;
    provenance.wall_s = started.elapsed().as_secs_f64();
    provenance.peak_rss_mb = crate::provenance::peak_rss_mb();
    record_failures(&mut provenance, &failures);
    if options.export {
        keep_earlier_records(&mut provenance, previous, pipeline);
        provenance
            .write(&provenance_path)
            .map_err(|cause| RunError::Output {
                path: provenance_path.clone(),
                cause,
            })?;
    }
    let report = RunReport {
        plan,
        provenance,
        failures,
        blocked,
    };
    if report.failures.is_empty() {
        Ok(report)
    } else {
        Err(RunError::Failed(Box::new(report)))
    }
}

/// Asks the kind of stage `index` to drop what it keeps for the next stage
/// of its kind ([`hypercontact_core::Stage::let_go`]) when the next stage
/// in the plan is of another kind.
fn let_go_before_another_kind(pipeline: &Pipeline, plan: &Plan, index: usize) {
    let kind = &plan.stages[index].kind;
    if plan
        .stages
        .get(index + 1)
        .is_none_or(|next| &next.kind != kind)
        && let Some(decl) = pipeline.stage(&plan.stages[index].name)
    {
        decl.stage.let_go();
    }
}

/// Whether the run was asked to stop ([`RunOptions::cancel`]).
fn cancelled(options: &RunOptions) -> bool {
    options
        .cancel
        .as_ref()
        .is_some_and(|flag| flag.load(Ordering::SeqCst))
}

/// The plan of a run. Keeping going, an unreadable input file fails its
/// stage alone; a dry run, which runs nothing, is refused as `--fail-fast`
/// is.
fn plan_run(
    pipeline: &Pipeline,
    cache: &Cache,
    options: &RunOptions,
    previous: Option<&Provenance>,
) -> Result<Plan, PipelineError> {
    let unreadable = match options.keep_going && !options.dry_run {
        true => Unreadable::FailStage,
        false => Unreadable::RefusePlan,
    };
    Plan::build_with(pipeline, cache, &options.plan, previous, unreadable)
}

/// One stage of a run that keeps going: not run when a stage it reads
/// failed (listed in `outcome.blocked`), failed at once when an input file
/// of it cannot be read or an earlier variant of the study failed on the
/// same entry, else run; a failure is
/// listed in `outcome.failures` (Ok(None)) unless the run stops at the
/// first one (Err). A concurrent run's removal of a temporary entry is
/// always an Err: [`run_with_hook`] plans again.
fn run_or_block(
    scope: &RunScope,
    planned: &PlannedStage,
    state: &mut RunState,
    outcome: &mut RunReport,
    multi: Option<&MultiProgress>,
    after_file: AfterFile,
) -> Result<Option<StageRecord>, RunError> {
    if let Some(because) = blocked_by(planned, &outcome.failures, &outcome.blocked) {
        outcome.blocked.push(Blocked {
            stage: planned.name.clone(),
            because,
        });
        state.memory.release(planned);
        return Ok(None);
    }
    let earlier = (scope.options.known_failures.get(&planned.key))
        .filter(|_| planned.reason != Reason::Cached);
    let failure = match (&planned.reason, earlier) {
        (Reason::Unreadable(error), _) => StageFailure::unreadable(planned, error),
        (_, Some(cause)) => StageFailure::earlier(planned, cause),
        (_, None) => {
            let t0 = Instant::now();
            match run_stage(scope, planned, state, multi, after_file) {
                Ok(record) => return Ok(Some(record)),
                Err(e @ RunError::TempGone { .. }) => return Err(e),
                Err(e) if !scope.options.keep_going => return Err(e),
                Err(e) => StageFailure::new(planned, &e, t0.elapsed().as_secs_f64()),
            }
        }
    };
    outcome.failures.push(failure);
    // The temporary entries held for readers: written now, before this
    // stage's reads leave memory, so the next run finds them.
    write_deferred(scope, state, after_file);
    state.memory.release(planned);
    Ok(None)
}

/// Refuses an output folder inside the cache or a cache inside the output
/// folder (compared as [`folders::is_within`] compares them).
fn check_apart(out: &Path, cache: &Path) -> Result<(), RunError> {
    if folders::is_within(out, cache) || folders::is_within(cache, out) {
        return Err(RunError::Overlap {
            out: out.to_owned(),
            cache: cache.to_owned(),
        });
    }
    Ok(())
}

/// The cache in `dir`, created if there is none.
pub(crate) fn open_cache(dir: &Path) -> Result<Cache, RunError> {
    Cache::open(dir).map_err(cache_error(dir))
}

/// An I/O error of the cache at `path`, as a [`RunError`].
fn cache_error(path: &Path) -> impl Fn(std::io::Error) -> RunError + '_ {
    move |cause| RunError::Cache {
        path: path.to_owned(),
        cause,
    }
}

/// Every failed stage into the record, with its time and error: a run's
/// time spent on a stage that failed is part of where the time went.
fn record_failures(provenance: &mut Provenance, failures: &[StageFailure]) {
    for f in failures {
        let record = FailedRecord {
            kind: f.kind.clone(),
            key: f.key.clone(),
            wall_s: f.wall_s,
            error: f.cause.clone(),
        };
        provenance.failed.insert(f.stage.clone(), record);
    }
}

/// The record of a run before any stage has run.
fn new_provenance(pipeline: &Pipeline, options: &RunOptions, started_unix_s: u64) -> Provenance {
    Provenance {
        pipeline: pipeline.name.clone(),
        pipeline_file: pipeline.file.display().to_string(),
        pipeline_blake3: pipeline.source_blake3().to_owned(),
        hypercontact_version: env!("CARGO_PKG_VERSION").to_owned(),
        producer: Some(crate::producer::running().to_owned()),
        overrides: options.overrides.clone(),
        started_unix_s,
        wall_s: 0.0,
        peak_rss_mb: None,
        stages: BTreeMap::new(),
        format: PROVENANCE_FORMAT,
        failed: BTreeMap::new(),
    }
}

/// What every stage of one run reads.
struct RunScope<'a> {
    pipeline: &'a Pipeline,
    plan: &'a Plan,
    cache: &'a Cache,
    options: &'a RunOptions,
    /// Earlier runs' stage times, for the stages' ETAs.
    history: &'a RunHistory<'a>,
}

/// What the stages of a run have left for the stages after them.
struct RunState {
    memory: Memory,
    /// The entry of every stage run so far, by stage name.
    manifests: HashMap<String, Manifest>,
    /// Temporary stages whose entries this run has removed.
    dropped: Vec<String>,
    /// Temporary stages computed but not written, by stage name (see
    /// [`defers_write`]); their manifests are in `manifests`.
    deferred: BTreeMap<String, Deferred>,
}

/// The products of a temporary stage whose entry waits: held weakly where
/// [`Memory`] holds them for readers, so each leaves memory with its last
/// reader (a paper-scale sample's 0.8 GB of tiles go once stitched, while
/// its truth waits for the contact experiment), and strongly for the
/// outputs no stage reads, which memory does not hold.
struct Deferred(BTreeMap<String, Held>);

enum Held {
    Read(Weak<Product>),
    Unread(Arc<Product>),
}

impl Deferred {
    fn new(stage: &str, outputs: &Products, memory: &Memory) -> Self {
        let held =
            |name: &String| (memory.products).contains_key(&(stage.to_owned(), name.clone()));
        Self(
            outputs
                .iter()
                .map(|(name, p)| {
                    let kept = match held(name) {
                        true => Held::Read(Arc::downgrade(p)),
                        false => Held::Unread(p.clone()),
                    };
                    (name.clone(), kept)
                })
                .collect(),
        )
    }

    /// Every product, if none has left memory yet.
    fn complete(&self) -> Option<Products> {
        (self.0.iter())
            .map(|(name, held)| {
                let product = match held {
                    Held::Read(p) => p.upgrade()?,
                    Held::Unread(p) => p.clone(),
                };
                Some((name.clone(), product))
            })
            .collect()
    }
}

/// A stage's products by output name.
type Products = BTreeMap<String, Arc<Product>>;

/// A product of a stage: (stage, output).
type ProductId = (String, String);

/// Products held in memory for the stages of this run still to read them,
/// each with how many of those there are: at zero it leaves memory (a
/// paper-scale run would otherwise hold every sample's tiles and truth at
/// once).
struct Memory {
    products: HashMap<ProductId, Arc<Product>>,
    readers: HashMap<ProductId, usize>,
}

impl Memory {
    fn for_plan(plan: &Plan) -> Self {
        let mut readers: HashMap<ProductId, usize> = HashMap::new();
        for s in &plan.stages {
            for input in &s.inputs {
                *readers
                    .entry((input.from_stage.clone(), input.from_output.clone()))
                    .or_default() += 1;
            }
        }
        Self {
            products: HashMap::new(),
            readers,
        }
    }

    /// Keeps the products a stage computed now that a later stage reads.
    fn keep(&mut self, stage: &str, outputs: &Products) {
        for (name, product) in outputs {
            let id = (stage.to_owned(), name.clone());
            if self.readers.get(&id).is_some_and(|&n| n > 0) {
                self.products.insert(id, product.clone());
            }
        }
    }

    /// Counts the reads of a stage that has run, dropping each product
    /// no stage reads any more.
    fn release(&mut self, planned: &PlannedStage) {
        for input in &planned.inputs {
            let id = (input.from_stage.clone(), input.from_output.clone());
            if let Some(n) = self.readers.get_mut(&id) {
                *n = n.saturating_sub(1);
                if *n == 0 {
                    self.products.remove(&id);
                }
            }
        }
        // What the stage and the products it outlived freed: back to the
        // system before the next stage, not kept in malloc's arenas (#48).
        crate::heap::return_freed();
    }
}

/// One stage of a run: its entry found or computed, exported, and its
/// provenance record.
fn run_stage(
    scope: &RunScope,
    planned: &PlannedStage,
    state: &mut RunState,
    multi: Option<&MultiProgress>,
    after_file: AfterFile,
) -> Result<StageRecord, RunError> {
    let t0 = Instant::now();
    let defer = defers_write(scope, planned);
    let sink = multi.map(|m| {
        TerminalProgress::new(m)
            .labelled(scope.options.label.as_deref())
            .recorded(scope.history.seconds(planned))
    });
    let Obtained {
        manifest,
        mut use_,
        outputs,
    } = obtain_entry(
        scope.pipeline,
        scope.plan,
        planned,
        scope.cache,
        &state.manifests,
        &mut state.memory.products,
        sink.as_ref().map(|s| s as &dyn ProgressSink),
        after_file,
        defer,
    )?;
    // Deferred only when computed now: a cache hit has its entry.
    let deferred = defer && outputs.is_some();
    let outputs: Products = outputs
        .map(Outputs::into_inner)
        .into_iter()
        .flatten()
        .map(|(name, product)| (name, Arc::new(product)))
        .collect();
    state.memory.keep(&planned.name, &outputs);
    if deferred {
        let waiting = Deferred::new(&planned.name, &outputs, &state.memory);
        state.deferred.insert(planned.name.clone(), waiting);
    }
    // Computed by a cluster job of this run: a hit here, but this run's
    // work.
    let job = scope.options.remote.get(&planned.key).cloned();
    if use_ == CacheUse::Hit && job.is_some() {
        use_ = CacheUse::Miss;
    }
    if use_ == CacheUse::Hit {
        scope.cache.touch(&planned.key);
    }
    let exported = if scope.options.export && !planned.temp {
        export_entry(&scope.options.out_dir, scope.cache, planned, &manifest)?
    } else {
        BTreeMap::new()
    };
    let record = StageRecord {
        kind: planned.kind.clone(),
        version: planned.version,
        key: planned.key.clone(),
        params: planned.params.clone(),
        files: planned.files.clone(),
        inputs: planned.input_records(),
        outputs: exported,
        cache: use_,
        wall_s: t0.elapsed().as_secs_f64(),
        compute_s: manifest.compute_s,
        temp: planned.temp,
        notes: manifest.notes.clone(),
        job,
        producer: Some(crate::producer::shown(manifest.producer.as_deref()).to_owned()),
    };
    if !deferred {
        scope.cache.restamp(&planned.key, &manifest);
    }
    state.manifests.insert(planned.name.clone(), manifest);
    if !scope.options.keep_temps {
        drop_finished_temps(scope.plan, scope.cache, state)?;
    }
    state.memory.release(planned);
    Ok(record)
}

/// Whether a temporary stage's entry can wait: its readers all run in this
/// process now (none is left out by `--only`), and the run keeps no
/// temporary entries (a study's variants share them). Its entry is then not
/// written (a paper-scale scan is 1.4 GB of tiles and truth per sample,
/// written, hashed and removed again within a minute): its products stay in
/// memory for the readers, and are written only if the run stops with an
/// error before they have their entries ([`write_deferred`]), so the next
/// run finds them as it would have.
fn defers_write(scope: &RunScope, planned: &PlannedStage) -> bool {
    planned.temp
        && !scope.options.keep_temps
        && scope
            .plan
            .consumers(&planned.name)
            .all(|c| c.reason != Reason::NotSelected)
}

/// Writes the entries of the temporary stages whose readers have not all
/// finished, as the run stops on an error. Best effort: the error that
/// stopped the run is the one to report, and a temporary entry that could
/// not be written, or whose products have partly left memory with their
/// last readers, is recomputed by the next run that needs it.
fn write_deferred(scope: &RunScope, state: &mut RunState, after_file: AfterFile) {
    for (name, waiting) in std::mem::take(&mut state.deferred) {
        let (Some(planned), Some(decl), Some(manifest), Some(products)) = (
            scope.plan.stage(&name),
            scope.pipeline.stage(&name),
            state.manifests.get(&name),
            waiting.complete(),
        ) else {
            continue;
        };
        let products = products.iter().map(|(n, p)| (n.as_str(), p.as_ref()));
        let _ = write_entry(
            scope.cache,
            planned,
            decl.stage.info(),
            products,
            (manifest.compute_s, manifest.notes.clone()),
            after_file,
        );
    }
}

/// Places the files of a stage's entry in `<out>/<stage>/`; returns each
/// exported file (`stage/name`) with its BLAKE3.
fn export_entry(
    out_dir: &Path,
    cache: &Cache,
    planned: &PlannedStage,
    manifest: &Manifest,
) -> Result<BTreeMap<String, String>, RunError> {
    let stage_dir = out_dir.join(&planned.name);
    let entry = cache.entry_dir(&planned.key);
    let mut exported = BTreeMap::new();
    for (output, record) in &manifest.outputs {
        for (rel, file) in &record.files {
            let name = store::export_name(output, record, rel);
            let dst = stage_dir.join(&name);
            store::place_unless_held(&entry.join(rel), &dst, file).map_err(|cause| {
                RunError::Export {
                    stage: planned.name.clone(),
                    cause,
                }
            })?;
            exported.insert(format!("{}/{name}", planned.name), file.blake3.clone());
        }
    }
    Ok(exported)
}

/// Stages of the pipeline that were not part of this run keep their
/// earlier record, marked skipped.
fn keep_earlier_records(
    provenance: &mut Provenance,
    previous: Option<Provenance>,
    pipeline: &Pipeline,
) {
    let Some(previous) = previous else {
        return;
    };
    for (name, record) in previous.stages {
        // A stage that failed now is listed as failed, not as its earlier
        // success.
        if pipeline.stage(&name).is_some() && !provenance.failed.contains_key(&name) {
            provenance.stages.entry(name).or_insert(StageRecord {
                cache: CacheUse::Skipped,
                ..record
            });
        }
    }
}

/// A stage's entry as [`obtain_entry`] found or made it.
struct Obtained {
    manifest: Manifest,
    use_: CacheUse,
    /// The products, when computed now (kept in memory for later stages).
    outputs: Option<Outputs>,
}

impl Obtained {
    /// An entry found whole in the cache.
    fn hit(manifest: Manifest) -> Self {
        Self {
            manifest,
            use_: CacheUse::Hit,
            outputs: None,
        }
    }
}

/// The entry of a planned stage: the one the plan verified, or computed
/// now under the entry's lock, unless another process (a concurrent run, a
/// cluster job) finished it while this one waited for the lock.
#[allow(clippy::too_many_arguments)]
fn obtain_entry(
    pipeline: &Pipeline,
    plan: &Plan,
    planned: &PlannedStage,
    cache: &Cache,
    manifests: &HashMap<String, Manifest>,
    products: &mut HashMap<(String, String), Arc<Product>>,
    sink: Option<&dyn ProgressSink>,
    after_file: AfterFile,
    defer_write: bool,
) -> Result<Obtained, RunError> {
    let forced = matches!(planned.reason, Reason::Forced);
    // A hit needs no lock: entries appear by rename, whole or not at all.
    // The plan already verified a cached entry; reuse that check.
    if planned.reason == Reason::Cached
        && let Some(manifest) = &planned.manifest
    {
        return Ok(Obtained::hit(manifest.clone()));
    }
    let _lock = cache
        .lock(&planned.key)
        .map_err(cache_error(cache.root()))?;
    // Staging folders of this entry are debris of killed runs now.
    cache.clear_staging(&planned.key);
    // Another run may have finished this entry while we waited.
    if !forced && let EntryState::Valid(m) = cache.check(&planned.key) {
        return Ok(Obtained::hit(*m));
    }
    let decl = pipeline
        .stage(&planned.name)
        .expect("the plan only names pipeline stages");
    let inputs = gather_inputs(plan, planned, cache, manifests, products)?;
    let reader = hypercontact_io::RunnerReader;
    let ctx = Context::with(&planned.name, sink, &reader)
        .with_upstream(upstream_record(plan, planned, pipeline));
    let t_compute = Instant::now();
    let outputs = decl
        .stage
        .run_dyn(decl.params.as_ref(), &inputs, &ctx)
        .map_err(|source| RunError::Stage {
            file: pipeline.file.clone(),
            stage: planned.name.clone(),
            kind: planned.kind.clone(),
            cause: Box::new(source),
        })?;
    let compute_s = t_compute.elapsed().as_secs_f64();
    let info = decl.stage.info();
    check_contract(planned, info, &outputs)?;
    let manifest = if defer_write {
        manifest_of(planned, BTreeMap::new(), compute_s, ctx.notes())
    } else {
        write_entry(
            cache,
            planned,
            info,
            outputs.iter(),
            (compute_s, ctx.notes()),
            after_file,
        )?
    };
    Ok(Obtained {
        manifest,
        use_: if forced {
            CacheUse::Forced
        } else {
            CacheUse::Miss
        },
        outputs: Some(outputs),
    })
}

/// One stage of a pipeline as a cluster job runs it.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize, PartialEq)]
pub struct StageJob {
    pub stage: String,
    /// The key the submitter planned: the job refuses to write any other.
    pub key: String,
    /// Recompute even if the entry exists (`--force`).
    #[serde(default)]
    pub force: bool,
}

/// What [`exec_stage`] did.
#[derive(Clone, Debug, PartialEq)]
pub enum JobOutcome {
    Computed {
        compute_s: f64,
    },
    /// The entry was there already (another job or run made it).
    AlreadyCached,
}

/// Computes one stage's entry from the entries of the stages it reads,
/// which must be in the cache (`hypercontact exec-stage`, a cluster job):
/// the same lock, staging folder and rename as a local run, so a job killed
/// mid-stage leaves the entry absent and the cache valid.
pub fn exec_stage(
    pipeline: &Pipeline,
    cache_dir: &Path,
    job: &StageJob,
) -> Result<JobOutcome, RunError> {
    let cache = open_cache(cache_dir)?;
    let options = PlanOptions {
        force: if job.force {
            vec![job.stage.clone()]
        } else {
            Vec::new()
        },
        only: Some(job.stage.clone()),
        prune: true,
    };
    let plan = Plan::build(pipeline, &cache, &options, None)?;
    let planned = plan.stage(&job.stage).expect("checked by the plan");
    if planned.key != job.key {
        return Err(RunError::Job(format!(
            "stage `{}`: its key is now {} but the job was submitted for {}: the pipeline, a file \
             it reads or the hypercontact binary changed since submission; submit again",
            job.stage,
            short_key(&planned.key),
            short_key(&job.key)
        )));
    }
    if planned.reason == Reason::Cached {
        cache.touch(&planned.key);
        return Ok(JobOutcome::AlreadyCached);
    }
    let mut manifests = HashMap::new();
    for input in &planned.inputs {
        let upstream = plan.stage(&input.from_stage).expect("inputs name stages");
        match &upstream.manifest {
            Some(m) => {
                manifests.insert(upstream.name.clone(), m.clone());
            }
            None => {
                return Err(RunError::Job(format!(
                    "stage `{}` reads `{}`, whose entry {} is not in the cache {} ({})",
                    job.stage,
                    upstream.name,
                    short_key(&upstream.key),
                    cache_dir.display(),
                    upstream.reason
                )));
            }
        }
    }
    let obtained = obtain_entry(
        pipeline,
        &plan,
        planned,
        &cache,
        &manifests,
        &mut HashMap::new(),
        None,
        &mut |_| {},
        false,
    )?;
    cache.restamp(&planned.key, &obtained.manifest);
    Ok(match obtained.use_ {
        CacheUse::Hit => JobOutcome::AlreadyCached,
        _ => JobOutcome::Computed {
            compute_s: obtained.manifest.compute_s,
        },
    })
}

/// Removes the entry of every temporary stage of this run whose readers all
/// have their entries now (each in `manifests`): nothing in this run needs
/// it any more, and a later run recomputes it from its key if one does.
fn drop_finished_temps(plan: &Plan, cache: &Cache, state: &mut RunState) -> Result<(), RunError> {
    let manifests = &state.manifests;
    for temp in plan.stages.iter().filter(|s| s.temp) {
        if state.dropped.contains(&temp.name) || !manifests.contains_key(&temp.name) {
            continue;
        }
        if plan
            .consumers(&temp.name)
            .all(|c| manifests.contains_key(&c.name) || c.reason == Reason::TempNotNeeded)
        {
            // A deferred entry was never written: its products go, and its
            // lock file with what else the removal clears.
            state.deferred.remove(&temp.name);
            remove_entry(cache, &temp.key)?;
            state.dropped.push(temp.name.clone());
        }
    }
    Ok(())
}

/// Removes the entries of every temporary stage of a finished run.
pub fn drop_temps(plan: &Plan, cache: &Cache) -> Result<(), RunError> {
    for temp in plan.stages.iter().filter(|s| s.temp) {
        if cache.entry_dir(&temp.key).exists() {
            remove_entry(cache, &temp.key)?;
        }
    }
    Ok(())
}

/// Removes one entry of the cache.
fn remove_entry(cache: &Cache, key: &str) -> Result<(), RunError> {
    cache
        .remove(key)
        .map_err(cache_error(&cache.entry_dir(key)))
}

/// Loads the products a stage needs, from this run's memory or the cache.
fn gather_inputs(
    plan: &Plan,
    planned: &PlannedStage,
    cache: &Cache,
    manifests: &HashMap<String, Manifest>,
    products: &mut HashMap<(String, String), Arc<Product>>,
) -> Result<Inputs, RunError> {
    let mut inputs = Inputs::new();
    for input in &planned.inputs {
        let id = (input.from_stage.clone(), input.from_output.clone());
        if !products.contains_key(&id) {
            let manifest = manifests
                .get(&input.from_stage)
                .expect("upstream stages run first");
            let record =
                manifest
                    .outputs
                    .get(&input.from_output)
                    .ok_or_else(|| RunError::Contract {
                        stage: input.from_stage.clone(),
                        kind: manifest.kind.clone(),
                        message: format!("its cache entry has no output `{}`", input.from_output),
                    })?;
            let dir = cache.entry_dir(&input.upstream_key);
            let product = match store::read_product(&dir, &input.from_output, record) {
                Ok(product) => product,
                Err(_)
                    if plan.stage(&input.from_stage).is_some_and(|s| s.temp)
                        && !matches!(cache.check(&input.upstream_key), EntryState::Valid(_)) =>
                {
                    return Err(RunError::TempGone {
                        stage: input.from_stage.clone(),
                    });
                }
                Err(e) => return Err(e.into()),
            };
            products.insert(id.clone(), Arc::new(product));
        }
        inputs.insert(&input.input, products[&id].clone());
    }
    Ok(inputs)
}

/// Every declared output present with its kind and columns, nothing else.
fn check_contract(
    planned: &PlannedStage,
    info: &hypercontact_core::StageInfo,
    outputs: &Outputs,
) -> Result<(), RunError> {
    let broken = |message: String| RunError::Contract {
        stage: planned.name.clone(),
        kind: planned.kind.clone(),
        message,
    };
    for spec in info.outputs {
        let product = outputs
            .get(spec.name)
            .ok_or_else(|| broken(format!("output `{}` is missing", spec.name)))?;
        if product.kind() != spec.kind {
            return Err(broken(format!(
                "output `{}` is a {}, declared a {}",
                spec.name,
                product.kind(),
                spec.kind
            )));
        }
        if let Product::Table(t) = product {
            t.validate()
                .and_then(|_| t.conform(spec.columns))
                .map_err(|e| broken(format!("output `{}`: {e}", spec.name)))?;
        }
        if let Product::Field(f) = product
            && spec.kind == ProductKind::Field
            && !(f.dx_m > 0.0 && f.dy_m > 0.0)
        {
            return Err(broken(format!(
                "output `{}` has no grid spacing",
                spec.name
            )));
        }
    }
    if let Some((name, _)) = outputs.iter().find(|(n, _)| info.output(n).is_none()) {
        return Err(broken(format!("output `{name}` is not declared")));
    }
    Ok(())
}

/// Writes the entry of a computed stage; each output carries the columns
/// its `info` declares (their units travel in the Parquet files).
fn write_entry<'a>(
    cache: &Cache,
    planned: &PlannedStage,
    info: &hypercontact_core::StageInfo,
    outputs: impl Iterator<Item = (&'a str, &'a Product)>,
    (compute_s, notes): (f64, Vec<String>),
    after_file: AfterFile,
) -> Result<Manifest, RunError> {
    let cache_err = cache_error(cache.root());
    let staging = cache.staging_dir(&planned.key).map_err(&cache_err)?;
    let write = || -> Result<Manifest, RunError> {
        let mut records: BTreeMap<String, OutputRecord> = BTreeMap::new();
        for (name, product) in outputs {
            // check_contract refused an undeclared output before this.
            let columns = info.output(name).map_or(&[][..], |spec| spec.columns);
            let record = store::write_product(&staging, name, product, columns, after_file)?;
            records.insert(name.to_owned(), record);
        }
        let manifest = manifest_of(planned, records, compute_s, notes);
        cache.commit(&staging, &manifest).map_err(&cache_err)?;
        Ok(manifest)
    };
    let written = write();
    if written.is_err() {
        // What a failed write left is no entry (never renamed into place);
        // a run that keeps going leaves no debris of it either. (A killed
        // run's staging folder is removed by the next writer or `cache gc`.)
        let _ = std::fs::remove_dir_all(&staging);
    }
    written
}

/// The manifest of a stage computed now with these output records.
fn manifest_of(
    planned: &PlannedStage,
    records: BTreeMap<String, OutputRecord>,
    compute_s: f64,
    notes: Vec<String>,
) -> Manifest {
    Manifest {
        format: MANIFEST_FORMAT,
        key: planned.key.clone(),
        kind: planned.kind.clone(),
        version: planned.version,
        stage: planned.name.clone(),
        created_unix_s: unix_now(),
        compute_s,
        params: planned.params.clone(),
        outputs: records,
        notes,
        producer: Some(crate::producer::running().to_owned()),
    }
}

/// What a stage may know of the stages it depends on, transitively: kind,
/// version, key, parameters and input-file hashes, from the plan. Only what
/// the keys determine (no times, no cache use, nothing about which stages
/// this run executed), so the same key always gets the same record and a
/// product that shows it (the report) is the same bytes on every run.
fn upstream_record(plan: &Plan, planned: &PlannedStage, pipeline: &Pipeline) -> serde_json::Value {
    let by_name: HashMap<&str, &PlannedStage> =
        plan.stages.iter().map(|s| (s.name.as_str(), s)).collect();
    let mut seen = std::collections::BTreeSet::new();
    let mut stack: Vec<&str> = planned
        .inputs
        .iter()
        .map(|i| i.from_stage.as_str())
        .collect();
    while let Some(name) = stack.pop() {
        if seen.insert(name.to_owned())
            && let Some(s) = by_name.get(name)
        {
            stack.extend(s.inputs.iter().map(|i| i.from_stage.as_str()));
        }
    }
    let stages: serde_json::Map<String, serde_json::Value> = seen
        .iter()
        .filter_map(|name| {
            let s = by_name.get(name.as_str())?;
            Some((
                name.clone(),
                serde_json::json!({
                    "kind": s.kind,
                    "version": s.version,
                    "key": s.key,
                    "params": s.params,
                    "files_blake3": s.files,
                }),
            ))
        })
        .collect();
    serde_json::json!({
        "pipeline": pipeline.name,
        "hypercontact_version": env!("CARGO_PKG_VERSION"),
        "stage": planned.name,
        "key": planned.key,
        "upstream": stages,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::Table;

    fn table(x: f64) -> Arc<Product> {
        Arc::new(Product::Table(Table::new().with("x", vec![x])))
    }

    #[test]
    fn a_deferred_stage_lets_each_read_product_go_with_its_last_reader() {
        let mut memory = Memory {
            products: HashMap::new(),
            readers: HashMap::new(),
        };
        let outputs: Products = [("tiles", 1.0), ("truth", 2.0), ("offsets", 3.0)]
            .into_iter()
            .map(|(name, x)| (name.to_owned(), table(x)))
            .collect();
        for read in ["tiles", "truth"] {
            let id = ("scan".to_owned(), read.to_owned());
            memory.readers.insert(id, 1);
        }
        memory.keep("scan", &outputs);
        let waiting = Deferred::new("scan", &outputs, &memory);
        drop(outputs);
        let all = waiting.complete().expect("every product still held");
        assert_eq!(all.len(), 3);
        drop(all);
        // The unread `offsets` is held by the deferral alone; `tiles` by memory.
        memory
            .products
            .remove(&("scan".to_owned(), "tiles".to_owned()));
        assert!(waiting.complete().is_none(), "tiles have left memory");
        let Held::Unread(offsets) = &waiting.0["offsets"] else {
            panic!("an output no stage reads is held strongly");
        };
        assert_eq!(Arc::strong_count(offsets), 1);
        let Held::Read(truth) = &waiting.0["truth"] else {
            panic!("a read output is held weakly");
        };
        assert!(truth.upgrade().is_some(), "memory still holds the truth");
    }
}
