//! Issue #50, item 7: an input file that cannot be read fails its stage
//! alone when the run keeps going (the default), as a stage failing at run
//! time does; `--fail-fast` and a dry run refuse the plan as before.

use crate::common;

use std::path::Path;

use common::{registry, write};
use hypercontact_runner::cache::{Cache, EntryState};
use hypercontact_runner::plan::Reason;
use hypercontact_runner::study::run_study;
use hypercontact_runner::{Pipeline, RunError, RunOptions, run};

/// `bad` reads `in.csv`; `later` and `after` depend on it, `src` and
/// `double` do not.
const BRANCHES: &str = "\
name: branches
stages:
  bad:
    uses: source
    with: { n: 1, path: in.csv }
  later:
    uses: scale
    inputs: { t: bad }
  after:
    uses: gather
    inputs:
      parts: { a: later, b: src }
  src:
    uses: source
    with: { value: 2.0e-5, n: 5 }
  double:
    uses: scale
    inputs: { t: src }
    with: { factor: 2 }
";

fn load(dir: &Path, text: &str) -> Pipeline {
    Pipeline::load(&write(dir, "p.yaml", text), &registry()).unwrap()
}

fn options(dir: &Path) -> RunOptions {
    RunOptions::in_folders(dir.join("out"), dir.join("cache"))
}

/// The message the plan was refused with before, and still is with
/// `--fail-fast` or a dry run; a failure's cause is the same without the
/// stage, which the list of failures names.
fn cannot_read(dir: &Path, stage: &str) -> String {
    format!(
        "{}:5:19: {stage}parameter `path`: cannot read `{}`: No such file or directory (os error 2)",
        dir.join("p.yaml").display(),
        dir.join("in.csv").display()
    )
}

#[test]
fn fail_fast_and_dry_run_refuse_the_plan() {
    let t = tempfile::tempdir().unwrap();
    let p = load(t.path(), BRANCHES);
    let o = options(t.path());
    for (what, options) in [
        (
            "--fail-fast",
            RunOptions {
                keep_going: false,
                ..o.clone()
            },
        ),
        (
            "--dry-run",
            RunOptions {
                dry_run: true,
                ..o.clone()
            },
        ),
    ] {
        let Err(RunError::Pipeline(e)) = run(&p, &options) else {
            panic!("{what}: the plan should be refused");
        };
        assert_eq!(
            e.to_string(),
            cannot_read(t.path(), "stage `bad`: "),
            "{what}"
        );
    }
    assert!(!o.out_dir.join("src").exists(), "nothing ran");
}

#[test]
fn a_missing_input_file_fails_its_stage_and_the_other_branch_runs() {
    let t = tempfile::tempdir().unwrap();
    let p = load(t.path(), BRANCHES);
    let o = options(t.path());
    let Err(RunError::Failed(report)) = run(&p, &o) else {
        panic!("a run with a failed stage is an error");
    };
    let bad = report.plan.stage("bad").unwrap();
    assert!(
        matches!(bad.reason, Reason::Unreadable(_)),
        "{:?}",
        bad.reason
    );
    let failed: Vec<(&str, &str, &str)> = (report.failures.iter())
        .map(|f| (f.stage.as_str(), f.kind.as_str(), f.cause.as_str()))
        .collect();
    assert_eq!(
        failed,
        [("bad", "source", cannot_read(t.path(), "").as_str())]
    );
    let blocked: Vec<(&str, &str)> = (report.blocked.iter())
        .map(|b| (b.stage.as_str(), b.because.as_str()))
        .collect();
    assert_eq!(blocked, [("later", "bad"), ("after", "bad")]);
    assert_eq!(report.computed(), 2, "src and double");
    let cache = Cache::open(&o.cache_dir).unwrap();
    for name in ["src", "double"] {
        let key = &report.plan.stage(name).unwrap().key;
        assert!(matches!(cache.check(key), EntryState::Valid(_)), "{name}");
    }
    assert!(o.out_dir.join("double/t.parquet").is_file());
    let summary = report.summary();
    assert!(summary.contains("  FAILED  bad "), "{summary}");
    assert!(summary.contains(" not run  after "), "{summary}");
    let recorded: serde_json::Value =
        serde_json::from_slice(&std::fs::read(o.out_dir.join("provenance.json")).unwrap()).unwrap();
    assert_eq!(recorded["failed"]["bad"]["kind"], "source");
    assert_eq!(
        recorded["failed"]["bad"]["error"].as_str(),
        Some(cannot_read(t.path(), "").as_str())
    );
    assert_eq!(recorded["stages"]["double"]["cache"], "miss");
    let said = RunError::Failed(report).to_string();
    assert!(said.contains(": 1 stage failed, 2 not run"), "{said}");

    // The file given: only the failed branch is computed.
    write(t.path(), "in.csv", "x\n1\n");
    let fixed = run(&p, &o).unwrap();
    assert_eq!((fixed.computed(), fixed.hits()), (3, 2));
    assert!(fixed.provenance.failed.is_empty());
}

/// A folder where a file is expected fails its stage the same way.
#[test]
fn a_folder_for_a_file_fails_its_stage_alone() {
    let t = tempfile::tempdir().unwrap();
    std::fs::create_dir(t.path().join("in.csv")).unwrap();
    let p = load(t.path(), BRANCHES);
    let Err(RunError::Failed(report)) = run(&p, &options(t.path())) else {
        panic!("a run with a failed stage is an error");
    };
    assert_eq!(report.failures.len(), 1);
    let folder = t.path().join("in.csv");
    assert_eq!(
        report.failures[0].cause,
        format!(
            "{}:5:19: parameter `path`: `{}` is a folder; `path` takes a file",
            t.path().join("p.yaml").display(),
            folder.display()
        )
    );
    assert_eq!(report.computed(), 2);
}

/// In a study, the variant whose file is missing fails alone: the other
/// variant runs whole and its tables are gathered.
#[test]
fn a_study_fails_only_the_variant_whose_file_is_missing() {
    let t = tempfile::tempdir().unwrap();
    write(t.path(), "in.csv", "x\n1\n");
    let text = format!(
        "{BRANCHES}study:\n  grid:\n    bad.path: [in.csv, nosuch.csv]\n  collect: [after.rows]\n"
    );
    let p = load(t.path(), &text);
    let o = RunOptions::in_folders(t.path().join("study"), t.path().join("cache"));
    let err = run_study(&p, &o).unwrap_err();
    let RunError::StudyFailed(report) = &err else {
        panic!("{err}");
    };
    assert!(report.runs[0].1.failures.is_empty());
    let second = &report.runs[1].1;
    let failed: Vec<&str> = second.failures.iter().map(|f| f.stage.as_str()).collect();
    assert_eq!(failed, ["bad"]);
    assert!(
        second.failures[0].cause.contains("nosuch.csv"),
        "{}",
        second.failures[0].cause
    );
    let said = err.to_string();
    assert!(said.starts_with("variant 2/2: "), "{said}");
    let rows = hypercontact_io::read_parquet_file(&o.out_dir.join("after.rows.parquet")).unwrap();
    assert_eq!(rows.i64("variant").unwrap()[0], 1);
}
