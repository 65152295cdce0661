//! The hypercontact pipeline runner: reads a YAML pipeline, plans it with
//! content-addressed cache keys, runs what changed, and records provenance.

pub mod cache;
pub mod error;
pub mod eta;
pub mod exec;
pub mod folders;
pub mod graph;
pub mod hash;
pub mod heap;
pub mod outcome;
pub mod pipeline;
pub mod plan;
pub mod producer;
pub mod progress;
pub mod provenance;
pub mod slurm;
mod stage_params;
pub mod store;
pub mod study;
pub mod timings;
pub mod yaml;

pub use exec::{RunError, RunOptions, RunReport, run};
pub use pipeline::{Pipeline, PipelineError};
pub use plan::{Action, Plan, PlanOptions, Reason, Unreadable};

use std::io::Write;
use std::path::Path;

/// Writes a file atomically: a temporary file beside it, then rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent)?;
    }
    let tmp = path.with_file_name(format!(
        ".{}.{}.tmp",
        path.file_name()
            .map(|n| n.to_string_lossy())
            .unwrap_or_default(),
        std::process::id()
    ));
    let mut file = std::fs::File::create(&tmp)?;
    file.write_all(bytes)?;
    file.sync_all()?;
    std::fs::rename(&tmp, path)
}
