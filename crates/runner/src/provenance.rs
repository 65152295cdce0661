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

/// The format of `provenance.json` this version writes. Format 2 (issue
/// #50) added `format` and `failed`; a record without `format` is format 1
/// and reads as one without failures.
pub const PROVENANCE_FORMAT: u32 = 2;

fn format_1() -> u32 {
    1
}

/// A stage that failed in the run: how long it ran, and what it said.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FailedRecord {
    pub kind: String,
    /// The cache key it failed on (no entry was made).
    pub key: String,
    /// Wall time until it failed, seconds (0 for an entry that failed in
    /// an earlier variant of the study and was not run again).
    pub wall_s: f64,
    /// The error with every cause, on one line.
    pub error: String,
}

/// The record of one run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// The record's format ([`PROVENANCE_FORMAT`]; 1 when absent).
    #[serde(default = "format_1")]
    pub format: u32,
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
    /// MiB, 2^20 bytes (Linux `VmHWM`); None where the system does not say, and in a
    /// record written before.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peak_rss_mb: Option<f64>,
    pub stages: BTreeMap<String, StageRecord>,
    /// Stages that failed in the run, with their time and error (they made
    /// no entry, so they are not in `stages`).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub failed: BTreeMap<String, FailedRecord>,
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

    /// Reads a finished run's record (for `timings` and `export`), naming
    /// what is wrong with a damaged one: missing, unreadable (a pipe, a
    /// device, too large), empty, not JSON (line and column), not a record,
    /// a format this version does not read, or a field missing or of the
    /// wrong type (with its path). Records of format 1 read as before.
    pub fn load(path: &Path) -> Result<Self, PipelineError> {
        let err = |message: String| PipelineError::new(path, message);
        let bytes = read_checked(path, "provenance records", RECORD_LIMIT_BYTES).map_err(|e| {
            err(match e.not_found {
                true => "no provenance.json here: give a run's output folder (runs/<name>)".into(),
                false => format!("cannot read the run's record: it {}", e.why),
            })
        })?;
        if bytes.iter().all(u8::is_ascii_whitespace) {
            return Err(err(
                "the run's record is empty (a run stopped while writing it?)".into(),
            ));
        }
        let value: serde_json::Value = serde_json::from_slice(&bytes)
            .map_err(|e| err(format!("the run's record is not valid JSON: {e}")))?;
        let Some(object) = value.as_object() else {
            return Err(err(format!(
                "the run's record is not a JSON object but {}",
                json_kind(&value)
            )));
        };
        if let Some(format) = object.get("format") {
            let known = format
                .as_u64()
                .is_some_and(|f| (1..=u64::from(PROVENANCE_FORMAT)).contains(&f));
            if !known {
                return Err(err(format!(
                    "the run's record has format {format}; this version reads formats 1 to \
                     {PROVENANCE_FORMAT} (a newer hypercontact wrote it?)"
                )));
            }
        }
        let record: Provenance = serde_path_to_error::deserialize(value).map_err(|e| {
            let at = e.path().to_string();
            match at.as_str() {
                "." => err(format!("the run's record is damaged: {}", e.inner())),
                _ => err(format!(
                    "the run's record is damaged at `{at}`: {}",
                    e.inner()
                )),
            }
        })?;
        Ok(record)
    }

    /// [`Provenance::load`], its times checked too ([`Provenance::check_times`]):
    /// what `timings` reads.
    pub fn load_with_times(path: &Path) -> Result<Self, PipelineError> {
        let record = Self::load(path)?;
        record.check_times().map_err(|why| {
            PipelineError::new(path, format!("the run's record is damaged: {why}"))
        })?;
        Ok(record)
    }

    /// Refuses times no run records: negative, not finite or over a year,
    /// and a stage's wall time in this run far beyond the run's own (more
    /// than twice it and a second: stages run within the run). A skipped
    /// stage's record is an earlier run's, held to the first rule only.
    pub fn check_times(&self) -> Result<(), String> {
        const YEAR_S: f64 = 365.25 * 24.0 * 3600.0;
        let possible = |s: f64| s.is_finite() && (0.0..=YEAR_S).contains(&s);
        if !possible(self.wall_s) {
            return Err(format!(
                "impossible run wall time `wall_s` = {} s (negative, not finite or over a year)",
                seconds(self.wall_s)
            ));
        }
        let this_run = |r: &StageRecord| r.cache != CacheUse::Skipped;
        let times = (self.stages.iter())
            .flat_map(|(name, r)| {
                [
                    (name, "wall_s", r.wall_s, this_run(r)),
                    (name, "compute_s", r.compute_s, false),
                ]
            })
            .chain(
                self.failed
                    .iter()
                    .map(|(name, f)| (name, "wall_s", f.wall_s, true)),
            );
        let bound = 2.0 * self.wall_s + 1.0;
        for (name, field, s, within_run) in times {
            if !possible(s) {
                return Err(format!(
                    "impossible time in stage `{name}`: `{field}` = {} s (negative, not finite \
                     or over a year)",
                    seconds(s)
                ));
            }
            if within_run && s > bound {
                return Err(format!(
                    "impossible time in stage `{name}`: `{field}` = {} s in a run of {} s",
                    seconds(s),
                    seconds(self.wall_s)
                ));
            }
        }
        match self.peak_rss_mb {
            Some(mb) if !(mb.is_finite() && mb >= 0.0) => Err(format!(
                "impossible peak memory `peak_rss_mb` = {} MiB",
                seconds(mb)
            )),
            _ => Ok(()),
        }
    }

    /// Writes the record atomically (temporary file, then rename).
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        let bytes = serde_json::to_vec_pretty(self).map_err(std::io::Error::other)?;
        crate::write_atomic(path, &bytes)
    }
}

/// A number as a message shows it: plain, or in exponent form when huge
/// or tiny (`1e308`, not 309 digits).
fn seconds(s: f64) -> String {
    if s != 0.0 && !(1e-3..1e7).contains(&s.abs()) {
        format!("{s:e}")
    } else {
        format!("{s}")
    }
}

/// What a JSON value is, as a message names it.
fn json_kind(value: &serde_json::Value) -> &'static str {
    match value {
        serde_json::Value::Null => "null",
        serde_json::Value::Bool(_) => "a boolean",
        serde_json::Value::Number(_) => "a number",
        serde_json::Value::String(_) => "a string",
        serde_json::Value::Array(_) => "a list",
        serde_json::Value::Object(_) => "an object",
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

    /// A format-1 record (before `format` and `failed`), as runs wrote it.
    const FORMAT_1: &str = r#"{
  "pipeline": "p", "pipeline_file": "p.yaml", "pipeline_blake3": "b",
  "hypercontact_version": "0.1.0", "overrides": [], "started_unix_s": 1,
  "wall_s": 10.0,
  "stages": {
    "fit": {
      "kind": "material-fit", "version": 1, "key": "k", "params": {},
      "files": {}, "inputs": {}, "outputs": {}, "cache": "miss",
      "wall_s": 4.0, "compute_s": 4.0
    }
  }
}"#;

    /// What `timings` says of a record damaged in each way (issue #50,
    /// item 10; before, every one read "no provenance.json this version
    /// reads"), and that a format-1 record still reads.
    #[test]
    fn each_kind_of_damage_is_named() {
        let t = tempfile::tempdir().unwrap();
        let path = t.path().join("provenance.json");
        let said = |text: Option<&str>| -> String {
            match text {
                Some(text) => std::fs::write(&path, text).unwrap(),
                None => drop(std::fs::remove_file(&path)),
            }
            match Provenance::load_with_times(&path) {
                Ok(_) => "read".to_owned(),
                Err(e) => e.to_string(),
            }
        };
        let old = said(Some(FORMAT_1));
        assert_eq!(old, "read");
        let record = Provenance::load(&path).unwrap();
        assert_eq!((record.format, record.failed.len()), (1, 0));
        let cases: Vec<(String, &str)> = vec![
            (
                said(None),
                "no provenance.json here: give a run's output folder (runs/<name>)",
            ),
            (said(Some(" \n")), "the run's record is empty"),
            (
                said(Some(&FORMAT_1[..60])),
                "not valid JSON: EOF while parsing",
            ),
            (said(Some("[1, 2]")), "not a JSON object but a list"),
            (
                said(Some(&FORMAT_1.replacen('{', "{ \"format\": 99,", 1))),
                "the run's record has format 99; this version reads formats 1 to 2",
            ),
            (
                said(Some(&FORMAT_1.replace("\"wall_s\": 4.0, ", ""))),
                "damaged at `stages.fit`: missing field `wall_s`",
            ),
            (
                said(Some(&FORMAT_1.replace("\"pipeline\": \"p\", ", ""))),
                "the run's record is damaged: missing field `pipeline`",
            ),
            (
                said(Some(
                    &FORMAT_1.replace("\"wall_s\": 4.0", "\"wall_s\": \"4\""),
                )),
                "damaged at `stages.fit.wall_s`: invalid type: string \"4\", expected f64",
            ),
            (
                said(Some(
                    &FORMAT_1.replace("\"wall_s\": 4.0", "\"wall_s\": -4.0"),
                )),
                "impossible time in stage `fit`: `wall_s` = -4 s (negative",
            ),
            (
                said(Some(
                    &FORMAT_1.replace("\"compute_s\": 4.0", "\"compute_s\": 1e308"),
                )),
                "impossible time in stage `fit`: `compute_s` = 1e308 s",
            ),
            (
                said(Some(
                    &FORMAT_1.replace("\"wall_s\": 4.0", "\"wall_s\": 400.0"),
                )),
                "impossible time in stage `fit`: `wall_s` = 400 s in a run of 10 s",
            ),
            (
                said(Some(
                    &FORMAT_1.replace("\"wall_s\": 10.0", "\"wall_s\": -1"),
                )),
                "impossible run wall time `wall_s` = -1 s",
            ),
            (
                said(Some("{\"wall_s\": 1e999}")),
                "not valid JSON: number out of range",
            ),
        ];
        let at = path.display().to_string();
        for (said, expected) in cases {
            assert!(
                said.starts_with(&at) && said.contains(expected),
                "{said}\nexpected: {expected}"
            );
        }
    }

    /// A record with a failed stage writes format 2 and reads back.
    #[test]
    fn failed_stages_are_recorded_and_read_back() {
        let t = tempfile::tempdir().unwrap();
        let path = t.path().join("provenance.json");
        let mut record: Provenance = serde_json::from_str(FORMAT_1).unwrap();
        record.format = PROVENANCE_FORMAT;
        record.failed.insert(
            "fem".to_owned(),
            FailedRecord {
                kind: "fem".to_owned(),
                key: "k2".to_owned(),
                wall_s: 5.5,
                error: "Newton did not converge".to_owned(),
            },
        );
        record.write(&path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.contains("\"format\": 2") && text.contains("\"failed\""),
            "{text}"
        );
        assert_eq!(Provenance::load_with_times(&path).unwrap(), record);
        record.failed.get_mut("fem").unwrap().wall_s = f64::INFINITY;
        let e = record.check_times().unwrap_err();
        assert!(e.contains("stage `fem`: `wall_s` = inf s"), "{e}");
    }
}
