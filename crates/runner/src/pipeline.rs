//! A pipeline file: its stages, their inputs and its study, read once from
//! YAML with the location of every key. The structure is checked by serde
//! (unknown keys are errors), each stage's parameters by its own declared
//! type ([`crate::stage_params`]); every error is placed by the path serde
//! or the check reports, looked up in the file's key locations.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use hypercontact_core::regular_file::{MIB, read_checked_text};
use hypercontact_core::{AnyParams, DynStage, Registry};
use indexmap::IndexMap;
use serde::Deserialize;

pub use crate::error::PipelineError;
use crate::slurm::SlurmKeys;
use crate::stage_params::ParamSources;
use crate::yaml::{Located, Location};

/// The largest pipeline or `with_file` recipe read: hand-written YAML is a
/// few kilobytes; a file of this size is a mistake, not a pipeline.
pub const PIPELINE_LIMIT_BYTES: u64 = 16 * MIB;

/// One input of a stage bound to an upstream product.
#[derive(Clone, Debug, PartialEq)]
pub struct InputBinding {
    /// What the stage sees: `surface`, or `responses.T1` for a many-input.
    pub input: String,
    /// The declared input it fills (`surface`, `responses`).
    pub declared: String,
    /// Upstream stage name.
    pub from_stage: String,
    /// Upstream output name, if given as `stage.output`.
    pub from_output: Option<String>,
    /// The labels the wiring gives it: none (`surface: surf`), one
    /// (`responses: { T1: icm1 }`) or two (`responses: { T1: { icm: a } }`);
    /// the plan holds them against the input's [`hypercontact_core::Arity`].
    pub labels: Vec<String>,
}

/// A stage as declared in the pipeline.
#[derive(Clone)]
pub struct StageDecl {
    pub name: String,
    pub kind: String,
    pub stage: Arc<dyn DynStage>,
    /// The parameters as given: `with_file:`, `with:` over it, then `--set`.
    pub raw_params: serde_json::Value,
    /// Typed, checked, with paths resolved against the pipeline's folder.
    pub params: Box<dyn AnyParams>,
    pub inputs: Vec<InputBinding>,
    /// Line of the stage's name in the pipeline file.
    pub line: Option<usize>,
    /// `temp: true`: the entry is dropped once every stage that reads it has
    /// its own entry, and recomputed from its key if a later run needs it
    /// (Snakemake's temporary files); its outputs are not exported.
    pub temp: bool,
    /// `slurm:`: this stage's job resources under `--executor slurm`.
    pub slurm: SlurmKeys,
    pub(crate) sources: ParamSources,
}

impl std::fmt::Debug for StageDecl {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StageDecl")
            .field("name", &self.name)
            .field("kind", &self.kind)
            .field("params", &self.params)
            .field("inputs", &self.inputs)
            .finish()
    }
}

impl StageDecl {
    /// An error about parameter `param` (a path, `weights.UT`), placed where
    /// that parameter was given: the pipeline, the `with_file:` recipe or
    /// the command line.
    pub fn param_error(&self, param: &str, message: String) -> PipelineError {
        self.sources.error(param, message).stage(&self.name)
    }
}

/// A parameter sweep over a pipeline.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StudySpec {
    /// Cartesian product: `stage.param` → values.
    pub grid: IndexMap<String, Vec<serde_json::Value>>,
    /// Explicit variants, each a set of `stage.param` → value.
    pub cases: Vec<IndexMap<String, serde_json::Value>>,
    /// Table outputs (`stage.output`) gathered into one table per output.
    pub collect: Vec<String>,
    /// `max_variants:`, the most variants the study may have (default
    /// [`DEFAULT_MAX_VARIANTS`]); checked when the pipeline is read, before
    /// any variant is enumerated.
    pub max_variants: Option<u64>,
}

/// The most variants a study has unless its `max_variants:` says more:
/// each variant is planned and kept in memory (a few kilobytes each).
pub const DEFAULT_MAX_VARIANTS: u64 = 100_000;

impl StudySpec {
    /// How many variants the study has: the number of cases (one if none)
    /// times the product of the grid's axis lengths, computed from the
    /// lengths alone; None past `u128`.
    pub fn count(&self) -> Option<u128> {
        (self.grid.values()).try_fold(self.cases.len().max(1) as u128, |n, values| {
            n.checked_mul(values.len() as u128)
        })
    }

    /// The study's shape as the refusal names it: `3 cases × grid 10 × 10`.
    fn shape(&self) -> String {
        let axes: Vec<String> = self.grid.values().map(|v| v.len().to_string()).collect();
        let cases = match self.cases.len() {
            0 => None,
            1 => Some("1 case".to_owned()),
            n => Some(format!("{n} cases")),
        };
        let grid = (!axes.is_empty()).then(|| format!("grid {}", axes.join(" × ")));
        cases
            .into_iter()
            .chain(grid)
            .collect::<Vec<_>>()
            .join(" × ")
    }
}

/// A parsed, checked pipeline.
#[derive(Clone, Debug)]
pub struct Pipeline {
    pub name: String,
    pub description: Option<String>,
    /// The pipeline file as given.
    pub file: PathBuf,
    /// Its folder: relative paths in parameters resolve against it.
    pub dir: PathBuf,
    pub stages: Vec<StageDecl>,
    pub study: Option<StudySpec>,
    /// `slurm:` at the top: job resources for every stage under
    /// `--executor slurm` (a stage's own `slurm:` overrides them).
    pub slurm: SlurmKeys,
    /// The text, its BLAKE3 and its key locations are shared by every
    /// copy (a study's variants), so a copy costs the stages, not the
    /// file: planning N variants of a file that lists N values stays
    /// linear in N (issue #50, item 3).
    source: Arc<str>,
    source_blake3: Arc<str>,
    doc: Arc<Located>,
    /// Stage name → position in `stages` as parsed, for [`Pipeline::stage`]
    /// (a scan per lookup made planning quadratic, #50 item 4). `stages`
    /// is public, so a hit is checked against it and a miss scans.
    index: Arc<HashMap<String, usize>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPipeline {
    name: String,
    #[serde(default)]
    description: Option<String>,
    stages: IndexMap<String, RawStage>,
    #[serde(default)]
    study: Option<RawStudy>,
    #[serde(default)]
    slurm: SlurmKeys,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStage {
    uses: String,
    #[serde(default)]
    with: Option<serde_json::Value>,
    /// A YAML file of parameters (a sample's recipe, say), relative to the
    /// pipeline; keys in `with:` override it.
    #[serde(default)]
    with_file: Option<PathBuf>,
    #[serde(default)]
    inputs: IndexMap<String, RawInput>,
    #[serde(default)]
    temp: bool,
    #[serde(default)]
    slurm: SlurmKeys,
    /// Free text for the reader of the pipeline.
    #[serde(default, rename = "doc")]
    _doc: Option<String>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum RawInput {
    One(String),
    Many(IndexMap<String, String>),
    Nested(IndexMap<String, IndexMap<String, String>>),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStudy {
    #[serde(default)]
    grid: IndexMap<String, Vec<serde_json::Value>>,
    #[serde(default)]
    cases: Vec<IndexMap<String, serde_json::Value>>,
    #[serde(default)]
    collect: Vec<String>,
    #[serde(default)]
    max_variants: Option<u64>,
}

/// Deserialises `value` as `T`, or the error placed at the path serde
/// reports, with the stage it concerns when the path is inside one.
pub(crate) fn located_deserialize<T: serde::de::DeserializeOwned>(
    file: &Path,
    doc: &Located,
    value: serde_json::Value,
) -> Result<T, PipelineError> {
    serde_path_to_error::deserialize(value).map_err(|e| {
        let path: Vec<String> = e.path().iter().filter_map(segment).collect();
        let message = e.inner().to_string();
        match path.as_slice() {
            [stages, stage, ..] if stages == "stages" => {
                PipelineError::new(file, message).stage(stage)
            }
            // Outside the stages, name the key the value belongs to (unless
            // the message does: "unknown field `stagse`").
            [] => PipelineError::new(file, message),
            [.., last] if message.contains(&format!("`{last}`")) => {
                PipelineError::new(file, message)
            }
            _ => PipelineError::new(file, format!("`{}`: {message}", path.join("."))),
        }
        .located(doc.locate(&path))
    })
}

pub(crate) fn segment(s: &serde_path_to_error::Segment) -> Option<String> {
    use serde_path_to_error::Segment;
    match s {
        Segment::Map { key } => Some(key.clone()),
        Segment::Seq { index } => Some(index.to_string()),
        Segment::Enum { variant } => Some(variant.clone()),
        Segment::Unknown => None,
    }
}

impl Pipeline {
    /// Reads and checks a pipeline file against the registry.
    pub fn load(file: &Path, registry: &Registry) -> Result<Self, PipelineError> {
        let source =
            read_checked_text(file, "pipeline files", PIPELINE_LIMIT_BYTES).map_err(|e| {
                PipelineError::new(file, format!("cannot read the pipeline: it {}", e.why))
            })?;
        Self::parse(file, &source, registry)
    }

    /// A pipeline file with `STAGE.PARAM=VALUE` assignments (`--set`)
    /// applied in order: what `hypercontact run` and the Python package run.
    pub fn load_with_sets(
        file: &Path,
        sets: &[String],
        registry: &Registry,
    ) -> Result<Self, PipelineError> {
        let mut pipeline = Self::load(file, registry)?;
        for assignment in sets {
            pipeline.set(assignment)?;
        }
        Ok(pipeline)
    }

    /// Parses pipeline text; `file` names it in errors and anchors paths.
    pub fn parse(file: &Path, source: &str, registry: &Registry) -> Result<Self, PipelineError> {
        let doc = parse_document(file, source)?;
        let raw: RawPipeline = located_deserialize(file, &doc, doc.value.clone())?;
        // The name becomes the default output folder `runs/<name>`: a name
        // that is a path (`../../x`) would write elsewhere.
        if let Err(why) = check_name(&raw.name) {
            return Err(
                PipelineError::new(file, format!("pipeline name `{}` {why}", raw.name))
                    .located(doc.locate(&["name"])),
            );
        }
        if raw.stages.is_empty() {
            return Err(PipelineError::new(file, "the pipeline has no stages")
                .located(doc.locate(&["stages"])));
        }
        let dir = match file.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_owned(),
            _ => PathBuf::from("."),
        };
        let stages = raw
            .stages
            .iter()
            .map(|(name, rs)| {
                let site = StageSite {
                    file,
                    dir: &dir,
                    doc: &doc,
                    name,
                };
                site.declare(rs, registry)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let study = study_spec(file, &doc, raw.study)?;
        let index = (stages.iter().enumerate())
            .map(|(i, s): (usize, &StageDecl)| (s.name.clone(), i))
            .collect();
        Ok(Pipeline {
            name: raw.name,
            description: raw.description,
            file: file.to_owned(),
            dir,
            stages,
            study,
            slurm: raw.slurm,
            source: source.into(),
            source_blake3: crate::hash::text_hash(source).into(),
            doc: Arc::new(doc),
            index: Arc::new(index),
        })
    }

    pub fn stage(&self, name: &str) -> Option<&StageDecl> {
        let indexed = (self.index.get(name))
            .and_then(|&i| self.stages.get(i))
            .filter(|s| s.name == name);
        indexed.or_else(|| self.stages.iter().find(|s| s.name == name))
    }

    /// The pipeline text as read.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The BLAKE3 of the pipeline text, as provenance records it.
    pub fn source_blake3(&self) -> &str {
        &self.source_blake3
    }

    /// The location of a key of the pipeline file (`["stages", "icm",
    /// "inputs", "profile"]`), or of the nearest enclosing one.
    pub fn locate<S: AsRef<str>>(&self, path: &[S]) -> Option<Location> {
        self.doc.locate(path)
    }

    /// Applies `STAGE.PARAM=VALUE` (VALUE read as YAML; PARAM may be a dotted
    /// path into nested parameters) and re-checks the stage's parameters.
    pub fn set(&mut self, assignment: &str) -> Result<(), PipelineError> {
        let file = self.file.clone();
        let err = |message: String| PipelineError::new(&file, message);
        let (path, text) = assignment
            .split_once('=')
            .ok_or_else(|| err(format!("--set `{assignment}`: expected STAGE.PARAM=VALUE")))?;
        let value = Located::parse(text)
            .map_err(|e| {
                err(format!(
                    "--set `{assignment}`: the value is not YAML: {}",
                    e.message
                ))
            })?
            .value;
        self.set_value(path.trim(), value, &format!("--set `{assignment}`"))
    }

    /// Sets `stage.param[.sub...]` to a JSON value and re-checks; `origin`
    /// (`--set \`a.b=1\``, a study variant) prefixes every message about it,
    /// now or when the plan reads its files.
    pub fn set_value(
        &mut self,
        path: &str,
        value: serde_json::Value,
        origin: &str,
    ) -> Result<(), PipelineError> {
        let file = self.file.clone();
        let dir = self.dir.clone();
        let err = |message: String| PipelineError::new(&file, format!("{origin}: {message}"));
        if path.is_empty() {
            return Err(err("give STAGE.PARAM before `=`".into()));
        }
        let (stage_name, param_path) = path
            .split_once('.')
            .filter(|(stage, param)| {
                !stage.is_empty() && !param.is_empty() && param.split('.').all(|p| !p.is_empty())
            })
            .ok_or_else(|| {
                err(format!(
                    "`{path}` should be STAGE.PARAM (names not empty; PARAM may be dotted)"
                ))
            })?;
        let known = self
            .stages
            .iter()
            .map(|s| s.name.as_str())
            .collect::<Vec<_>>()
            .join(", ");
        let decl = self
            .stages
            .iter_mut()
            .find(|s| s.name == stage_name)
            .ok_or_else(|| err(format!("no stage `{stage_name}` (stages: {known})")))?;
        let mut sources = decl.sources.clone();
        sources.set(
            param_path.split('.').map(str::to_owned).collect(),
            value,
            origin,
        );
        let (raw_params, params) = sources.parse(decl.stage.as_ref(), &dir, stage_name)?;
        decl.sources = sources;
        decl.raw_params = raw_params;
        decl.params = params;
        Ok(())
    }
}

/// The YAML of a pipeline file with the location of every key; a map.
fn parse_document(file: &Path, source: &str) -> Result<Located, PipelineError> {
    let doc =
        Located::parse(source).map_err(|e| PipelineError::new(file, e.message).located(e.at))?;
    let found = match &doc.value {
        serde_json::Value::Object(_) => None,
        serde_json::Value::Null => Some("nothing"),
        serde_json::Value::Array(_) => Some("a list"),
        serde_json::Value::String(_) => Some("text"),
        serde_json::Value::Number(_) => Some("a number"),
        serde_json::Value::Bool(_) => Some("a boolean"),
    };
    match found {
        Some(found) => Err(PipelineError::new(
            file,
            format!("a pipeline is a map with `name:` and `stages:`; the file holds {found}"),
        )),
        None => Ok(doc),
    }
}

/// Where a stage is declared: in which file, under which name; every
/// message about the stage is placed by it.
struct StageSite<'a> {
    file: &'a Path,
    /// The pipeline's folder: `with_file:` and paths resolve against it.
    dir: &'a Path,
    doc: &'a Located,
    name: &'a str,
}

impl StageSite<'_> {
    /// The location of a key of the stage (`["with"]`; `[]`: its name).
    fn at(&self, key: &[&str]) -> Option<Location> {
        let mut path = vec!["stages", self.name];
        path.extend_from_slice(key);
        self.doc.locate(&path)
    }

    fn error(&self, message: String, at: Option<Location>) -> PipelineError {
        PipelineError::new(self.file, message)
            .located(at)
            .stage(self.name)
    }

    /// The stage as declared: its kind from the registry, its parameters
    /// (`with_file:`, then `with:` over it) typed and checked, its inputs.
    fn declare(&self, rs: &RawStage, registry: &Registry) -> Result<StageDecl, PipelineError> {
        let name = self.name;
        if let Err(why) = check_name(name) {
            return Err(self.error(format!("the stage name {why}"), self.at(&[])));
        }
        let stage = registry
            .get(&rs.uses)
            .ok_or_else(|| self.error(unknown_kind(&rs.uses, registry), self.at(&["uses"])))?
            .clone();
        let with = self.doc.sub(&["stages", name, "with"]);
        if rs
            .with
            .as_ref()
            .is_some_and(|w| !w.is_object() && !w.is_null())
        {
            return Err(self.error(
                "`with:` must be a map of parameters".into(),
                self.at(&["with"]),
            ));
        }
        let file_params = match &rs.with_file {
            None => None,
            Some(with_file) => Some(self.read_with_file(with_file)?),
        };
        let with_at = self.at(&["with"]).or(self.at(&[]));
        let sources = ParamSources::new(self.file, with, with_at, file_params);
        let (raw_params, params) = sources.parse(stage.as_ref(), self.dir, name)?;
        Ok(StageDecl {
            name: name.to_owned(),
            kind: rs.uses.clone(),
            stage,
            raw_params,
            params,
            inputs: bindings(&rs.inputs),
            line: self.at(&[]).map(|l| l.line),
            temp: rs.temp,
            slurm: rs.slurm.clone(),
            sources,
        })
    }

    /// The `with_file:` recipe, a YAML map of parameters, with its path.
    fn read_with_file(&self, with_file: &Path) -> Result<(PathBuf, Located), PipelineError> {
        let path = self.dir.join(with_file);
        let text =
            read_checked_text(&path, "with_file recipes", PIPELINE_LIMIT_BYTES).map_err(|e| {
                self.error(
                    format!("with_file: cannot read {}: it {}", path.display(), e.why),
                    self.at(&["with_file"]),
                )
            })?;
        let recipe = Located::parse(&text).map_err(|e| {
            PipelineError::new(&path, e.message)
                .located(e.at)
                .stage(self.name)
        })?;
        if !recipe.value.is_object() && !recipe.value.is_null() {
            return Err(PipelineError::new(&path, "expected a map of parameters").stage(self.name));
        }
        Ok((path, recipe))
    }
}

/// The `study:` section, once every grid parameter lists a value.
fn study_spec(
    file: &Path,
    doc: &Located,
    raw: Option<RawStudy>,
) -> Result<Option<StudySpec>, PipelineError> {
    let Some(study) = raw else {
        return Ok(None);
    };
    if let Some((param, _)) = study.grid.iter().find(|(_, values)| values.is_empty()) {
        return Err(PipelineError::new(
            file,
            format!("study.grid `{param}` lists no values (a grid needs at least one)"),
        )
        .located(doc.locate(&["study", "grid", param.as_str()])));
    }
    let spec = StudySpec {
        grid: study.grid,
        cases: study.cases,
        collect: study.collect,
        max_variants: study.max_variants,
    };
    check_study_size(&spec).map_err(|message| {
        let key = if spec.grid.is_empty() {
            "cases"
        } else {
            "grid"
        };
        PipelineError::new(file, message).located(doc.locate(&["study", key]))
    })?;
    Ok(Some(spec))
}

/// Refuses a study of more variants than its limit, from the axis lengths
/// alone (a grid of 10^8 variants is never enumerated), naming the count
/// and the key that raises the limit.
fn check_study_size(spec: &StudySpec) -> Result<(), String> {
    let limit = spec.max_variants.unwrap_or(DEFAULT_MAX_VARIANTS);
    let count = spec.count();
    if count.is_some_and(|n| n <= u128::from(limit)) {
        return Ok(());
    }
    let (count, raise) = match count {
        Some(n) => (n.to_string(), format!("`max_variants: {n}`")),
        None => ("more than 3.4e38".to_owned(), "`max_variants:`".to_owned()),
    };
    let default = match spec.max_variants {
        Some(_) => "",
        None => ", the default",
    };
    Err(format!(
        "study: {count} variants ({}), more than the limit of {limit} (`study.max_variants`\
         {default}); narrow the study, or raise the limit with {raise} under `study:`",
        spec.shape()
    ))
}

fn bindings(inputs: &IndexMap<String, RawInput>) -> Vec<InputBinding> {
    let mut out = Vec::new();
    for (input, binding) in inputs {
        let refs: Vec<(Vec<String>, &str)> = match binding {
            RawInput::One(r) => vec![(Vec::new(), r.as_str())],
            RawInput::Many(m) => m
                .iter()
                .map(|(label, r)| (vec![label.clone()], r.as_str()))
                .collect(),
            RawInput::Nested(m) => m
                .iter()
                .flat_map(|(sample, models)| {
                    models
                        .iter()
                        .map(move |(model, r)| (vec![sample.clone(), model.clone()], r.as_str()))
                })
                .collect(),
        };
        for (labels, reference) in refs {
            let seen_as = std::iter::once(input.as_str())
                .chain(labels.iter().map(String::as_str))
                .collect::<Vec<_>>()
                .join(".");
            let (from_stage, from_output) = match reference.split_once('.') {
                Some((s, o)) => (s.to_owned(), Some(o.to_owned())),
                None => (reference.to_owned(), None),
            };
            out.push(InputBinding {
                input: seen_as,
                declared: input.clone(),
                from_stage,
                from_output,
                labels,
            });
        }
    }
    out
}

/// Pipeline and stage names become folder names and `stage.output`
/// references: letters, digits, `-` and `_` only.
fn check_name(name: &str) -> Result<(), &'static str> {
    if name.is_empty() {
        Err("is empty")
    } else if name.chars().count() > hypercontact_core::shown::ECHO_MAX_CHARS {
        Err("is longer than 100 characters")
    } else if !name
        .chars()
        .all(|c| c.is_alphanumeric() || c == '-' || c == '_')
    {
        Err("may hold only letters, digits, `-` and `_`")
    } else {
        Ok(())
    }
}

fn unknown_kind(kind: &str, registry: &Registry) -> String {
    let known: Vec<_> = registry.kinds().collect();
    format!(
        "unknown stage kind `{kind}` (known kinds: {}; `hypercontact stages` describes them)",
        known.join(", ")
    )
}
