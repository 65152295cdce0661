//! Every message the runner gives for a pipeline it refuses, pinned as a
//! snapshot: a change of wording or of a reported location shows up in
//! review. Each case is a small pipeline over the test stages.

use crate::common;

use std::path::Path;

use common::{BASIC, registry, write};
use hypercontact_core::Registry;
use hypercontact_runner::cache::Cache;
use hypercontact_runner::plan::{Plan, PlanOptions};
use hypercontact_runner::study::run_study;
use hypercontact_runner::{Pipeline, RunOptions, run};

/// A registry with the test stages and `count-lines`, whose file
/// parameters are nested.
fn stages() -> Registry {
    let mut r = registry();
    r.add(common::CountLines);
    r
}

/// Loads and plans `text` as `bad.yaml` beside `files`, with `sets`
/// applied and `force`d stages; the error, with the folder written `<dir>`.
fn refusal(text: &str, files: &[(&str, &str)], sets: &[&str], force: &[&str]) -> String {
    let t = tempfile::tempdir().unwrap();
    for (name, content) in files {
        write(t.path(), name, content);
    }
    let path = write(t.path(), "bad.yaml", text);
    let result = Pipeline::load(&path, &stages()).and_then(|mut p| {
        for s in sets {
            p.set(s)?;
        }
        let cache = Cache::open(&t.path().join("cache")).unwrap();
        let options = PlanOptions {
            force: force.iter().map(|s| s.to_string()).collect(),
            only: None,
            prune: false,
        };
        Plan::build(&p, &cache, &options, None).map(|_| ())
    });
    let message = result
        .expect_err("the pipeline should be refused")
        .to_string();
    redact(&message, t.path())
}

fn redact(message: &str, dir: &Path) -> String {
    message.replace(&dir.display().to_string(), "<dir>")
}

/// A stage that depends on another's wrong output, for input errors.
const TWO: &str = "name: two\nstages:\n  src:\n    uses: source\n    with: { n: 3 }\n  sink:\n    uses: scale\n    inputs: { t: src }\n";

#[test]
fn pipeline_refusals() {
    let cases: Vec<(&str, String)> = vec![
        (
            "YAML syntax",
            refusal("name: x\nstages: [\n", &[], &[], &[]),
        ),
        (
            "duplicate key",
            refusal("name: x\nname: y\nstages: {}\n", &[], &[], &[]),
        ),
        (
            "two documents",
            refusal("name: x\nstages: {}\n---\nname: y\n", &[], &[], &[]),
        ),
        (
            "top-level typo",
            refusal("nme: x\nstages: {}\n", &[], &[], &[]),
        ),
        ("no name", refusal("stages: {}\n", &[], &[], &[])),
        (
            "stage key typo",
            refusal("name: x\nstages:\n  a:\n    use: source\n", &[], &[], &[]),
        ),
        (
            "unknown kind",
            refusal(&BASIC.replace("uses: scale", "uses: scael"), &[], &[], &[]),
        ),
        (
            "bad stage name",
            refusal(
                "name: x\nstages:\n  a.b:\n    uses: source\n",
                &[],
                &[],
                &[],
            ),
        ),
        (
            "with not a map",
            refusal(
                "name: x\nstages:\n  a:\n    uses: source\n    with: 3\n",
                &[],
                &[],
                &[],
            ),
        ),
        (
            "unknown parameter",
            refusal(&BASIC.replace("factor: 2", "factr: 2"), &[], &[], &[]),
        ),
        (
            "wrong type",
            refusal(&BASIC.replace("n: 5", "n: five"), &[], &[], &[]),
        ),
        (
            "out of range",
            refusal(&BASIC.replace("n: 5", "n: 5000000"), &[], &[], &[]),
        ),
        (
            "missing required parameter",
            refusal(
                "name: x\nstages:\n  c:\n    uses: count-lines\n    with: {}\n",
                &[],
                &[],
                &[],
            ),
        ),
        (
            "nested unknown parameter",
            refusal(
                "name: x\nstages:\n  c:\n    uses: count-lines\n    with:\n      lookup:\n        tabel: a.txt\n",
                &[],
                &[],
                &[],
            ),
        ),
        (
            "empty path",
            refusal(
                "name: x\nstages:\n  c:\n    uses: count-lines\n    with:\n      lookup: { table: \"\" }\n",
                &[],
                &[],
                &[],
            ),
        ),
        (
            "missing input file",
            refusal(
                &BASIC.replace("n: 5 }", "n: 5, path: nowhere.csv }"),
                &[],
                &[],
                &[],
            ),
        ),
        (
            "missing nested input file",
            refusal(
                "name: x\nstages:\n  c:\n    uses: count-lines\n    with:\n      lookup: { table: gone.txt }\n",
                &[],
                &[],
                &[],
            ),
        ),
        (
            "with_file missing",
            refusal(
                &BASIC.replace("with: { value: 2.0e-5, n: 5 }", "with_file: recipe.yaml"),
                &[],
                &[],
                &[],
            ),
        ),
        (
            "with_file a device",
            refusal(
                &BASIC.replace("with: { value: 2.0e-5, n: 5 }", "with_file: /dev/zero"),
                &[],
                &[],
                &[],
            ),
        ),
        (
            "file parameter a device",
            refusal(
                "name: x\nstages:\n  c:\n    uses: count-lines\n    with:\n      lookup: { table: /dev/zero }\n",
                &[],
                &[],
                &[],
            ),
        ),
        (
            "with_file not YAML",
            refusal(
                &BASIC.replace("with: { value: 2.0e-5, n: 5 }", "with_file: recipe.yaml"),
                &[("recipe.yaml", "n: [1\n")],
                &[],
                &[],
            ),
        ),
        (
            "with_file not a map",
            refusal(
                &BASIC.replace("with: { value: 2.0e-5, n: 5 }", "with_file: recipe.yaml"),
                &[("recipe.yaml", "- 1\n- 2\n")],
                &[],
                &[],
            ),
        ),
        (
            "with_file value out of range",
            refusal(
                &BASIC.replace("with: { value: 2.0e-5, n: 5 }", "with_file: recipe.yaml"),
                &[("recipe.yaml", "value: 1\nn: 5000000\n")],
                &[],
                &[],
            ),
        ),
        (
            "no such input",
            refusal(&TWO.replace("{ t: src }", "{ tt: src }"), &[], &[], &[]),
        ),
        (
            "unknown upstream stage",
            refusal(&TWO.replace("{ t: src }", "{ t: srcc }"), &[], &[], &[]),
        ),
        (
            "no such output",
            refusal(&TWO.replace("{ t: src }", "{ t: src.nope }"), &[], &[], &[]),
        ),
        (
            "wrong product kind",
            refusal(
                &format!("{TWO}  again:\n    uses: scale\n    inputs: {{ t: sink.map }}\n"),
                &[],
                &[],
                &[],
            ),
        ),
        (
            "missing column",
            refusal(
                &format!(
                    "{TWO}  rows:\n    uses: gather\n    inputs: {{ parts: {{ a: src }} }}\n  again:\n    uses: scale\n    inputs: {{ t: rows }}\n"
                ),
                &[],
                &[],
                &[],
            ),
        ),
        (
            "missing input",
            refusal(&TWO.replace("    inputs: { t: src }\n", ""), &[], &[], &[]),
        ),
        // Issue 30: a many-input wired without labels reached the stage as
        // no product at all (the report drew "not wired").
        (
            "many-input without labels",
            refusal(
                &format!("{TWO}  rows:\n    uses: gather\n    inputs: {{ parts: src }}\n"),
                &[],
                &[],
                &[],
            ),
        ),
        (
            "many-input labelled twice",
            refusal(
                &format!(
                    "{TWO}  rows:\n    uses: gather\n    inputs: {{ parts: {{ T1: {{ a: src }} }} }}\n"
                ),
                &[],
                &[],
                &[],
            ),
        ),
        (
            "nested input labelled once",
            refusal(
                &format!(
                    "{TWO}  grid:\n    uses: collect-nested\n    inputs: {{ parts: {{ a: src }} }}\n"
                ),
                &[],
                &[],
                &[],
            ),
        ),
        (
            "single input labelled",
            refusal(
                &TWO.replace("inputs: { t: src }", "inputs: { t: { a: src } }"),
                &[],
                &[],
                &[],
            ),
        ),
        (
            "label with a dot",
            refusal(
                &format!(
                    "{TWO}  rows:\n    uses: gather\n    inputs: {{ parts: {{ a.b: src }} }}\n"
                ),
                &[],
                &[],
                &[],
            ),
        ),
        (
            "files without the index an input needs",
            refusal(
                &format!(
                    "{TWO}  idx:\n    uses: files-indexed\n    inputs: {{ maps: sink.figs }}\n"
                ),
                &[],
                &[],
                &[],
            ),
        ),
        (
            "cycle",
            refusal(
                "name: c\nstages:\n  a:\n    uses: scale\n    inputs: { t: b }\n  b:\n    uses: scale\n    inputs: { t: a }\n",
                &[],
                &[],
                &[],
            ),
        ),
        (
            "force an unknown stage",
            refusal(BASIC, &[], &[], &["nope"]),
        ),
        (
            "--set without =",
            refusal(BASIC, &[], &["double.factor"], &[]),
        ),
        (
            "--set value not YAML",
            refusal(BASIC, &[], &["double.factor=[1"], &[]),
        ),
        (
            "--set unknown stage",
            refusal(BASIC, &[], &["nostage.x=1"], &[]),
        ),
        (
            "--set unknown parameter",
            refusal(BASIC, &[], &["double.bogus=1"], &[]),
        ),
        (
            "--set wrong type",
            refusal(BASIC, &[], &["double.factor=abc"], &[]),
        ),
        (
            "--set out of range",
            refusal(BASIC, &[], &["src.n=-1"], &[]),
        ),
        // Issue 12: accepted silently, or with an empty name in the message.
        (
            "duplicate stage name",
            refusal(
                &format!("{BASIC}  double:\n    uses: scale\n    inputs: {{ t: src }}\n"),
                &[],
                &[],
                &[],
            ),
        ),
        (
            "duplicate input key",
            refusal(
                &BASIC.replace("inputs: { t: src }", "inputs:\n      t: src\n      t: src"),
                &[],
                &[],
                &[],
            ),
        ),
        ("no stages", refusal("name: x\nstages: {}\n", &[], &[], &[])),
        (
            "pipeline name escapes the output folder",
            refusal(
                &BASIC.replace("name: basic", "name: ../../escaped"),
                &[],
                &[],
                &[],
            ),
        ),
        (
            "pipeline name with a space",
            refusal(&BASIC.replace("name: basic", "name: my run"), &[], &[], &[]),
        ),
        (
            "stage name with a slash",
            refusal(&BASIC.replace("  double:", "  a/b:"), &[], &[], &[]),
        ),
        (
            "--set empty stage name",
            refusal(BASIC, &[], &[".factor=1"], &[]),
        ),
        (
            "--set empty parameter name",
            refusal(BASIC, &[], &["double.=1"], &[]),
        ),
        ("--set empty path", refusal(BASIC, &[], &["=1"], &[])),
        (
            "slurm: memory not in Slurm's notation",
            refusal(&format!("{BASIC}slurm: {{ mem: 4X }}\n"), &[], &[], &[]),
        ),
        (
            "slurm: a stage's time limit of zero",
            refusal(
                &BASIC.replace("  double:\n", "  double:\n    slurm: { time: \"0:00\" }\n"),
                &[],
                &[],
                &[],
            ),
        ),
        (
            "slurm: unknown key",
            refusal(&format!("{BASIC}slurm: {{ memory: 4G }}\n"), &[], &[], &[]),
        ),
        (
            "slurm: zero CPUs",
            refusal(&format!("{BASIC}slurm: {{ cpus: 0 }}\n"), &[], &[], &[]),
        ),
        (
            "slurm: partition with a space",
            refusal(
                &format!("{BASIC}slurm: {{ partition: a b }}\n"),
                &[],
                &[],
                &[],
            ),
        ),
    ];
    let text: String = cases
        .iter()
        .map(|(name, message)| format!("## {name}\n{message}\n\n"))
        .collect();
    insta::assert_snapshot!(text);
}

/// Refusals of `hypercontact study`, and a stage that fails while running.
#[test]
fn study_and_run_refusals() {
    let t = tempfile::tempdir().unwrap();
    let options = RunOptions {
        dry_run: true,
        ..RunOptions::in_folders(t.path().join("out"), t.path().join("cache"))
    };
    let study = |name: &str, text: &str| {
        let path = write(t.path(), &format!("{name}.yaml"), text);
        // Refused when loaded, or when the study runs.
        let message = match Pipeline::load(&path, &stages()) {
            Err(e) => e.to_string(),
            Ok(pipeline) => run_study(&pipeline, &options)
                .map(|_| ())
                .expect_err("the study should be refused")
                .to_string(),
        };
        redact(&message, t.path())
    };
    let mut cases: Vec<(&str, String)> = vec![
        ("no study", study("none", BASIC)),
        (
            "collect not STAGE.OUTPUT",
            study("format", &format!("{BASIC}study:\n  collect: [double]\n")),
        ),
        (
            "collect unknown stage",
            study("stage", &format!("{BASIC}study:\n  collect: [triple.t]\n")),
        ),
        (
            "collect not a table",
            study(
                "table",
                &format!("{BASIC}study:\n  collect: [double.map]\n"),
            ),
        ),
        (
            "grid value is an empty list",
            study(
                "empty",
                &format!("{BASIC}study:\n  grid:\n    src.n: []\n  collect: [double.t]\n"),
            ),
        ),
        (
            "grid names an unknown stage",
            study(
                "unknown",
                &format!("{BASIC}study:\n  grid:\n    triple.n: [1]\n  collect: [double.t]\n"),
            ),
        ),
        (
            "collect a temporary stage",
            study(
                "temp",
                &format!(
                    "{}study:\n  collect: [src.t]\n",
                    BASIC.replace("uses: source", "uses: source\n    temp: true")
                ),
            ),
        ),
        (
            "grid value out of range",
            study(
                "grid",
                &format!(
                    "{BASIC}study:\n  grid:\n    src.n: [1, 5000000]\n  collect: [double.t]\n"
                ),
            ),
        ),
    ];
    // A stage that fails at run time: its CSV has no `x` column.
    write(t.path(), "y.csv", "y\n1\n");
    let path = write(
        t.path(),
        "fails.yaml",
        &BASIC.replace("n: 5 }", "n: 5, path: y.csv }"),
    );
    let pipeline = Pipeline::load(&path, &stages()).unwrap();
    let failed = run(
        &pipeline,
        &RunOptions {
            dry_run: false,
            ..options.clone()
        },
    )
    .map(|_| ())
    .expect_err("the stage fails")
    .to_string();
    cases.push(("stage failure", redact(&failed, t.path())));
    let text: String = cases
        .iter()
        .map(|(name, message)| format!("## {name}\n{message}\n\n"))
        .collect();
    insta::assert_snapshot!(text);
}
