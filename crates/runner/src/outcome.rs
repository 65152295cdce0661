//! A run that keeps going past a failed stage: which stages failed and
//! why, which were not run because they read a failed one, and how the
//! summary and the error say so.
//!
//! Keeping going is the default (`--fail-fast` stops at the first
//! failure): every stage that does not read a failed one, directly or
//! through others, still runs and is cached and exported, as the Slurm
//! executor's jobs do (Snakemake's and make's `--keep-going`).

use crate::exec::{RunError, RunReport};
use crate::pipeline::PipelineError;
use crate::plan::PlannedStage;

/// A stage that failed in this run.
#[derive(Clone, Debug, PartialEq)]
pub struct StageFailure {
    pub stage: String,
    pub kind: String,
    /// The cache key it failed on (a study does not compute it again).
    pub key: String,
    /// The error with every cause, on one line.
    pub cause: String,
    /// How long it ran before failing, seconds (0 for an entry that
    /// failed in an earlier variant and is not run again).
    pub wall_s: f64,
}

/// A stage not run because a stage it reads failed.
#[derive(Clone, Debug, PartialEq)]
pub struct Blocked {
    pub stage: String,
    /// The failed stage upstream of it.
    pub because: String,
}

impl StageFailure {
    /// `planned` failed with `error` after `wall_s` seconds.
    pub fn new(planned: &PlannedStage, error: &RunError, wall_s: f64) -> Self {
        Self {
            stage: planned.name.clone(),
            kind: planned.kind.clone(),
            key: planned.key.clone(),
            cause: match error {
                // The list names the stage and kind already.
                RunError::Stage { cause, .. } => {
                    crate::error::said_once(crate::error::chain(cause.as_ref()))
                }
                other => crate::error::said_once(crate::error::chain(other)),
            },
            wall_s,
        }
    }

    /// `planned` failed at planning: an input file of it cannot be read.
    pub fn unreadable(planned: &PlannedStage, error: &PipelineError) -> Self {
        // The list names the stage and kind already: the cause keeps the
        // file, line, column and parameter.
        let cause = PipelineError {
            stage: None,
            ..error.clone()
        };
        Self {
            stage: planned.name.clone(),
            kind: planned.kind.clone(),
            key: planned.key.clone(),
            cause: cause.to_string(),
            wall_s: 0.0,
        }
    }

    /// `planned`'s entry failed earlier in this invocation with `cause`.
    pub fn earlier(planned: &PlannedStage, cause: &str) -> Self {
        Self {
            stage: planned.name.clone(),
            kind: planned.kind.clone(),
            key: planned.key.clone(),
            cause: format!("{cause} (the same entry failed in an earlier variant; not run again)"),
            wall_s: 0.0,
        }
    }
}

/// The failed stage that `planned` waits on, if one of its inputs failed
/// or was itself not run because of one.
pub fn blocked_by(
    planned: &PlannedStage,
    failures: &[StageFailure],
    blocked: &[Blocked],
) -> Option<String> {
    planned.inputs.iter().find_map(|input| {
        let from = input.from_stage.as_str();
        if failures.iter().any(|f| f.stage == from) {
            Some(from.to_owned())
        } else {
            (blocked.iter())
                .find(|b| b.stage == from)
                .map(|b| b.because.clone())
        }
    })
}

impl RunReport {
    /// The summary line of a stage that failed or was not run.
    pub(crate) fn not_run_line(&self, stage: &str, kind: &str) -> Option<String> {
        let (status, why) = if self.failures.iter().any(|f| f.stage == stage) {
            ("FAILED", String::from("(see below)"))
        } else {
            let b = self.blocked.iter().find(|b| b.stage == stage)?;
            ("not run", format!("(`{}` failed)", b.because))
        };
        Some(format!(
            "{status:>8}  {stage:<16} {kind:<16} {:>10}  {why}\n",
            "-"
        ))
    }

    /// Every failure with its cause, then the stages not run because of
    /// them: the error of a run that kept going.
    pub fn failure_text(&self) -> String {
        let n = self.failures.len();
        let mut text = format!(
            "{}: {n} stage{} failed",
            self.provenance.pipeline_file,
            if n == 1 { "" } else { "s" }
        );
        if !self.blocked.is_empty() {
            text.push_str(&format!(
                ", {} not run because {} on a failed one",
                self.blocked.len(),
                if self.blocked.len() == 1 {
                    "it depends"
                } else {
                    "they depend"
                }
            ));
        }
        text.push_str("; every other stage ran and is cached");
        for f in self.failures.iter().take(SHOWN) {
            text.push_str(&format!(
                "\n  stage `{}` ({}): {}",
                f.stage, f.kind, f.cause
            ));
        }
        more(
            &mut text,
            n,
            "failures: provenance.json lists each under `failed`",
        );
        for b in self.blocked.iter().take(SHOWN) {
            text.push_str(&format!(
                "\n  `{}` not run: it depends on `{}`, which failed",
                b.stage, b.because
            ));
        }
        more(&mut text, self.blocked.len(), "stages not run");
        text
    }
}

/// Failures (and stages not run) listed one per line; the rest are
/// counted: a study or a generated pipeline can fail thousands of stages at
/// once, and a terminal of them helps no one.
const SHOWN: usize = 20;

/// "… and N more WHAT" past the first [`SHOWN`] of `total`.
fn more(text: &mut String, total: usize, what: &str) {
    if total > SHOWN {
        text.push_str(&format!("\n  … and {} more {what}", total - SHOWN));
    }
}
