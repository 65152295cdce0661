//! Issue #50, item 3: a study's plan grows with its variants, not with
//! their square, and a grid too large to plan is refused from its axis
//! lengths before a single variant is enumerated.

use crate::common;

use std::path::Path;
use std::time::Instant;

use common::{BASIC, registry, write};
use hypercontact_runner::study::{run_study, variant_pipelines};
use hypercontact_runner::{Pipeline, RunOptions};

/// BASIC with a study of `n` variants: one grid axis listing `n` factors,
/// so the pipeline file itself grows with the study.
fn study_text(n: usize) -> String {
    let factors: Vec<String> = (1..=n).map(|k| format!("{}.5", k)).collect();
    format!(
        "{BASIC}study:\n  grid:\n    double.factor: [{}]\n  collect: [double.t]\n",
        factors.join(", ")
    )
}

/// This thread's CPU time in seconds (user + system), from
/// `/proc/thread-self/stat` (ticks of 1/100 s): what the test's own work
/// cost, whatever else the machine runs.
fn thread_cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/thread-self/stat").expect("Linux /proc");
    // Fields after the command's closing parenthesis: state is field 3,
    // utime and stime are fields 14 and 15.
    let rest = &stat[stat.rfind(')').expect("stat has a command") + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: u64 = fields[11].parse::<u64>().unwrap() + fields[12].parse::<u64>().unwrap();
    ticks as f64 / 100.0
}

/// Plans (a dry run) the study of `n` variants and prints its plan's
/// summary; returns the CPU and wall seconds it took.
fn plan_study(dir: &Path, n: usize) -> (f64, f64) {
    let path = write(dir, &format!("s{n}.yaml"), &study_text(n));
    let (cpu0, wall0) = (thread_cpu_s(), Instant::now());
    let pipeline = Pipeline::load(&path, &registry()).unwrap();
    let options = RunOptions {
        dry_run: true,
        ..RunOptions::in_folders(dir.join(format!("study{n}")), dir.join("cache"))
    };
    let report = run_study(&pipeline, &options).unwrap();
    let text = report.describe();
    let (cpu, wall) = (thread_cpu_s() - cpu0, wall0.elapsed().as_secs_f64());
    assert_eq!(report.runs.len(), n);
    let last = text.lines().last().unwrap();
    assert_eq!(
        last,
        format!(
            "study: {} entries to compute (1 of them shared by several variants), 0 cached",
            n + 1
        )
    );
    (cpu, wall)
}

/// 1 000 and 10 000 variants planned, the figures printed (run with
/// `--nocapture`). Before the fix every variant copied the whole pipeline
/// file and its key locations, and counting shared entries compared every
/// variant's stages with every other's: 10 000 variants took minutes. The
/// bound is generous (a loaded machine must pass): 30 s of this thread's
/// CPU for 10 000, and ten times the variants may cost no more than 30
/// times the CPU (a quadratic plan costs 100 times).
#[test]
fn planning_a_study_is_linear_in_its_variants() {
    let t = tempfile::tempdir().unwrap();
    let (cpu_1k, wall_1k) = plan_study(t.path(), 1_000);
    let (cpu_10k, wall_10k) = plan_study(t.path(), 10_000);
    println!(
        "study --dry-run: 1 000 variants {cpu_1k:.2} s CPU ({wall_1k:.2} s wall), \
         10 000 variants {cpu_10k:.2} s CPU ({wall_10k:.2} s wall)"
    );
    assert!(cpu_10k < 30.0, "10 000 variants took {cpu_10k:.1} s of CPU");
    // Ticks are 10 ms: a floor keeps a fast 1 000 from making the ratio noise.
    let ratio = cpu_10k / cpu_1k.max(0.2);
    assert!(
        ratio < 30.0,
        "10 × the variants cost {ratio:.0} × the CPU ({cpu_1k:.2} s, {cpu_10k:.2} s)"
    );
}

/// The algorithmic property behind the timing: a variant is the pipeline's
/// stages with its values set, sharing the file's text (no copy) and
/// without the study (whose grid lists every value).
#[test]
fn variants_share_the_pipeline_text_and_leave_the_study_behind() {
    let t = tempfile::tempdir().unwrap();
    let path = write(t.path(), "p.yaml", &study_text(50));
    let pipeline = Pipeline::load(&path, &registry()).unwrap();
    let variants = variant_pipelines(&pipeline).unwrap();
    assert_eq!(variants.len(), 50);
    for (values, p) in &variants {
        assert!(
            std::ptr::eq(p.source().as_ptr(), pipeline.source().as_ptr()),
            "variant {values:?} copied the pipeline text"
        );
        assert!(p.study.is_none());
    }
}

/// The size a study is refused at, with the count, its shape and the key
/// that raises the limit; an 8-axis grid of 10^8 variants is refused when
/// the file is read (quickly: it is never enumerated), and `max_variants`
/// lets a larger study through.
#[test]
fn a_grid_beyond_the_limit_is_refused_before_it_is_enumerated() {
    let t = tempfile::tempdir().unwrap();
    let ten = "[0, 1, 2, 3, 4, 5, 6, 7, 8, 9]";
    let axes: String = (0..8)
        .map(|k| format!("    double.a{k}: {ten}\n"))
        .collect();
    let text = format!("{BASIC}study:\n  grid:\n{axes}");
    let path = write(t.path(), "huge.yaml", &text);
    let started = Instant::now();
    let err = Pipeline::load(&path, &registry()).unwrap_err().to_string();
    assert!(started.elapsed().as_secs_f64() < 5.0, "enumerated?");
    assert!(
        err.contains(
            "study: 100000000 variants (grid 10 × 10 × 10 × 10 × 10 × 10 × 10 × 10), more than \
             the limit of 100000 (`study.max_variants`, the default); narrow the study, or \
             raise the limit with `max_variants: 100000000` under `study:`"
        ),
        "{err}"
    );
    assert!(err.contains("huge.yaml:"), "placed in the file: {err}");

    // Cases multiply the grid.
    let cases = "  cases:\n    - { src.n: 1 }\n    - { src.n: 2 }\n    - { src.n: 3 }\n";
    let text = format!(
        "{BASIC}study:\n  max_variants: 200\n{cases}  grid:\n    double.factor: [{}]\n",
        (0..100)
            .map(|k| k.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let path = write(t.path(), "cases.yaml", &text);
    let err = Pipeline::load(&path, &registry()).unwrap_err().to_string();
    assert!(
        err.contains(
            "study: 300 variants (3 cases × grid 100), more than the limit of 200 \
             (`study.max_variants`); narrow the study, or raise the limit with \
             `max_variants: 300` under `study:`"
        ),
        "{err}"
    );
    let raised = text.replace("max_variants: 200", "max_variants: 300");
    let path = write(t.path(), "raised.yaml", &raised);
    let pipeline = Pipeline::load(&path, &registry()).unwrap();
    assert_eq!(variant_pipelines(&pipeline).unwrap().len(), 300);
}
