//! Kind names → stage implementations, behind an object-safe facade.

use std::any::Any;
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::{
    Checked, Context, InputPath, Inputs, Outputs, ParamSpec, ParamValue, Params, Stage, StageError,
    StageInfo,
};

/// Checked parameters of some stage kind: the only parameters the runner
/// holds, so the only ones it can hand a stage.
pub trait AnyParams: fmt::Debug + Send + Sync {
    fn as_any(&self) -> &dyn Any;
    /// Canonical form: every field, defaults filled in.
    fn to_json(&self) -> serde_json::Value;
    /// Every input path, with its parameter path (`path`, `files.2`).
    fn input_paths(&self) -> Vec<(String, PathBuf)>;
    fn clone_box(&self) -> Box<dyn AnyParams>;
}

impl<P: Params> AnyParams for Checked<P> {
    fn as_any(&self) -> &dyn Any {
        self
    }

    fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(self).expect("stage parameters serialise to JSON")
    }

    fn input_paths(&self) -> Vec<(String, PathBuf)> {
        let mut copy: P = (**self).clone();
        let mut paths = Vec::new();
        copy.visit_paths("", &mut |param, path| {
            paths.push((param.to_owned(), path.path().to_owned()))
        });
        paths
    }

    fn clone_box(&self) -> Box<dyn AnyParams> {
        Box::new(self.clone())
    }
}

impl Clone for Box<dyn AnyParams> {
    fn clone(&self) -> Self {
        self.clone_box()
    }
}

/// Why parameters could not be made: a value of the wrong shape, or a failed
/// check. `param` is the parameter's path (`weights.UT`), empty for the
/// block as a whole (a missing required key).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}", self.describe())]
pub struct ParamsError {
    pub param: String,
    pub message: String,
    /// True for a failed check, false for a value serde could not read.
    pub failed_check: bool,
}

impl ParamsError {
    fn describe(&self) -> String {
        if self.param.is_empty() {
            self.message.clone()
        } else {
            format!("parameter `{}`: {}", self.param, self.message)
        }
    }
}

/// A stage of any kind, as the runner sees it.
pub trait DynStage: Send + Sync {
    fn info(&self) -> &'static StageInfo;
    /// The kind's default cluster resources ([`Stage::RESOURCES`]).
    fn resources(&self) -> crate::stage::Resources;
    /// The declared parameters.
    fn params_spec(&self) -> Vec<ParamSpec>;
    /// Typed parameters from their JSON form, input paths resolved against
    /// `dir` (the pipeline's folder), checked.
    fn params_from_json(
        &self,
        value: serde_json::Value,
        dir: &Path,
    ) -> Result<Box<dyn AnyParams>, ParamsError>;
    fn run_dyn(
        &self,
        params: &dyn AnyParams,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError>;
    /// [`Stage::let_go`].
    fn let_go(&self);
}

impl<S: Stage> DynStage for S {
    fn info(&self) -> &'static StageInfo {
        Stage::info(self)
    }

    fn let_go(&self) {
        Stage::let_go(self)
    }

    fn resources(&self) -> crate::stage::Resources {
        S::RESOURCES
    }

    fn params_spec(&self) -> Vec<ParamSpec> {
        S::Params::spec()
    }

    fn params_from_json(
        &self,
        value: serde_json::Value,
        dir: &Path,
    ) -> Result<Box<dyn AnyParams>, ParamsError> {
        let mut params: S::Params =
            serde_path_to_error::deserialize(value).map_err(|e| ParamsError {
                param: dotted(e.path()),
                message: crate::param::explain_quoted_number(&e.inner().to_string()),
                failed_check: false,
            })?;
        params.visit_paths("", &mut |_, path: &mut InputPath| path.resolve_against(dir));
        let checked = params.check().map_err(|e| ParamsError {
            param: e.param,
            message: e.message,
            failed_check: true,
        })?;
        Ok(Box::new(checked))
    }

    fn run_dyn(
        &self,
        params: &dyn AnyParams,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let params = params
            .as_any()
            .downcast_ref::<Checked<S::Params>>()
            .expect("the runner passes each stage its own parameter type");
        self.run(params, inputs, ctx)
    }
}

/// `weights.UT`, `files.2`: the parameter path of a deserialisation error.
fn dotted(path: &serde_path_to_error::Path) -> String {
    use serde_path_to_error::Segment;
    path.iter()
        .filter_map(|segment| match segment {
            Segment::Map { key } => Some(key.clone()),
            Segment::Seq { index } => Some(index.to_string()),
            Segment::Enum { variant } => Some(variant.clone()),
            Segment::Unknown => None,
        })
        .collect::<Vec<_>>()
        .join(".")
}

/// Maps the kind names used after `uses:` to implementations.
#[derive(Clone, Default)]
pub struct Registry {
    stages: BTreeMap<&'static str, Arc<dyn DynStage>>,
}

impl Registry {
    pub fn new() -> Self {
        Self::default()
    }

    /// Registers a stage. Two stages with one kind name are a programming
    /// error, caught by every test that builds the registry.
    pub fn add<S: Stage>(&mut self, stage: S) -> &mut Self {
        let kind = Stage::info(&stage).kind;
        let previous = self.stages.insert(kind, Arc::new(stage));
        assert!(previous.is_none(), "stage kind `{kind}` registered twice");
        self
    }

    pub fn get(&self, kind: &str) -> Option<&Arc<dyn DynStage>> {
        self.stages.get(kind)
    }

    pub fn kinds(&self) -> impl Iterator<Item = &'static str> + '_ {
        self.stages.keys().copied()
    }

    pub fn iter(&self) -> impl Iterator<Item = &Arc<dyn DynStage>> {
        self.stages.values()
    }
}
