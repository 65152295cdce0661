//! `provenance.json`: what every stage of a run was, what it read and wrote.

use std::collections::BTreeMap;
use std::path::Path;

use hypercontact_core::regular_file::{MIB, read_checked};
use serde::{Deserialize, Serialize};

use crate::error::PipelineError;

/// The largest `provenance.json` read: a record per stage, with the
/// parameters and file hashes of each; far below this for any pipeline.
pub const RECORD_LIMIT_BYTES: u64 = 64 * MIB;

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
    /// The running process's peak resident memory by the end of the run,
    /// MB (Linux `VmHWM`); None where the system does not say, and in a
    /// record written before.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peak_rss_mb: Option<f64>,
    pub stages: BTreeMap<String, StageRecord>,
}

impl Provenance {
    /// Reads a previous run's record: `None` when there is none, or when
    /// the file is one this version does not parse (an older format; it is
    /// replaced atomically at the end of the run). What cannot be read
    /// safely — a pipe, a device, a file over [`RECORD_LIMIT_BYTES`] — fails
    /// the run: opening a pipe would hang it, and writing over a thing this
    /// run did not make would hide whoever put it there.
    pub fn read(path: &Path) -> Result<Option<Self>, PipelineError> {
        // An output "folder" that is a file holds no record; exporting
        // into it fails later, naming it.
        if path
            .parent()
            .is_some_and(|dir| dir.exists() && !dir.is_dir())
        {
            return Ok(None);
        }
        let bytes = match read_checked(path, "provenance records", RECORD_LIMIT_BYTES) {
            Err(e) if e.not_found => return Ok(None),
            read => read,
        };
        let bytes = bytes.map_err(|e| {
            PipelineError::new(
                path,
                format!(
                    "cannot read the previous run's record: it {}; remove it or give another --out",
                    e.why
                ),
            )
        })?;
        Ok(serde_json::from_slice(&bytes).ok())
    }

    /// Writes the record atomically (temporary file, then rename).
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        let bytes = serde_json::to_vec_pretty(self).map_err(std::io::Error::other)?;
        crate::write_atomic(path, &bytes)
    }
}

/// This process's peak resident set so far, MB: `VmHWM` of
/// `/proc/self/status` (Linux); None where there is no such file.
pub fn peak_rss_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line
        .trim_start_matches("VmHWM:")
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kib / 1024.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    // Before, `read` swallowed every failure: a pipe hung the run and
    // `/dev/zero` read until memory ran out, then counted as "no record".
    #[test]
    fn a_record_that_cannot_be_read_safely_fails_instead_of_being_none() {
        let t = tempfile::tempdir().unwrap();
        let path = t.path().join("provenance.json");
        assert_eq!(Provenance::read(&path).unwrap(), None);
        std::fs::write(&path, "{ not json").unwrap();
        assert_eq!(Provenance::read(&path).unwrap(), None);
        std::fs::remove_file(&path).unwrap();
        std::os::unix::fs::symlink("/dev/zero", &path).unwrap();
        let e = Provenance::read(&path).unwrap_err().to_string();
        assert!(
            e.starts_with(&path.display().to_string())
                && e.contains("character device")
                && e.contains("--out"),
            "{e}"
        );
        std::fs::remove_file(&path).unwrap();
        let made = std::process::Command::new("mkfifo").arg(&path).status();
        assert!(made.is_ok_and(|s| s.success()), "mkfifo");
        let e = Provenance::read(&path).unwrap_err().to_string();
        assert!(e.contains("not a regular file (a pipe)"), "{e}");
    }
}
