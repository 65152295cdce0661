//! A stage's parameters from where a pipeline gives them — a `with_file:`
//! recipe, the `with:` block over it, `--set` (or a study's values) over
//! both — typed and checked by the stage's declaration, with every error
//! placed where the failing parameter was given.

use std::path::{Path, PathBuf};

use hypercontact_core::{AnyParams, DynStage};

use crate::error::PipelineError;
use crate::yaml::{Located, Location};

#[derive(Clone, Debug)]
pub(crate) struct ParamSources {
    pipeline: PathBuf,
    /// The `with:` block, its key locations relative to it.
    with: Located,
    /// Where the `with:` key is (or the stage, when it has none).
    with_at: Option<Location>,
    /// The `with_file:` recipe: its path and content.
    file: Option<(PathBuf, Located)>,
    /// Values set from the command line or a study, by parameter path, with
    /// who set them (`--set \`a.b=1\``) for messages.
    sets: Vec<(Vec<String>, serde_json::Value, String)>,
}

impl ParamSources {
    pub fn new(
        pipeline: &Path,
        with: Located,
        with_at: Option<Location>,
        file: Option<(PathBuf, Located)>,
    ) -> Self {
        Self {
            pipeline: pipeline.to_owned(),
            with,
            with_at,
            file,
            sets: Vec::new(),
        }
    }

    /// Sets the parameter at `path` (nested keys allowed), over the rest.
    pub fn set(&mut self, path: Vec<String>, value: serde_json::Value, origin: &str) {
        self.sets.retain(|(p, _, _)| *p != path);
        self.sets.push((path, value, origin.to_owned()));
    }

    /// The parameters as given: the recipe, `with:` keys over it, then the
    /// set values.
    pub fn merged(&self) -> serde_json::Value {
        use serde_json::Value;
        let mut merged = match &self.file {
            Some((_, recipe)) if recipe.value.is_object() => recipe.value.clone(),
            _ => Value::Object(Default::default()),
        };
        if let (Some(base), Some(over)) = (merged.as_object_mut(), self.with.value.as_object()) {
            for (k, v) in over {
                base.insert(k.clone(), v.clone());
            }
        }
        for (path, value, _) in &self.sets {
            let mut slot = &mut merged;
            for key in path {
                if !slot.is_object() {
                    *slot = Value::Object(Default::default());
                }
                slot = slot
                    .as_object_mut()
                    .expect("made an object above")
                    .entry(key.clone())
                    .or_insert(Value::Null);
            }
            *slot = value.clone();
        }
        merged
    }

    /// The merged parameters and their typed, checked form.
    pub fn parse(
        &self,
        stage: &dyn DynStage,
        dir: &Path,
        name: &str,
    ) -> Result<(serde_json::Value, Box<dyn AnyParams>), PipelineError> {
        let merged = self.merged();
        let params = stage
            .params_from_json(merged.clone(), dir)
            .map_err(|e| self.error(&e.param, e.to_string()).stage(name))?;
        Ok((merged, params))
    }

    /// An error about parameter `param` (dotted path; empty for the block),
    /// placed where it was given.
    pub fn error(&self, param: &str, message: String) -> PipelineError {
        let path: Vec<&str> = if param.is_empty() {
            Vec::new()
        } else {
            param.split('.').collect()
        };
        let related = |set: &[String]| {
            !path.is_empty()
                && set
                    .iter()
                    .map(String::as_str)
                    .zip(&path)
                    .all(|(a, b)| a == *b)
        };
        // Whoever set it (`--set`, a study) names the assignment.
        if let Some((_, _, origin)) = self.sets.iter().rev().find(|(set, _, _)| related(set)) {
            return PipelineError::new(&self.pipeline, format!("{origin}: {message}"));
        }
        let given_in = |doc: &Located| {
            path.first()
                .is_some_and(|top| doc.value.get(*top).is_some())
        };
        if given_in(&self.with) {
            return PipelineError::new(&self.pipeline, message).located(self.with.locate(&path));
        }
        if let Some((file, recipe)) = &self.file
            && given_in(recipe)
        {
            return PipelineError::new(
                file,
                format!(
                    "{message} (read by with_file in {})",
                    self.pipeline.display()
                ),
            )
            .located(recipe.locate(&path));
        }
        PipelineError::new(&self.pipeline, message).located(self.with_at)
    }
}
