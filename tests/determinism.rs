//! Every product of a run is the same to the byte whatever the thread count
//! and however the threads are scheduled (issue 12): the quick paper
//! pipeline once on one thread and twice on two, each into a fresh cache,
//! must export identical files. Only `provenance.json` may differ: it
//! records wall times and cache use, which belong to the run.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Child, Command, Stdio};

use crate::common;
use common::{products, repo};

/// Starts `run pipelines/quick.yaml` into `dir`/out with its own cache in
/// `dir`/cache on `threads` rayon threads.
fn start_quick(dir: &Path, threads: usize) -> Child {
    Command::new(env!("CARGO_BIN_EXE_hypercontact"))
        .arg("run")
        .arg(repo().join("pipelines/quick.yaml"))
        .arg("--out")
        .arg(dir.join("out"))
        .arg("--cache")
        .arg(dir.join("cache"))
        .arg("--quiet")
        .env("RAYON_NUM_THREADS", threads.to_string())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// The files that differ between two runs' products (present in one only,
/// or with other bytes).
fn differing(a: &BTreeMap<String, Vec<u8>>, b: &BTreeMap<String, Vec<u8>>) -> Vec<String> {
    let mut names: Vec<&String> = a.keys().chain(b.keys()).collect();
    names.sort();
    names.dedup();
    names
        .into_iter()
        .filter(|name| a.get(*name) != b.get(*name))
        .cloned()
        .collect()
}

#[test]
fn the_quick_pipeline_is_byte_identical_on_one_and_two_threads() {
    let runs = [("1 thread", 1), ("2 threads", 2), ("2 threads again", 2)];
    let dirs: Vec<tempfile::TempDir> = runs.iter().map(|_| tempfile::tempdir().unwrap()).collect();
    // At the same time, so the two-thread runs also compete for the cores
    // and their work stealing differs from one run to the other.
    let children: Vec<Child> = runs
        .iter()
        .zip(&dirs)
        .map(|((_, threads), dir)| start_quick(dir.path(), *threads))
        .collect();
    for ((label, _), child) in runs.iter().zip(children) {
        let out = child.wait_with_output().unwrap();
        assert!(
            out.status.success(),
            "{label}: {}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    }

    let reference = products(&dirs[0].path().join("out"), |n| n == "provenance.json");
    // 61 since the synthetic raw data are temporary (not exported): every
    // stage's products from DIC and stitching on.
    assert!(
        reference.len() >= 60,
        "only {} products: {:?}",
        reference.len(),
        reference.keys().collect::<Vec<_>>()
    );
    let mut failures = Vec::new();
    for ((label, _), dir) in runs.iter().zip(&dirs).skip(1) {
        let files = differing(
            &reference,
            &products(&dir.path().join("out"), |n| n == "provenance.json"),
        );
        if !files.is_empty() {
            failures.push(format!(
                "{label} vs {}: {} of {} files differ:\n  {}",
                runs[0].0,
                files.len(),
                reference.len(),
                files.join("\n  ")
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
