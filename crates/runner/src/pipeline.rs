//! Reading a pipeline file: YAML → stages with typed, checked parameters.
//!
//! The file is read twice. The first pass checks the structure (`name`,
//! `stages`, `uses`, `with`, `inputs`, `study`) with serde's derive. The second
//! pass walks the same YAML stream again and hands each `with:` block to its
//! stage kind's own parameter type, so a typo or a wrong type is reported at
//! its line and column, never after the fact.

use std::cell::RefCell;
use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use hypercontact_core::{AnyParams, DynStage, Registry};
use indexmap::IndexMap;
use serde::Deserialize;
use serde::de::{self, DeserializeSeed, IgnoredAny, MapAccess, Visitor};

/// A pipeline error: names the file, the line and column where known, and the
/// stage.
#[derive(Debug, Clone, PartialEq)]
pub struct PipelineError {
    pub file: PathBuf,
    pub line: Option<usize>,
    pub column: Option<usize>,
    pub stage: Option<String>,
    pub message: String,
}

impl fmt::Display for PipelineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        match (self.line, self.column) {
            (Some(l), Some(c)) => write!(f, ":{l}:{c}")?,
            (Some(l), None) => write!(f, ":{l}")?,
            _ => {}
        }
        write!(f, ": ")?;
        if let Some(stage) = &self.stage {
            write!(f, "stage `{stage}`: ")?;
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for PipelineError {}

impl PipelineError {
    pub fn new(file: &Path, message: impl Into<String>) -> Self {
        Self {
            file: file.to_owned(),
            line: None,
            column: None,
            stage: None,
            message: message.into(),
        }
    }

    pub fn at(mut self, line: Option<usize>, column: Option<usize>) -> Self {
        self.line = line;
        self.column = column;
        self
    }

    pub fn stage(mut self, stage: &str) -> Self {
        self.stage = Some(stage.to_owned());
        self
    }

    /// From a YAML error: its innermost position, with the position phrases
    /// that nested deserialisers append removed from the message.
    fn from_yaml(file: &Path, err: &impl fmt::Display) -> Self {
        let (message, position) = split_positions(&err.to_string());
        let (line, column) = position.map_or((None, None), |(l, c)| (Some(l), Some(c)));
        Self::new(file, message).at(line, column)
    }
}

/// Removes every " at line L column C" from a message and returns the first
/// (innermost) position.
fn split_positions(message: &str) -> (String, Option<(usize, usize)>) {
    const AT: &str = " at line ";
    let mut clean = String::new();
    let mut first = None;
    let mut rest = message;
    while let Some(i) = rest.find(AT) {
        clean.push_str(&rest[..i]);
        let tail = &rest[i + AT.len()..];
        let line_end = tail
            .find(|c: char| !c.is_ascii_digit())
            .unwrap_or(tail.len());
        let line: Option<usize> = tail[..line_end].parse().ok();
        let after_line = &tail[line_end..];
        let (column, consumed) = match after_line.strip_prefix(" column ") {
            Some(c) => {
                let end = c.find(|ch: char| !ch.is_ascii_digit()).unwrap_or(c.len());
                (c[..end].parse().ok(), line_end + " column ".len() + end)
            }
            None => (None, line_end),
        };
        if first.is_none()
            && let (Some(l), Some(c)) = (line, column)
        {
            first = Some((l, c));
        }
        rest = &tail[consumed..];
    }
    clean.push_str(rest);
    (
        drop_repeated_paths(clean.trim_end_matches(['.', ' '])),
        first,
    )
}

/// Nested deserialisers each prefix the YAML path (`stages.a.with: stages.a.with.x: msg`):
/// keep only the innermost path.
fn drop_repeated_paths(message: &str) -> String {
    let mut rest = message;
    let mut innermost = None;
    while let Some((head, tail)) = rest.split_once(": ") {
        if head.starts_with("stages.") && !head.contains(' ') {
            innermost = Some(head);
            rest = tail;
        } else {
            break;
        }
    }
    match innermost {
        Some(path) => format!("{path}: {rest}"),
        None => rest.to_owned(),
    }
}

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
}

/// A stage as declared in the pipeline.
#[derive(Clone)]
pub struct StageDecl {
    pub name: String,
    pub kind: String,
    pub stage: Arc<dyn DynStage>,
    /// The `with:` block as written, plus `--set` overrides.
    pub raw_params: serde_json::Value,
    /// Typed, checked, with paths resolved against the pipeline's folder.
    pub params: Box<dyn AnyParams>,
    pub inputs: Vec<InputBinding>,
    /// Line of the stage's name in the pipeline file.
    pub line: Option<usize>,
}

impl fmt::Debug for StageDecl {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("StageDecl")
            .field("name", &self.name)
            .field("kind", &self.kind)
            .field("params", &self.params)
            .field("inputs", &self.inputs)
            .finish()
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
    source: String,
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
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStage {
    uses: String,
    #[serde(default)]
    with: Option<yaml_serde::Value>,
    /// A YAML file of parameters (a sample's recipe, say), relative to the
    /// pipeline; keys in `with:` override it.
    #[serde(default)]
    with_file: Option<PathBuf>,
    #[serde(default)]
    inputs: IndexMap<String, RawInput>,
    #[serde(default)]
    #[allow(dead_code)]
    doc: Option<String>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum RawInput {
    One(String),
    Many(IndexMap<String, String>),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStudy {
    #[serde(default)]
    grid: IndexMap<String, Vec<yaml_serde::Value>>,
    #[serde(default)]
    cases: Vec<IndexMap<String, yaml_serde::Value>>,
    #[serde(default)]
    collect: Vec<String>,
}

fn to_json(file: &Path, value: &yaml_serde::Value) -> Result<serde_json::Value, PipelineError> {
    serde_json::to_value(value).map_err(|e| PipelineError::new(file, e.to_string()))
}

impl Pipeline {
    /// Reads and checks a pipeline file against the registry.
    pub fn load(file: &Path, registry: &Registry) -> Result<Self, PipelineError> {
        let source = std::fs::read_to_string(file)
            .map_err(|e| PipelineError::new(file, format!("cannot read the pipeline: {e}")))?;
        Self::parse(file, &source, registry)
    }

    /// Parses pipeline text; `file` names it in errors and anchors paths.
    pub fn parse(file: &Path, source: &str, registry: &Registry) -> Result<Self, PipelineError> {
        let raw: RawPipeline =
            yaml_serde::from_str(source).map_err(|e| PipelineError::from_yaml(file, &e))?;
        let dir = file
            .parent()
            .map(|p| {
                if p.as_os_str().is_empty() {
                    Path::new(".")
                } else {
                    p
                }
            })
            .unwrap_or(Path::new("."))
            .to_owned();

        // Second pass: typed parameters at their line and column.
        let kinds: HashMap<String, String> = raw
            .stages
            .iter()
            .map(|(name, s)| (name.clone(), s.uses.clone()))
            .collect();
        let parsed = RefCell::new(HashMap::new());
        let seed = DocSeed {
            registry,
            kinds: &kinds,
            parsed: &parsed,
        };
        let de = yaml_serde::Deserializer::from_str(source);
        seed.deserialize(de).map_err(|e| {
            let mut err = PipelineError::from_yaml(file, &e);
            let Some(stage) = stage_at_line(source, &raw.stages, err.line) else {
                return err;
            };
            // The stage is named separately; keep only the path inside it.
            if let Some(rest) = err.message.strip_prefix(&format!("stages.{stage}")) {
                err.message = rest.trim_start_matches(['.', ':', ' ']).to_owned();
            }
            // A failed check names its parameter: point at that key's line.
            let checked = err
                .message
                .split_once("parameter `")
                .and_then(|(_, rest)| rest.split_once('`'))
                .map(|(param, _)| param.to_owned());
            if let Some(param) = checked
                && let Some(line) = find_stage_line(source, &stage)
                    .and_then(|start| find_key_line(source, start, &param))
            {
                err = err.at(Some(line), None);
            }
            err.stage(&stage)
        })?;
        let mut parsed = parsed.into_inner();

        let mut stages = Vec::new();
        for (name, rs) in &raw.stages {
            let line = find_stage_line(source, name);
            let locate =
                |message: String| PipelineError::new(file, message).at(line, None).stage(name);
            if name.is_empty() || name.contains(['.', '/', ' ']) {
                return Err(locate(
                    "stage names may not be empty or contain `.`, `/` or spaces".into(),
                ));
            }
            let stage = registry
                .get(&rs.uses)
                .ok_or_else(|| locate(unknown_kind(&rs.uses, registry)))?
                .clone();
            let mut params = parsed
                .remove(name)
                .ok_or_else(|| locate("parameters were not parsed".into()))?;
            let mut raw_params = match &rs.with {
                Some(v) => to_json(file, v)?,
                None => serde_json::Value::Object(Default::default()),
            };
            if let Some(with_file) = &rs.with_file {
                let at_key = || {
                    let key_line = line.and_then(|l| find_key_line(source, l, "with_file"));
                    PipelineError::new(file, String::new())
                        .at(key_line, None)
                        .stage(name)
                };
                let (merged, typed) = params_from_file(
                    &dir.join(with_file),
                    &raw_params,
                    stage.as_ref(),
                )
                .map_err(|e| match e {
                    FileParamsError::Read(message) => PipelineError {
                        message,
                        ..at_key()
                    },
                    FileParamsError::Located(mut e) => {
                        e.message =
                            format!("{} (read by with_file in {})", e.message, file.display());
                        e.stage(name)
                    }
                })?;
                raw_params = merged;
                params = typed;
            }
            resolve_paths(params.as_mut(), &dir);
            let mut inputs = Vec::new();
            for (input, binding) in &rs.inputs {
                let refs: Vec<(String, &str)> = match binding {
                    RawInput::One(r) => vec![(input.clone(), r.as_str())],
                    RawInput::Many(m) => m
                        .iter()
                        .map(|(label, r)| (format!("{input}.{label}"), r.as_str()))
                        .collect(),
                };
                for (seen_as, reference) in refs {
                    let (from_stage, from_output) = match reference.split_once('.') {
                        Some((s, o)) => (s.to_owned(), Some(o.to_owned())),
                        None => (reference.to_owned(), None),
                    };
                    inputs.push(InputBinding {
                        input: seen_as,
                        declared: input.clone(),
                        from_stage,
                        from_output,
                    });
                }
            }
            stages.push(StageDecl {
                name: name.clone(),
                kind: rs.uses.clone(),
                stage,
                raw_params,
                params,
                inputs,
                line,
            });
        }

        let study = match &raw.study {
            None => None,
            Some(s) => Some(StudySpec {
                grid: s
                    .grid
                    .iter()
                    .map(|(k, vs)| {
                        Ok((
                            k.clone(),
                            vs.iter()
                                .map(|v| to_json(file, v))
                                .collect::<Result<_, _>>()?,
                        ))
                    })
                    .collect::<Result<_, PipelineError>>()?,
                cases: s
                    .cases
                    .iter()
                    .map(|case| {
                        case.iter()
                            .map(|(k, v)| Ok((k.clone(), to_json(file, v)?)))
                            .collect::<Result<_, PipelineError>>()
                    })
                    .collect::<Result<_, _>>()?,
                collect: s.collect.clone(),
            }),
        };

        Ok(Pipeline {
            name: raw.name,
            description: raw.description,
            file: file.to_owned(),
            dir,
            stages,
            study,
            source: source.to_owned(),
        })
    }

    pub fn stage(&self, name: &str) -> Option<&StageDecl> {
        self.stages.iter().find(|s| s.name == name)
    }

    /// The pipeline text as read.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The line of `key:` inside a stage's block, for errors about it.
    pub fn key_line(&self, stage: &str, key: &str) -> Option<usize> {
        let start = self.stage(stage)?.line?;
        find_key_line(&self.source, start, key)
    }

    /// Applies `STAGE.PARAM=VALUE` (VALUE read as YAML; PARAM may be a dotted
    /// path into nested parameters) and re-checks the stage's parameters.
    pub fn set(&mut self, assignment: &str) -> Result<(), PipelineError> {
        let file = self.file.clone();
        let err = |message: String| PipelineError::new(&file, message);
        let (path, value) = assignment
            .split_once('=')
            .ok_or_else(|| err(format!("--set `{assignment}`: expected STAGE.PARAM=VALUE")))?;
        let value: yaml_serde::Value = yaml_serde::from_str(value)
            .map_err(|e| err(format!("--set `{assignment}`: the value is not YAML: {e}")))?;
        let value = to_json(&file, &value)?;
        self.set_value(path.trim(), value).map_err(|e| {
            err(format!("--set `{assignment}`: {}", e.message)).stage(&e.stage.unwrap_or_default())
        })
    }

    /// Sets `stage.param[.sub...]` to a JSON value and re-checks.
    pub fn set_value(&mut self, path: &str, value: serde_json::Value) -> Result<(), PipelineError> {
        let file = self.file.clone();
        let dir = self.dir.clone();
        let (stage_name, param_path) = path
            .split_once('.')
            .ok_or_else(|| PipelineError::new(&file, format!("`{path}` should be STAGE.PARAM")))?;
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
            .ok_or_else(|| {
                PipelineError::new(&file, format!("no stage `{stage_name}` (stages: {known})"))
            })?;
        let mut raw = decl.raw_params.clone();
        let mut slot = &mut raw;
        for key in param_path.split('.') {
            if !slot.is_object() {
                *slot = serde_json::Value::Object(Default::default());
            }
            slot = slot
                .as_object_mut()
                .expect("made an object above")
                .entry(key.to_owned())
                .or_insert(serde_json::Value::Null);
        }
        *slot = value;
        let mut params = parse_params(decl.stage.as_ref(), raw.clone())
            .map_err(|m| PipelineError::new(&file, m).stage(stage_name))?;
        resolve_paths(params.as_mut(), &dir);
        decl.raw_params = raw;
        decl.params = params;
        Ok(())
    }
}

enum FileParamsError {
    /// The file cannot be read: reported at the `with_file:` key.
    Read(String),
    /// Bad content: reported in the file itself.
    Located(PipelineError),
}

/// Parameters from a `with_file:` YAML file with the stage's `with:` keys
/// laid over them: the merged JSON and its typed, checked form. Errors in
/// the file's content name the file (and line, where YAML gives one).
fn params_from_file(
    path: &Path,
    inline: &serde_json::Value,
    stage: &dyn DynStage,
) -> Result<(serde_json::Value, Box<dyn AnyParams>), FileParamsError> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        FileParamsError::Read(format!("with_file: cannot read {}: {e}", path.display()))
    })?;
    let value: yaml_serde::Value = yaml_serde::from_str(&text)
        .map_err(|e| FileParamsError::Located(PipelineError::from_yaml(path, &e)))?;
    let mut merged = to_json(path, &value).map_err(FileParamsError::Located)?;
    let Some(base) = merged.as_object_mut() else {
        return Err(FileParamsError::Located(PipelineError::new(
            path,
            "expected a map of parameters",
        )));
    };
    if let Some(over) = inline.as_object() {
        for (k, v) in over {
            base.insert(k.clone(), v.clone());
        }
    }
    let typed = parse_params(stage, merged.clone()).map_err(|message| {
        // A failed check or an unknown key names its parameter: point at it.
        let line = message
            .split('`')
            .nth(1)
            .and_then(|key| {
                text.lines()
                    .position(|l| l.trim_start().starts_with(&format!("{key}:")))
            })
            .map(|i| i + 1);
        FileParamsError::Located(PipelineError::new(path, message).at(line, None))
    })?;
    Ok((merged, typed))
}

/// Typed parameters from a JSON object, checked.
pub fn parse_params(
    stage: &dyn DynStage,
    raw: serde_json::Value,
) -> Result<Box<dyn AnyParams>, String> {
    let mut de = <dyn erased_serde::Deserializer>::erase(raw);
    let params = stage
        .deserialize_params(&mut de)
        .map_err(|e| e.to_string())?;
    params.check().map_err(|e| e.to_string())?;
    Ok(params)
}

fn resolve_paths(params: &mut dyn AnyParams, dir: &Path) {
    for path in params.paths_mut() {
        if !path.as_os_str().is_empty() && path.is_relative() {
            *path = dir.join(&*path);
        }
    }
}

fn unknown_kind(kind: &str, registry: &Registry) -> String {
    let known: Vec<_> = registry.kinds().collect();
    format!(
        "unknown stage kind `{kind}` (known kinds: {}; `hypercontact stages` describes them)",
        known.join(", ")
    )
}

/// The 1-based line where `name:` opens a stage (indented, under `stages:`).
fn find_stage_line(source: &str, name: &str) -> Option<usize> {
    let mut in_stages = false;
    for (i, line) in source.lines().enumerate() {
        let trimmed = line.trim_start();
        if !line.starts_with([' ', '\t']) {
            in_stages = trimmed.starts_with("stages:");
            continue;
        }
        if in_stages {
            let key = trimmed.trim_start_matches(['"', '\'']);
            if let Some(rest) = key.strip_prefix(name)
                && rest.trim_start_matches(['"', '\'']).starts_with(':')
            {
                return Some(i + 1);
            }
        }
    }
    None
}

/// The first line at or after `start` (1-based) whose key is `key`, within
/// the block that `start` opens.
fn find_key_line(source: &str, start: usize, key: &str) -> Option<usize> {
    let lines: Vec<&str> = source.lines().collect();
    let indent = |l: &str| l.len() - l.trim_start().len();
    let base = indent(lines.get(start - 1)?);
    for (i, line) in lines.iter().enumerate().skip(start) {
        if !line.trim().is_empty() && indent(line) <= base && !line.trim_start().starts_with('#') {
            break;
        }
        let t = line.trim_start().trim_start_matches(['{', ' ']);
        if t.starts_with(&format!("{key}:"))
            || line.contains(&format!(" {key}:"))
            || line.contains(&format!("{{{key}:"))
        {
            return Some(i + 1);
        }
    }
    None
}

/// The stage whose block contains `line`.
fn stage_at_line(
    source: &str,
    stages: &IndexMap<String, RawStage>,
    line: Option<usize>,
) -> Option<String> {
    let line = line?;
    stages
        .keys()
        .filter_map(|name| find_stage_line(source, name).map(|l| (l, name)))
        .filter(|(l, _)| *l <= line)
        .max_by_key(|(l, _)| *l)
        .map(|(_, name)| name.clone())
}

// ---- second pass: typed parameters from the YAML stream ----

type Parsed = RefCell<HashMap<String, Box<dyn AnyParams>>>;

struct DocSeed<'a> {
    registry: &'a Registry,
    kinds: &'a HashMap<String, String>,
    parsed: &'a Parsed,
}

impl<'de> DeserializeSeed<'de> for DocSeed<'_> {
    type Value = ();

    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for DocSeed<'_> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a pipeline")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        while let Some(key) = map.next_key::<String>()? {
            if key == "stages" {
                map.next_value_seed(StagesSeed {
                    registry: self.registry,
                    kinds: self.kinds,
                    parsed: self.parsed,
                })?;
            } else {
                map.next_value::<IgnoredAny>()?;
            }
        }
        Ok(())
    }
}

struct StagesSeed<'a> {
    registry: &'a Registry,
    kinds: &'a HashMap<String, String>,
    parsed: &'a Parsed,
}

impl<'de> DeserializeSeed<'de> for StagesSeed<'_> {
    type Value = ();

    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for StagesSeed<'_> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a map of stages")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        while let Some(name) = map.next_key::<String>()? {
            let stage = self
                .kinds
                .get(&name)
                .and_then(|kind| self.registry.get(kind));
            map.next_value_seed(StageSeed {
                name: &name,
                registry: self.registry,
                stage: stage.map(|s| s.as_ref()),
                parsed: self.parsed,
            })?;
        }
        Ok(())
    }
}

struct StageSeed<'a> {
    name: &'a str,
    registry: &'a Registry,
    stage: Option<&'a dyn DynStage>,
    parsed: &'a Parsed,
}

impl<'de> DeserializeSeed<'de> for StageSeed<'_> {
    type Value = ();

    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for StageSeed<'_> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a stage")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let mut params = None;
        while let Some(key) = map.next_key::<String>()? {
            match key.as_str() {
                "uses" => map.next_value_seed(KindSeed(self.registry))?,
                "with" => match self.stage {
                    Some(stage) => params = Some(map.next_value_seed(ParamsSeed(stage))?),
                    None => {
                        map.next_value::<IgnoredAny>()?;
                    }
                },
                _ => {
                    map.next_value::<IgnoredAny>()?;
                }
            }
        }
        if let Some(stage) = self.stage {
            let params = match params {
                Some(p) => p,
                None => parse_params(stage, serde_json::Value::Object(Default::default()))
                    .map_err(de::Error::custom)?,
            };
            self.parsed
                .borrow_mut()
                .insert(self.name.to_owned(), params);
        }
        Ok(())
    }
}

/// Checks a `uses:` value against the registry, at its position.
struct KindSeed<'a>(&'a Registry);

impl<'de> DeserializeSeed<'de> for KindSeed<'_> {
    type Value = ();

    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        let kind = String::deserialize(d)?;
        if self.0.get(&kind).is_none() {
            return Err(de::Error::custom(unknown_kind(&kind, self.0)));
        }
        Ok(())
    }
}

/// Deserialises a `with:` block into the kind's parameter type and checks it.
struct ParamsSeed<'a>(&'a dyn DynStage);

impl<'de> DeserializeSeed<'de> for ParamsSeed<'_> {
    type Value = Box<dyn AnyParams>;

    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        let mut erased = <dyn erased_serde::Deserializer>::erase(d);
        let params = self
            .0
            .deserialize_params(&mut erased)
            .map_err(de::Error::custom)?;
        params.check().map_err(de::Error::custom)?;
        Ok(params)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_are_split_from_messages() {
        let (m, p) = split_positions(
            "stages.t.with: unknown field `levls` at line 9 column 7 at line 8 column 5",
        );
        assert_eq!(m, "stages.t.with: unknown field `levls`");
        let (m, _) = split_positions(
            "stages.t.with: stages.t.with.model: stages.t.with.model: unknown variant",
        );
        assert_eq!(m, "stages.t.with.model: unknown variant");
        assert_eq!(p, Some((9, 7)));
        assert_eq!(split_positions("plain"), ("plain".into(), None));
    }

    #[test]
    fn stage_lines_are_found() {
        let src = "name: x\nstages:\n  a:\n    uses: k\n  b:\n    uses: k\n";
        assert_eq!(find_stage_line(src, "b"), Some(5));
        assert_eq!(find_key_line(src, 3, "uses"), Some(4));
    }
}
