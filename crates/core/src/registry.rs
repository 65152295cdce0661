//! Kind names → stage implementations, behind an object-safe facade.

use std::any::Any;
use std::collections::BTreeMap;
use std::fmt;
use std::path::PathBuf;
use std::sync::Arc;

use crate::{Context, Inputs, Outputs, ParamError, Params, Stage, StageError, StageInfo};

/// Type-erased parameters of some stage kind.
pub trait AnyParams: fmt::Debug + Send + Sync {
    fn as_any(&self) -> &dyn Any;
    /// Canonical form: every field, defaults filled in, keys sorted.
    fn to_json(&self) -> serde_json::Value;
    fn check(&self) -> Result<(), ParamError>;
    fn paths_mut(&mut self) -> Vec<&mut PathBuf>;
    fn clone_box(&self) -> Box<dyn AnyParams>;
}

impl<P: Params> AnyParams for P {
    fn as_any(&self) -> &dyn Any {
        self
    }

    fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(self).expect("stage parameters serialise to JSON")
    }

    fn check(&self) -> Result<(), ParamError> {
        Params::check(self)
    }

    fn paths_mut(&mut self) -> Vec<&mut PathBuf> {
        Params::paths_mut(self)
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

/// A stage of any kind, as the runner sees it.
pub trait DynStage: Send + Sync {
    fn info(&self) -> &'static StageInfo;
    fn default_params(&self) -> serde_json::Value;
    /// Deserialises this kind's parameters from any serde source: the YAML
    /// stream (so errors carry line and column) or a JSON value.
    fn deserialize_params(
        &self,
        de: &mut dyn erased_serde::Deserializer<'_>,
    ) -> Result<Box<dyn AnyParams>, erased_serde::Error>;
    fn run_dyn(
        &self,
        params: &dyn AnyParams,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError>;
}

impl<S: Stage> DynStage for S {
    fn info(&self) -> &'static StageInfo {
        Stage::info(self)
    }

    fn default_params(&self) -> serde_json::Value {
        S::Params::default().to_json()
    }

    fn deserialize_params(
        &self,
        de: &mut dyn erased_serde::Deserializer<'_>,
    ) -> Result<Box<dyn AnyParams>, erased_serde::Error> {
        let params: S::Params = erased_serde::deserialize(de)?;
        Ok(Box::new(params))
    }

    fn run_dyn(
        &self,
        params: &dyn AnyParams,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let params = params
            .as_any()
            .downcast_ref::<S::Params>()
            .expect("the runner passes each stage its own parameter type");
        self.run(params, inputs, ctx)
    }
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
