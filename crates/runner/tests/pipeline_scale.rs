//! Issue #50, item 4: a long pipeline loads and plans in time linear in its
//! stages, and a fully cached rerun costs little per stage.

use crate::common;

use std::path::Path;

use common::{registry, write};
use hypercontact_runner::{Pipeline, RunOptions, run};

/// This process's CPU time in seconds (user + system, every thread), from
/// `/proc/self/stat` (ticks of 1/100 s): what the work cost, whatever else
/// the machine runs.
fn process_cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").expect("Linux /proc");
    let rest = &stat[stat.rfind(')').expect("stat has a command") + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: u64 = fields[11].parse::<u64>().unwrap() + fields[12].parse::<u64>().unwrap();
    ticks as f64 / 100.0
}

/// A chain of `n` `scale` stages after one source: each reads the last.
fn chain(n: usize) -> String {
    let mut text =
        String::from("name: chain\nstages:\n  s0:\n    uses: source\n    with: { n: 2 }\n");
    for i in 1..=n {
        text.push_str(&format!(
            "  s{i}:\n    uses: scale\n    inputs: {{ t: s{} }}\n    with: {{ factor: {i} }}\n",
            i - 1
        ));
    }
    text
}

/// `n` independent `scale` stages reading one source.
fn wide(n: usize) -> String {
    let mut text =
        String::from("name: wide\nstages:\n  s0:\n    uses: source\n    with: { n: 2 }\n");
    for i in 1..=n {
        text.push_str(&format!(
            "  s{i}:\n    uses: scale\n    inputs: {{ t: s0 }}\n    with: {{ factor: {i} }}\n"
        ));
    }
    text
}

/// CPU seconds to load and plan (a dry run) the chain of `n` stages.
fn plan_chain(dir: &Path, n: usize) -> f64 {
    let path = write(dir, &format!("chain{n}.yaml"), &chain(n));
    let cpu0 = process_cpu_s();
    let pipeline = Pipeline::load(&path, &registry()).unwrap();
    let options = RunOptions {
        dry_run: true,
        ..RunOptions::in_folders(dir.join(format!("out{n}")), dir.join("cache"))
    };
    let report = run(&pipeline, &options).unwrap();
    assert_eq!(report.plan.stages.len(), n + 1);
    process_cpu_s() - cpu0
}

/// 2 000 and 20 000 chained stages planned (figures with `--nocapture`).
/// Before the fix each stage's parameters were located by scanning every
/// key of the file: 5 000 stages took 1.3 s, 20 000 some 20 s. Ten times the
/// stages may cost no more than 30 times the CPU (a quadratic plan costs
/// 100 times); generous bounds, a loaded machine must pass.
#[test]
fn planning_a_long_pipeline_is_linear_in_its_stages() {
    let t = tempfile::tempdir().unwrap();
    let cpu_2k = plan_chain(t.path(), 2_000);
    let cpu_20k = plan_chain(t.path(), 20_000);
    println!("plan: 2 000 stages {cpu_2k:.2} s CPU, 20 000 stages {cpu_20k:.2} s CPU");
    let ratio = cpu_20k / cpu_2k.max(0.1);
    assert!(
        ratio < 30.0,
        "10 × the stages cost {ratio:.0} × the CPU ({cpu_2k:.2} s, {cpu_20k:.2} s)"
    );
}

/// 1 000 independent stages run, then rerun with every entry cached. Before
/// the fix each file hashed took a zeroed 8 MiB buffer and each export was
/// copied and renamed over itself: 2.5 ms of CPU per cached stage (5 000
/// took 14 s of wall on a 2-core machine); now ~0.25 ms. The bound, 1.5 ms
/// a stage, leaves room for a loaded machine.
#[test]
fn a_fully_cached_rerun_costs_little_per_stage() {
    let t = tempfile::tempdir().unwrap();
    let n = 1_000;
    let path = write(t.path(), "wide.yaml", &wide(n));
    let pipeline = Pipeline::load(&path, &registry()).unwrap();
    let options = RunOptions::in_folders(t.path().join("out"), t.path().join("cache"));
    assert_eq!(run(&pipeline, &options).unwrap().computed(), n + 1);
    let exported = t.path().join("out/s7/t.parquet");
    let inode = std::os::unix::fs::MetadataExt::ino(&std::fs::metadata(&exported).unwrap());
    let cpu0 = process_cpu_s();
    let report = run(&pipeline, &options).unwrap();
    let cpu = process_cpu_s() - cpu0;
    assert_eq!(report.computed(), 0);
    println!("cached rerun: {n} stages {cpu:.2} s CPU");
    assert!(
        cpu < 1.5e-3 * n as f64,
        "{cpu:.2} s of CPU for {n} cached stages"
    );
    // The export already held the entry's bytes: left as it was.
    let now = std::os::unix::fs::MetadataExt::ino(&std::fs::metadata(&exported).unwrap());
    assert_eq!(now, inode);
}
