//! `provenance.json`: what every stage of a run was, what it read and wrote.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

/// Where a stage's output came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CacheUse {
    /// Reused from the cache.
    Hit,
    /// Computed in this run.
    Miss,
    /// Computed in this run because `--force` asked.
    Forced,
    /// Not part of this run (`--only`).
    Skipped,
}

/// One input as it entered the key.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InputRecord {
    /// `stage.output` it came from.
    pub from: String,
    /// The upstream entry's key.
    pub key: String,
}

/// One stage of a run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StageRecord {
    pub kind: String,
    pub version: u32,
    pub key: String,
    pub params: serde_json::Value,
    /// Input files named in the parameters → BLAKE3 of their content.
    pub files: BTreeMap<String, String>,
    pub inputs: BTreeMap<String, InputRecord>,
    /// Output file (as exported into the run folder) → BLAKE3.
    pub outputs: BTreeMap<String, String>,
    pub cache: CacheUse,
    /// Wall time in this run, seconds (loading for a hit).
    pub wall_s: f64,
    /// Wall time of the computation that made the entry, seconds.
    pub compute_s: f64,
    /// A temporary stage: not exported, its entry dropped once its readers
    /// had theirs.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub temp: bool,
    /// What the stage said when it computed its entry (its notes and
    /// warnings), kept with the entry so a cached stage reports them too.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    /// The cluster job that computed the entry in this run (`slurm 1234`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub job: Option<String>,
    /// The build that computed the entry (`unknown build` for an entry
    /// older than the record); None in a record written before.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub producer: Option<String>,
}

/// The record of one run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    pub pipeline: String,
    pub pipeline_file: String,
    pub pipeline_blake3: String,
    pub hypercontact_version: String,
    /// The build that ran this run; None in a record written before.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub producer: Option<String>,
    pub overrides: Vec<String>,
    pub started_unix_s: u64,
    pub wall_s: f64,
    pub stages: BTreeMap<String, StageRecord>,
}

impl Provenance {
    /// Reads a previous run's record, if there is a readable one.
    pub fn read(path: &Path) -> Option<Self> {
        let bytes = std::fs::read(path).ok()?;
        serde_json::from_slice(&bytes).ok()
    }

    /// Writes the record atomically (temporary file, then rename).
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        let bytes = serde_json::to_vec_pretty(self).map_err(std::io::Error::other)?;
        crate::write_atomic(path, &bytes)
    }
}
