//! The version guard (issue 30): a stage's `version` is part of every cache
//! key, and it is bumped by hand when the stage's outputs change. A
//! forgotten bump makes users' caches serve the old code's results. This
//! test runs `tests/guard/pipeline.yaml` (every stage kind once, at tiny
//! sizes) and holds each stage's output hashes against the committed table
//! `tests/guard/hashes.json`, keyed by the stage's kind, version and inputs
//! (its canonical parameters, input files and upstream cache keys).
//! Products are the same bytes on every run, so the comparison is exact:
//!
//! - same kind, version and inputs, other bytes: the stage's code changed
//!   its results without a version bump. The test fails naming the kind to
//!   bump.
//! - a new version, or other inputs (an upstream stage or the fixture
//!   changed): the table is stale; the test fails asking to record it again
//!   with `HYPERCONTACT_RECORD_GUARD=1 cargo test --workspace --release
//!   --test integration -- version_guard::`, which writes the new table but refuses, with the same
//!   message, to record a stage whose bytes changed under an unchanged
//!   version and inputs.
//! - a new store format (`MANIFEST_FORMAT`, bumped when the runner writes
//!   every product another way, as when tables began to carry their units)
//!   counts among the inputs: every entry is stale, none a forgotten bump.
//! - every registered kind must appear in the fixture.
//!
//! Across machines the FFT kernels a CPU selects may move the last bits
//! (README, "Every product is the same bytes"): the table is recorded and
//! checked on this project's CI machine kind.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use hypercontact_runner::cache::MANIFEST_FORMAT;
use hypercontact_runner::hash::canonical_json;
use serde_json::{Value, json};

use crate::common;
use common::{bin, repo, text};

/// One fixture stage as the table records it.
#[derive(Debug, Clone, PartialEq)]
struct Entry {
    kind: String,
    version: u64,
    /// BLAKE3 of the stage's inputs: parameters, input files, upstream
    /// keys, and the store format the runner wrote them in.
    inputs: String,
    /// Output file → BLAKE3.
    outputs: BTreeMap<String, String>,
}

impl Entry {
    fn from_provenance(record: &Value) -> Self {
        // The fixture's files are named by absolute path, so the checkout's
        // folder is taken out: the table holds on any clone.
        let checkout = format!("{}/", repo().display());
        let mut hasher = blake3::Hasher::new();
        for part in ["params", "files", "inputs"] {
            let text = canonical_json(&record[part]).replace(&checkout, "<repo>/");
            hasher.update(text.as_bytes());
            hasher.update(b"\0");
        }
        // Not in the cache key (the manifest's format check retires old
        // entries instead), so added here.
        hasher.update(format!("store format {MANIFEST_FORMAT}").as_bytes());
        Entry {
            kind: record["kind"].as_str().unwrap().to_owned(),
            version: record["version"].as_u64().unwrap(),
            inputs: hasher.finalize().to_hex().to_string(),
            outputs: strings(&record["outputs"]),
        }
    }

    fn from_table(value: &Value) -> Self {
        Entry {
            kind: value["kind"].as_str().unwrap().to_owned(),
            version: value["version"].as_u64().unwrap(),
            inputs: value["inputs"].as_str().unwrap().to_owned(),
            outputs: strings(&value["outputs"]),
        }
    }

    fn to_table(&self) -> Value {
        json!({
            "kind": self.kind,
            "version": self.version,
            "inputs": self.inputs,
            "outputs": self.outputs,
        })
    }
}

fn strings(value: &Value) -> BTreeMap<String, String> {
    value
        .as_object()
        .unwrap()
        .iter()
        .map(|(k, v)| (k.clone(), v.as_str().unwrap().to_owned()))
        .collect()
}

/// What is wrong with one fixture stage against its recorded entry: a
/// forgotten bump (`Err`), a stale entry (`Ok(Some)`), or nothing.
fn judge(stage: &str, now: &Entry, then: Option<&Entry>) -> Result<Option<String>, String> {
    let Some(then) = then else {
        return Ok(Some(format!(
            "stage `{stage}` ({}) is not in the table",
            now.kind
        )));
    };
    if now.kind != then.kind || now.version != then.version || now.inputs != then.inputs {
        let why = if now.kind != then.kind {
            format!("its kind is now `{}` (was `{}`)", now.kind, then.kind)
        } else if now.version != then.version {
            format!(
                "`{}` is now version {} (was {})",
                now.kind, now.version, then.version
            )
        } else {
            "its parameters, input files, upstream stages or the store format changed".to_owned()
        };
        return Ok(Some(format!("stage `{stage}`: {why}")));
    }
    let changed: Vec<String> = now
        .outputs
        .keys()
        .chain(then.outputs.keys())
        .collect::<BTreeSet<_>>()
        .into_iter()
        .filter(|name| now.outputs.get(*name) != then.outputs.get(*name))
        .cloned()
        .collect();
    if changed.is_empty() {
        return Ok(None);
    }
    Err(format!(
        "stage `{stage}`: kind `{kind}` gives other bytes ({files}) from the same parameters and \
         inputs while its version stayed {version}: bump `version` in the StageInfo of \
         `{kind}` (grep 'kind: \"{kind}\"' crates), then record the table again with \
         HYPERCONTACT_RECORD_GUARD=1",
        kind = now.kind,
        version = now.version,
        files = changed.join(", "),
    ))
}

fn run_fixture(dir: &Path) -> Value {
    let out = bin()
        .arg("run")
        .arg(repo().join("tests/guard/pipeline.yaml"))
        .arg("--out")
        .arg(dir.join("out"))
        .arg("--cache")
        .arg(dir.join("cache"))
        .arg("--quiet")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "the guard's fixture failed: {}",
        text(&out)
    );
    serde_json::from_slice(&std::fs::read(dir.join("out/provenance.json")).unwrap()).unwrap()
}

fn registered_kinds() -> BTreeSet<String> {
    let out = bin().args(["stages", "--json"]).output().unwrap();
    assert!(out.status.success());
    let all: Value = serde_json::from_slice(&out.stdout).unwrap();
    all.as_array()
        .unwrap()
        .iter()
        .map(|s| s["kind"].as_str().unwrap().to_owned())
        .collect()
}

#[test]
fn every_stage_gives_its_recorded_bytes_or_has_a_new_version() {
    let t = tempfile::tempdir().unwrap();
    let provenance = run_fixture(t.path());
    let now: BTreeMap<String, Entry> = provenance["stages"]
        .as_object()
        .unwrap()
        .iter()
        .map(|(stage, record)| (stage.clone(), Entry::from_provenance(record)))
        .collect();

    let covered: BTreeSet<String> = now.values().map(|e| e.kind.clone()).collect();
    let missing: Vec<String> = registered_kinds().difference(&covered).cloned().collect();
    assert!(
        missing.is_empty(),
        "tests/guard/pipeline.yaml runs no stage of kind {}: add one",
        missing.join(", ")
    );

    let table_path = repo().join("tests/guard/hashes.json");
    let table: BTreeMap<String, Entry> = std::fs::read(&table_path)
        .ok()
        .and_then(|bytes| serde_json::from_slice::<Value>(&bytes).ok())
        .and_then(|v| v.as_object().cloned())
        .unwrap_or_default()
        .iter()
        .map(|(stage, v)| (stage.clone(), Entry::from_table(v)))
        .collect();

    let mut forgotten = Vec::new();
    let mut stale = Vec::new();
    for (stage, entry) in &now {
        match judge(stage, entry, table.get(stage)) {
            Err(message) => forgotten.push(message),
            Ok(Some(message)) => stale.push(message),
            Ok(None) => {}
        }
    }
    stale.extend(
        table
            .keys()
            .filter(|stage| !now.contains_key(*stage))
            .map(|stage| format!("stage `{stage}` is no longer in the fixture")),
    );
    assert!(forgotten.is_empty(), "{}", forgotten.join("\n"));
    if std::env::var_os("HYPERCONTACT_RECORD_GUARD").is_some() {
        let record: serde_json::Map<String, Value> = now
            .iter()
            .map(|(stage, entry)| (stage.clone(), entry.to_table()))
            .collect();
        let text = serde_json::to_string_pretty(&Value::Object(record)).unwrap() + "\n";
        std::fs::write(&table_path, text).unwrap();
        return;
    }
    assert!(
        stale.is_empty(),
        "tests/guard/hashes.json is stale (a version was bumped or a fixture input changed); \
         record it again with HYPERCONTACT_RECORD_GUARD=1 cargo test --workspace --release \
         --test integration -- version_guard::\n{}",
        stale.join("\n")
    );
}

#[test]
fn a_changed_output_under_an_unchanged_version_is_named_for_a_bump() {
    let entry = |hash: &str| Entry {
        kind: "bem".into(),
        version: 2,
        inputs: "i".into(),
        outputs: BTreeMap::from([("response.parquet".into(), hash.into())]),
    };
    let e = judge("t1-bem", &entry("new"), Some(&entry("old"))).unwrap_err();
    assert!(
        e.contains("kind `bem`") && e.contains("response.parquet") && e.contains("bump `version`"),
        "{e}"
    );
    assert_eq!(
        judge("t1-bem", &entry("old"), Some(&entry("old"))),
        Ok(None)
    );
    let bumped = Entry {
        version: 3,
        ..entry("new")
    };
    let stale = judge("t1-bem", &bumped, Some(&entry("old")))
        .unwrap()
        .unwrap();
    assert!(stale.contains("now version 3 (was 2)"), "{stale}");
    let moved = Entry {
        inputs: "j".into(),
        ..entry("new")
    };
    assert!(
        judge("t1-bem", &moved, Some(&entry("old")))
            .unwrap()
            .is_some()
    );
}
