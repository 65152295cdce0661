//! Kill -9 injection: runs of the quick paper pipeline killed at random
//! moments on one cache, then a clean run must equal an uninterrupted one
//! byte for byte, and every entry left in the cache must pass its hashes.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

mod common;
use common::{bin, products, run_record, text};

fn quick() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("pipelines/quick.yaml")
}

fn run(cache: &Path, out: &Path) -> Command {
    let mut c = bin();
    c.arg("run")
        .arg(quick())
        .arg("--quiet")
        .arg("--cache")
        .arg(cache)
        .arg("--out")
        .arg(out);
    c
}

/// splitmix64: a fixed sequence of kill moments, the same on every run of
/// the test (printed on failure, so a failing schedule can be replayed).
struct Moments(u64);

impl Moments {
    fn next_fraction(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[test]
fn runs_killed_at_random_moments_leave_a_cache_that_gives_the_reference_bytes() {
    let t = tempfile::tempdir().unwrap();
    let reference_out = t.path().join("reference");
    let started = Instant::now();
    let reference = run(&t.path().join("reference-cache"), &reference_out)
        .output()
        .unwrap();
    assert!(reference.status.success(), "{}", text(&reference));
    let cold = started.elapsed();

    // Runs killed on one cache until 12 were killed mid-run. Before most,
    // the entries (not the debris: staging folders, stamps, locks) are
    // deleted so the kill lands at a random moment of a cold run; every
    // third run instead resumes what the previous one left, killed early.
    // A run that finished before its kill shortens the later delays (the
    // machine may be faster now than during the reference run).
    let cache = t.path().join("cache");
    let mut moments = Moments(12);
    let mut schedule = Vec::new();
    let mut killed = 0;
    let mut span = cold;
    for k in 0..40 {
        if killed == 12 {
            break;
        }
        let resume = k % 3 == 2;
        if !resume && cache.join("entries").exists() {
            std::fs::remove_dir_all(cache.join("entries")).unwrap();
            std::fs::create_dir(cache.join("entries")).unwrap();
        }
        let fraction = if resume {
            0.2
        } else {
            0.05 + 0.8 * moments.next_fraction()
        };
        let delay = span.mul_f64(fraction);
        schedule.push(delay.as_millis());
        let mut child = run(&cache, &t.path().join("killed")).spawn().unwrap();
        std::thread::sleep(delay);
        // `Child::kill` is SIGKILL on Unix: no handler, no cleanup.
        if child.try_wait().unwrap().is_none() {
            child.kill().unwrap();
            killed += 1;
        } else {
            span = span.mul_f64(0.8);
        }
        child.wait().unwrap();
    }
    assert!(
        killed >= 10,
        "only {killed} runs were still running when killed (delays in ms: {schedule:?})"
    );

    // What the kills left: no corrupt entry (unreadable entries would be
    // listed and fail `verify`).
    let verify = bin()
        .args(["cache", "verify", "--cache"])
        .arg(&cache)
        .output()
        .unwrap();
    assert!(
        verify.status.success(),
        "kills at {schedule:?} ms: {}",
        text(&verify)
    );

    // A clean run over the debris gives the reference bytes.
    let out = t.path().join("after");
    let after = run(&cache, &out).output().unwrap();
    assert!(
        after.status.success(),
        "kills at {schedule:?} ms: {}",
        text(&after)
    );
    let (want, got) = (
        products(&reference_out, run_record),
        products(&out, run_record),
    );
    let differing: Vec<_> = want
        .keys()
        .chain(got.keys())
        .filter(|k| want.get(*k) != got.get(*k))
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    assert!(
        differing.is_empty(),
        "kills at {schedule:?} ms: {} of {} files differ from the uninterrupted run: {differing:?}",
        differing.len(),
        want.len()
    );

    // `gc` removes the debris and keeps the entries.
    let gc = bin()
        .args(["cache", "gc", "--cache"])
        .arg(&cache)
        .output()
        .unwrap();
    assert!(gc.status.success(), "{}", text(&gc));
    let leftovers: Vec<_> = std::fs::read_dir(cache.join("tmp"))
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert!(leftovers.is_empty(), "left in tmp/: {leftovers:?}");
    let again = run(&cache, &out).arg("--dry-run").output().unwrap();
    assert!(
        !text(&again)
            .lines()
            .any(|l| l.trim_start().starts_with("RUN ")),
        "after gc, stages would rerun:\n{}",
        text(&again)
    );
    assert!(
        cold < Duration::from_secs(120),
        "the reference run took {cold:?}"
    );
}
