//! The plan: stage order, every cache key, and what runs and why, before
//! anything runs.
//!
//! A key is the BLAKE3 of the stage kind, its implementation version, its
//! canonical parameters (input files replaced by their content hashes) and,
//! for each input, the upstream entry's key and output name. Upstream keys
//! are known before anything runs, so the plan sees every downstream rerun
//! that an upstream change causes (Snakemake's dry run does; DVC's does not).

use std::collections::{BTreeMap, HashMap, HashSet};
use std::fmt;

use hypercontact_core::stage::Arity;
use hypercontact_core::{InputSpec, OutputSpec, ProductKind, StageInfo};

use crate::cache::{Cache, EntryState, Manifest};
use crate::hash::{canonical_json, path_hash, text_hash};
use crate::pipeline::{InputBinding, Pipeline, PipelineError, StageDecl};
use crate::provenance::{InputRecord, Provenance, StageRecord};
use crate::yaml::Location;

/// An input resolved to an upstream product.
#[derive(Clone, Debug, PartialEq)]
pub struct ResolvedInput {
    pub input: String,
    pub from_stage: String,
    pub from_output: String,
    pub upstream_key: String,
}

/// Why a stage runs, or that it does not.
#[derive(Clone, Debug, PartialEq)]
pub enum Reason {
    Cached,
    New,
    Forced,
    VersionChanged {
        from: u32,
        to: u32,
    },
    KindChanged {
        from: String,
    },
    ParamsChanged(Vec<String>),
    InputsChanged(Vec<String>),
    FilesChanged(Vec<String>),
    /// Nothing changed since the last run, but the entry is gone or corrupt.
    NotInCache(String),
    /// Not needed for `--only`.
    NotSelected,
    /// A temporary stage whose entry is gone and whose readers are all
    /// cached: nothing needs it.
    TempNotNeeded,
    /// An input file of the stage cannot be read (missing, unreadable, a
    /// folder for a file): the run fails the stage at once and keeps going
    /// ([`Unreadable::FailStage`]). The error is the one the plan would
    /// otherwise be refused with.
    Unreadable(PipelineError),
}

/// What the plan does with a stage whose input file cannot be read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unreadable {
    /// Refuse the whole plan (`--fail-fast`, `--dry-run`, `graph`, a Slurm
    /// submission, a cluster job).
    RefusePlan,
    /// Plan the stage as failing ([`Reason::Unreadable`]): a run that keeps
    /// going fails it as it fails a stage at run time, and runs every stage
    /// that does not read it.
    FailStage,
}

impl fmt::Display for Reason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Reason::Cached => f.write_str("cached"),
            Reason::New => f.write_str("new (no earlier run in this output folder)"),
            Reason::Forced => f.write_str("forced"),
            Reason::VersionChanged { from, to } => write!(f, "version changed ({from} → {to})"),
            Reason::KindChanged { from } => write!(f, "kind changed (was `{from}`)"),
            Reason::ParamsChanged(p) => write!(f, "params changed: {}", p.join(", ")),
            Reason::InputsChanged(i) => write!(f, "input changed: {}", i.join(", ")),
            Reason::FilesChanged(p) => write!(f, "input file changed: {}", p.join(", ")),
            Reason::NotInCache(why) => write!(f, "not in cache ({why})"),
            Reason::NotSelected => f.write_str("skipped (not needed for --only)"),
            Reason::TempNotNeeded => {
                f.write_str("temporary, not needed (every stage that reads it is cached)")
            }
            Reason::Unreadable(e) => write!(f, "fails: {e}"),
        }
    }
}

/// One stage in the plan.
#[derive(Clone, Debug)]
pub struct PlannedStage {
    pub name: String,
    pub kind: String,
    pub version: u32,
    pub key: String,
    pub params: serde_json::Value,
    pub files: BTreeMap<String, String>,
    pub inputs: Vec<ResolvedInput>,
    pub runs: bool,
    pub reason: Reason,
    /// `temp: true` in the pipeline.
    pub temp: bool,
    /// The verified entry when the plan found one, so the run need not hash
    /// its files a second time.
    pub manifest: Option<Manifest>,
}

/// What a run does with a planned stage: the verdict `run --dry-run`
/// prints and `hypercontact graph` draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// Computed (new, changed, forced or missing from the cache).
    Run,
    /// Served from its valid cache entry.
    Cached,
    /// Left out: not needed for `--only`, or a temporary stage no reader needs.
    Skip,
}

impl PlannedStage {
    /// What a run does with this stage.
    pub fn action(&self) -> Action {
        match self.reason {
            Reason::Cached => Action::Cached,
            Reason::NotSelected | Reason::TempNotNeeded => Action::Skip,
            _ => Action::Run,
        }
    }

    /// The provenance view of the inputs.
    pub fn input_records(&self) -> BTreeMap<String, InputRecord> {
        self.inputs
            .iter()
            .map(|i| {
                (
                    i.input.clone(),
                    InputRecord {
                        from: format!("{}.{}", i.from_stage, i.from_output),
                        key: i.upstream_key.clone(),
                    },
                )
            })
            .collect()
    }
}

/// Stages in execution order with their keys and reasons.
#[derive(Clone, Debug)]
pub struct Plan {
    pub stages: Vec<PlannedStage>,
}

/// What the user asked for.
#[derive(Clone, Debug, Default)]
pub struct PlanOptions {
    pub force: Vec<String>,
    pub only: Option<String>,
    /// With `only`: leave the stages it does not need out of the plan
    /// altogether, neither keyed nor looked up (a cluster job, which must
    /// not hash every input file of the pipeline to compute one stage).
    pub prune: bool,
}

impl Plan {
    /// The plan, refused when an input file of a stage cannot be read.
    pub fn build(
        pipeline: &Pipeline,
        cache: &Cache,
        options: &PlanOptions,
        previous: Option<&Provenance>,
    ) -> Result<Plan, PipelineError> {
        Self::build_with(pipeline, cache, options, previous, Unreadable::RefusePlan)
    }

    /// The plan; `unreadable` says whether a stage's unreadable input file
    /// refuses it or fails that stage alone. Every other error (the
    /// wiring, a cycle, an unknown stage to force) refuses it.
    pub fn build_with(
        pipeline: &Pipeline,
        cache: &Cache,
        options: &PlanOptions,
        previous: Option<&Provenance>,
        unreadable: Unreadable,
    ) -> Result<Plan, PipelineError> {
        let order = topological_order(pipeline)?;
        for name in options.force.iter().chain(options.only.iter()) {
            if pipeline.stage(name).is_none() {
                return Err(PipelineError::new(
                    &pipeline.file,
                    format!(
                        "no stage `{name}` to force or run (stages: {})",
                        stage_list(pipeline)
                    ),
                ));
            }
        }
        let selected = match &options.only {
            Some(only) => ancestors(pipeline, only),
            None => pipeline.stages.iter().map(|s| s.name.clone()).collect(),
        };

        let mut keys: HashMap<String, String> = HashMap::new();
        let mut runs: HashMap<String, bool> = HashMap::new();
        let mut stages = Vec::new();
        for index in order {
            let decl = &pipeline.stages[index];
            if options.prune && !selected.contains(&decl.name) {
                continue;
            }
            let info = decl.stage.info();
            let inputs = resolve_inputs(pipeline, decl, info, &keys)?;
            // A stage failing on its file still has a key (over its
            // parameters as given), so its readers are keyed and listed.
            let (params, files, refused) = match keyed_params(decl) {
                Ok((params, files)) => (params, files, None),
                Err(e) if unreadable == Unreadable::FailStage => {
                    (decl.params.to_json(), BTreeMap::new(), Some(e))
                }
                Err(e) => return Err(e),
            };
            let material = serde_json::json!({
                "kind": info.kind,
                "version": info.version,
                "params": params,
                "inputs": inputs
                    .iter()
                    .map(|i| (i.input.clone(), format!("{}/{}", i.upstream_key, i.from_output)))
                    .collect::<BTreeMap<_, _>>(),
            });
            let key = text_hash(&canonical_json(&material));
            keys.insert(decl.name.clone(), key.clone());

            let is_selected = selected.contains(&decl.name);
            // A stage `--only` does not need is not looked up (a cluster
            // job plans with `--only` its stage: it reads its inputs' entries,
            // not every entry of the pipeline), nor one that cannot be keyed.
            let state = match is_selected && refused.is_none() {
                true => cache.check(&key),
                false => EntryState::Missing,
            };
            let reason = match (is_selected, refused) {
                (false, _) => Reason::NotSelected,
                (true, Some(e)) => Reason::Unreadable(e),
                (true, None) => {
                    let record = previous.and_then(|p| p.stages.get(&decl.name));
                    let forced = options.force.contains(&decl.name);
                    let change = Change {
                        files: &files,
                        inputs: &inputs,
                        record,
                        runs: &runs,
                    };
                    reason_to_run(decl, info, forced, &state, change)
                }
            };
            let run = !matches!(reason, Reason::Cached | Reason::NotSelected);
            runs.insert(decl.name.clone(), run);
            stages.push(PlannedStage {
                name: decl.name.clone(),
                kind: decl.kind.clone(),
                version: info.version,
                key,
                params: decl.params.to_json(),
                files,
                inputs,
                runs: run,
                reason,
                temp: decl.temp,
                manifest: match &state {
                    EntryState::Valid(m) => Some((**m).clone()),
                    _ => None,
                },
            });
        }
        skip_unneeded_temps(&mut stages);
        Ok(Plan { stages })
    }

    /// The stages that read `name`'s outputs.
    pub fn consumers<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a PlannedStage> + 'a {
        self.stages
            .iter()
            .filter(move |s| s.inputs.iter().any(|i| i.from_stage == name))
    }

    pub fn stage(&self, name: &str) -> Option<&PlannedStage> {
        self.stages.iter().find(|s| s.name == name)
    }

    /// The plan as a human reads it: one line per stage.
    pub fn describe(&self) -> String {
        self.describe_with(&|_| None)
    }

    /// [`Plan::describe`], where a stage for which `shared` says why (a
    /// study's entry an earlier variant computes) shows as `shared`.
    pub fn describe_with(&self, shared: &dyn Fn(&PlannedStage) -> Option<String>) -> String {
        // Widths in characters, as `{:<w$}` pads: a `µ` is one column.
        let width = self
            .stages
            .iter()
            .map(|s| s.name.chars().count())
            .max()
            .unwrap_or(0);
        let kind_width = self
            .stages
            .iter()
            .map(|s| s.kind.chars().count())
            .max()
            .unwrap_or(0);
        let mut out = String::new();
        for s in &self.stages {
            let verb = match s.action() {
                Action::Cached => "cached",
                Action::Skip => "skip",
                Action::Run => "RUN",
            };
            let (verb, why) = match shared(s) {
                Some(why) => ("shared", why),
                None => (verb, s.reason.to_string()),
            };
            out.push_str(&format!(
                "{verb:>6}  {:<width$}  {:<kind_width$}  {}  {why}\n",
                s.name,
                s.kind,
                &s.key[..12],
            ));
        }
        out
    }
}

/// A temporary stage need not run when no stage of this run will read it:
/// each reader is cached, skipped, or itself a temporary stage not needed.
/// Readers come later in the order, so one pass from the end settles chains.
fn skip_unneeded_temps(stages: &mut [PlannedStage]) {
    for i in (0..stages.len()).rev() {
        let s = &stages[i];
        if !s.temp || !s.runs || s.reason == Reason::Forced {
            continue;
        }
        let needed = stages[i + 1..].iter().any(|c| {
            c.inputs.iter().any(|input| input.from_stage == s.name)
                && !matches!(
                    c.reason,
                    Reason::Cached | Reason::NotSelected | Reason::TempNotNeeded
                )
        });
        if !needed {
            stages[i].reason = Reason::TempNotNeeded;
            stages[i].runs = false;
        }
    }
}

fn stage_list(pipeline: &Pipeline) -> String {
    pipeline
        .stages
        .iter()
        .map(|s| s.name.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}

/// What a selected stage's key is compared with: its input files, its
/// inputs, its record in the last run and which stages run.
struct Change<'a> {
    files: &'a BTreeMap<String, String>,
    inputs: &'a [ResolvedInput],
    record: Option<&'a StageRecord>,
    runs: &'a HashMap<String, bool>,
}

/// Why a selected stage whose key could be computed runs, or that it is
/// cached.
fn reason_to_run(
    decl: &StageDecl,
    info: &StageInfo,
    forced: bool,
    state: &EntryState,
    change: Change,
) -> Reason {
    if forced {
        Reason::Forced
    } else if matches!(state, EntryState::Valid(_)) {
        Reason::Cached
    } else {
        why_rerun(decl, info, change, state)
    }
}

fn why_rerun(decl: &StageDecl, info: &StageInfo, change: Change, state: &EntryState) -> Reason {
    let Change {
        files,
        inputs,
        record,
        runs,
    } = change;
    let Some(record) = record else {
        return Reason::New;
    };
    if record.kind != decl.kind {
        return Reason::KindChanged {
            from: record.kind.clone(),
        };
    }
    if record.version != info.version {
        return Reason::VersionChanged {
            from: record.version,
            to: info.version,
        };
    }
    let changed = changed_keys(&record.params, &decl.params.to_json(), "");
    if !changed.is_empty() {
        return Reason::ParamsChanged(changed);
    }
    let changed_files: Vec<String> = files
        .iter()
        .filter(|(path, hash)| record.files.get(*path) != Some(hash))
        .map(|(path, _)| path.clone())
        .collect();
    if !changed_files.is_empty() {
        return Reason::FilesChanged(changed_files);
    }
    let changed_inputs: Vec<String> = inputs
        .iter()
        .filter(|i| record.inputs.get(&i.input).map(|r| &r.key) != Some(&i.upstream_key))
        .map(|i| {
            if runs.get(&i.from_stage).copied().unwrap_or(false) {
                format!("{} ({} reruns)", i.input, i.from_stage)
            } else {
                format!("{} (from {})", i.input, i.from_stage)
            }
        })
        .collect();
    if !changed_inputs.is_empty() {
        return Reason::InputsChanged(changed_inputs);
    }
    Reason::NotInCache(match state {
        EntryState::Corrupt(why) => format!("entry corrupt: {why}"),
        _ => "entry missing".into(),
    })
}

/// Dotted paths whose values differ between two JSON objects.
fn changed_keys(old: &serde_json::Value, new: &serde_json::Value, prefix: &str) -> Vec<String> {
    use serde_json::Value;
    match (old, new) {
        (Value::Object(a), Value::Object(b)) => {
            let mut keys: Vec<&String> = a.keys().chain(b.keys()).collect();
            keys.sort();
            keys.dedup();
            keys.into_iter()
                .flat_map(|k| {
                    let path = if prefix.is_empty() {
                        k.clone()
                    } else {
                        format!("{prefix}.{k}")
                    };
                    changed_keys(
                        a.get(k).unwrap_or(&Value::Null),
                        b.get(k).unwrap_or(&Value::Null),
                        &path,
                    )
                })
                .collect()
        }
        (a, b) if canonical_json(a) == canonical_json(b) => Vec::new(),
        (a, b) => vec![format!("{prefix}: {} → {}", short(a), short(b))],
    }
}

/// A value as the plan shows it: at most 40 characters, cut at a character
/// boundary (a `µ` across the cut must not split).
fn short(v: &serde_json::Value) -> String {
    let s = v.to_string();
    match s.char_indices().nth(40) {
        Some((cut, _)) => format!("{}…", &s[..cut]),
        None => s,
    }
}

/// The canonical parameters with every input path replaced by the hash of
/// its content, and the map path → hash. The paths come from the
/// parameters' declared `InputPath`s, so no stage can leave one out.
fn keyed_params(
    decl: &StageDecl,
) -> Result<(serde_json::Value, BTreeMap<String, String>), PipelineError> {
    let mut params = decl.params.to_json();
    let mut files = BTreeMap::new();
    for (param, path) in decl.params.input_paths() {
        let shown = path.display().to_string();
        // Checked before hashing: a folder given for a file would be hashed
        // whole (gigabytes, seconds) only to be refused by the stage.
        if path.is_dir() && !takes_folder(&param) {
            return Err(decl.param_error(
                &param,
                format!("parameter `{param}`: `{shown}` is a folder; `{param}` takes a file"),
            ));
        }
        let hash = path_hash(&path).map_err(|e| {
            decl.param_error(
                &param,
                format!("parameter `{param}`: cannot read `{shown}`: {e}"),
            )
        })?;
        let pointer: String = param
            .split('.')
            .map(|key| format!("/{}", key.replace('~', "~0").replace('/', "~1")))
            .collect();
        if let Some(slot) = params.pointer_mut(&pointer) {
            *slot = serde_json::Value::String(format!("blake3:{hash}"));
        }
        files.insert(shown, hash);
    }
    Ok((params, files))
}

/// Whether the path parameter `param` (a dotted path, list items by
/// index) names a folder: every stage calls a folder parameter `dir`
/// (`dic`, `contact-images`, `surface`), every other path is a file.
fn takes_folder(param: &str) -> bool {
    param
        .rsplit('.')
        .find(|part| !part.bytes().all(|b| b.is_ascii_digit()))
        .is_some_and(|name| name == "dir")
}

fn resolve_inputs(
    pipeline: &Pipeline,
    decl: &StageDecl,
    info: &StageInfo,
    keys: &HashMap<String, String>,
) -> Result<Vec<ResolvedInput>, PipelineError> {
    let wiring = Wiring {
        pipeline,
        decl,
        stage_at: pipeline.locate(&["stages", decl.name.as_str()]),
    };
    let mut resolved = Vec::new();
    for binding in &decl.inputs {
        let line = pipeline.locate(&[
            "stages",
            decl.name.as_str(),
            "inputs",
            binding.declared.as_str(),
        ]);
        let spec = wiring.spec(info, binding, line)?;
        wiring.check_labels(spec, binding, line)?;
        let upstream = pipeline.stage(&binding.from_stage).ok_or_else(|| {
            wiring.err(
                line,
                format!(
                    "input `{}` refers to unknown stage `{}` (stages: {})",
                    binding.input,
                    binding.from_stage,
                    stage_list(pipeline)
                ),
            )
        })?;
        let output = wiring.output(spec, binding, upstream, line)?;
        wiring.check_columns(spec, binding, &upstream.name, output, line)?;
        let upstream_key = keys
            .get(&upstream.name)
            .cloned()
            .expect("upstream stages are planned first");
        resolved.push(ResolvedInput {
            input: binding.input.clone(),
            from_stage: upstream.name.clone(),
            from_output: output.name.to_owned(),
            upstream_key,
        });
    }
    wiring.check_counts(info)?;
    Ok(resolved)
}

/// One stage's inputs being resolved: where its errors point.
struct Wiring<'a> {
    pipeline: &'a Pipeline,
    decl: &'a StageDecl,
    stage_at: Option<Location>,
}

impl Wiring<'_> {
    fn err(&self, at: Option<Location>, message: String) -> PipelineError {
        PipelineError::new(&self.pipeline.file, message)
            .located(at.or(self.stage_at))
            .stage(&self.decl.name)
    }

    /// The declared input a binding fills.
    fn spec(
        &self,
        info: &StageInfo,
        binding: &InputBinding,
        line: Option<Location>,
    ) -> Result<&'static InputSpec, PipelineError> {
        info.input(&binding.declared).ok_or_else(|| {
            let declared: Vec<&str> = info.inputs.iter().map(|i| i.name).collect();
            self.err(
                line,
                format!(
                    "`{}` takes no input `{}` (its inputs: {})",
                    self.decl.kind,
                    binding.declared,
                    if declared.is_empty() {
                        "none".to_owned()
                    } else {
                        declared.join(", ")
                    }
                ),
            )
        })
    }

    /// The binding is labelled as its input's arity asks: a many-input
    /// wired without labels (`responses: icm`) would reach the stage as no
    /// product at all, so it is refused here with the form to write.
    fn check_labels(
        &self,
        spec: &InputSpec,
        binding: &InputBinding,
        line: Option<Location>,
    ) -> Result<(), PipelineError> {
        let name = spec.name;
        if let Some(label) = binding
            .labels
            .iter()
            .find(|l| l.is_empty() || l.contains('.'))
        {
            return Err(self.err(
                line,
                format!("input `{name}`: label `{label}` is empty or holds `.`"),
            ));
        }
        let given = binding.labels.len();
        let wanted = spec.arity.depth();
        if wanted.is_none_or(|d| d == given) && (wanted.is_some() || given < 2) {
            return Ok(());
        }
        let form = match spec.arity {
            Arity::One | Arity::Optional => {
                format!("takes one product, not labelled ones: write `{name}: <stage>`")
            }
            Arity::Many => format!(
                "takes labelled products, one per sample (or mode): write `{name}: {{ T1: <stage>, \
                 T2: <stage> }}`"
            ),
            Arity::OneOrMore => format!(
                "takes one product or labelled ones: write `{name}: <stage>` or `{name}: {{ UT: \
                 <stage>, PT: <stage> }}`"
            ),
            Arity::Nested => format!(
                "takes products labelled by sample and then by model: write `{name}: {{ T1: {{ \
                 icm: <stage>, bem: <stage> }} }}`"
            ),
        };
        Err(self.err(line, format!("input `{name}` {form}")))
    }

    /// The upstream output a binding names (or the one of the input's kind).
    fn output(
        &self,
        spec: &InputSpec,
        binding: &InputBinding,
        upstream: &StageDecl,
        line: Option<Location>,
    ) -> Result<&'static OutputSpec, PipelineError> {
        let up_info = upstream.stage.info();
        let output = match &binding.from_output {
            Some(o) => up_info.output(o).ok_or_else(|| {
                self.err(
                    line,
                    format!(
                        "input `{}`: stage `{}` ({}) has no output `{o}` (its outputs: {})",
                        binding.input,
                        upstream.name,
                        upstream.kind,
                        up_info
                            .outputs
                            .iter()
                            .map(|o| o.name)
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                )
            })?,
            None => up_info
                .output(&binding.declared)
                .or_else(|| up_info.outputs.iter().find(|o| o.kind == spec.kind))
                .ok_or_else(|| {
                    self.err(
                        line,
                        format!(
                            "input `{}`: stage `{}` has no {} output",
                            binding.input, upstream.name, spec.kind
                        ),
                    )
                })?,
        };
        if output.kind != spec.kind {
            return Err(self.err(
                line,
                format!(
                    "input `{}` takes a {}, but `{}.{}` is a {}",
                    binding.input, spec.kind, upstream.name, output.name, output.kind
                ),
            ));
        }
        Ok(output)
    }

    /// The upstream output declares every column the input needs: a
    /// table's columns, or the columns of a files output's index. (A table
    /// output declaring none, a loader's, is checked when read.)
    fn check_columns(
        &self,
        spec: &InputSpec,
        binding: &InputBinding,
        upstream: &str,
        output: &OutputSpec,
        line: Option<Location>,
    ) -> Result<(), PipelineError> {
        if spec.columns.is_empty() {
            return Ok(());
        }
        let what =
            match spec.kind {
                ProductKind::Files if output.columns.is_empty() => {
                    return Err(self.err(
                    line,
                    format!(
                        "input `{}` needs files with an index ({}), and `{upstream}.{}` hands on \
                         none",
                        binding.input,
                        spec.columns.iter().map(|c| c.name).collect::<Vec<_>>().join(", "),
                        output.name
                    ),
                ));
                }
                ProductKind::Files => "whose index",
                ProductKind::Table if output.columns.is_empty() => return Ok(()),
                _ => "which",
            };
        match spec
            .columns
            .iter()
            .find(|c| !output.columns.iter().any(|o| o.name == c.name))
        {
            Some(column) => Err(self.err(
                line,
                format!(
                    "input `{}` needs column `{}`, {what} `{upstream}.{}` does not declare",
                    binding.input, column.name, output.name
                ),
            )),
            None => Ok(()),
        }
    }

    /// Every required input is given, and single inputs at most once.
    fn check_counts(&self, info: &StageInfo) -> Result<(), PipelineError> {
        for spec in info.inputs {
            let given = self
                .decl
                .inputs
                .iter()
                .filter(|b| b.declared == spec.name)
                .count();
            match spec.arity {
                Arity::One | Arity::OneOrMore if given == 0 => {
                    return Err(self.err(
                        None,
                        format!(
                            "missing input `{}` ({}: {}); add `inputs: {{ {}: <stage> }}`",
                            spec.name, spec.kind, spec.doc, spec.name
                        ),
                    ));
                }
                Arity::One | Arity::Optional if given > 1 => {
                    return Err(self.err(
                        None,
                        format!("input `{}` takes at most one product", spec.name),
                    ));
                }
                _ => {}
            }
        }
        Ok(())
    }
}

/// Stage indices in dependency order (YAML order among independent stages),
/// or the cycle.
fn topological_order(pipeline: &Pipeline) -> Result<Vec<usize>, PipelineError> {
    let index: HashMap<&str, usize> = pipeline
        .stages
        .iter()
        .enumerate()
        .map(|(i, s)| (s.name.as_str(), i))
        .collect();
    let n = pipeline.stages.len();
    // 0 = unvisited, 1 = on the stack, 2 = done.
    let mut state = vec![0u8; n];
    let mut order = Vec::with_capacity(n);
    fn visit(
        i: usize,
        pipeline: &Pipeline,
        index: &HashMap<&str, usize>,
        state: &mut [u8],
        order: &mut Vec<usize>,
        stack: &mut Vec<usize>,
    ) -> Result<(), Vec<usize>> {
        match state[i] {
            2 => return Ok(()),
            1 => {
                let start = stack.iter().position(|&s| s == i).unwrap_or(0);
                let mut cycle = stack[start..].to_vec();
                cycle.push(i);
                return Err(cycle);
            }
            _ => {}
        }
        state[i] = 1;
        stack.push(i);
        for binding in &pipeline.stages[i].inputs {
            // Unknown upstream stages are reported when inputs are resolved.
            if let Some(&j) = index.get(binding.from_stage.as_str()) {
                visit(j, pipeline, index, state, order, stack)?;
            }
        }
        stack.pop();
        state[i] = 2;
        order.push(i);
        Ok(())
    }
    for i in 0..n {
        let mut stack = Vec::new();
        visit(i, pipeline, &index, &mut state, &mut order, &mut stack).map_err(|cycle| {
            let names: Vec<&str> = cycle
                .iter()
                .map(|&j| pipeline.stages[j].name.as_str())
                .collect();
            let first = &pipeline.stages[cycle[0]];
            PipelineError::new(
                &pipeline.file,
                format!("the stages form a cycle: {}", names.join(" → ")),
            )
            .at(first.line, None)
            .stage(&first.name)
        })?;
    }
    Ok(order)
}

/// `name` and every stage it depends on: a set, so that asking whether a
/// stage is selected does not scan a list (quadratic over a pipeline of
/// thousands of stages, #50 item 4).
fn ancestors(pipeline: &Pipeline, name: &str) -> HashSet<String> {
    let by_name: HashMap<&str, &StageDecl> = pipeline
        .stages
        .iter()
        .map(|s| (s.name.as_str(), s))
        .collect();
    let mut out = HashSet::from([name.to_owned()]);
    let mut todo = vec![name.to_owned()];
    while let Some(next) = todo.pop() {
        if let Some(decl) = by_name.get(next.as_str()) {
            for b in &decl.inputs {
                if out.insert(b.from_stage.clone()) {
                    todo.push(b.from_stage.clone());
                }
            }
        }
    }
    out
}
