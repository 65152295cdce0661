//! The runner against small test stages: keys, invalidation, crash safety,
//! concurrency, corruption, re-runs and YAML errors.

use crate::common;

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

use common::{BASIC, SCALE_LET_GOS, SCALE_RUNS, registry, write};
use hypercontact_runner::cache::{Cache, EntryState, MANIFEST_FORMAT};
use hypercontact_runner::plan::{Plan, PlanOptions, Reason};
use hypercontact_runner::provenance::CacheUse;
use hypercontact_runner::{Pipeline, RunOptions, run};

fn options(dir: &Path) -> RunOptions {
    RunOptions::in_folders(dir.join("out"), dir.join("cache"))
}

/// What a dry run of `p` with options `o` would do.
fn dry_plan(p: &Pipeline, o: &RunOptions) -> Plan {
    let dry = RunOptions {
        dry_run: true,
        ..o.clone()
    };
    run(p, &dry).unwrap().plan
}

fn load(dir: &Path, name: &str, text: &str) -> Pipeline {
    let path = write(dir, name, text);
    Pipeline::load(&path, &registry()).unwrap()
}

fn keys(p: &Pipeline, dir: &Path) -> Vec<String> {
    let cache = Cache::open(&dir.join("cache")).unwrap();
    Plan::build(p, &cache, &PlanOptions::default(), None)
        .unwrap()
        .stages
        .into_iter()
        .map(|s| s.key)
        .collect()
}

#[test]
fn a_kind_lets_go_of_what_it_keeps_once_another_kind_follows() {
    // src, a, b (two of a kind, side by side), all, c: `scale` is asked to
    // let go after b and after c, on the thread that ran them, not after a.
    let t = tempfile::tempdir().unwrap();
    let text = "name: letgo\nstages:\n  src:\n    uses: source\n    with: { n: 2 }\n  \
        a:\n    uses: scale\n    inputs: { t: src }\n  b:\n    uses: scale\n    inputs: { t: src }\n    \
        with: { factor: 3 }\n  all:\n    uses: gather\n    inputs:\n      parts: { a: a.t, b: b.t }\n  \
        c:\n    uses: scale\n    inputs: { t: src }\n    with: { factor: 4 }\n";
    let p = load(t.path(), "p.yaml", text);
    let order: Vec<String> = dry_plan(&p, &options(t.path()))
        .stages
        .iter()
        .map(|s| s.name.clone())
        .collect();
    assert_eq!(order, ["src", "a", "b", "all", "c"]);
    let before = SCALE_LET_GOS.with(|n| n.get());
    run(&p, &options(t.path())).unwrap();
    assert_eq!(SCALE_LET_GOS.with(|n| n.get()) - before, 2);
}

#[test]
fn keys_ignore_parameter_order_and_float_spelling() {
    let t = tempfile::tempdir().unwrap();
    let a = load(t.path(), "a.yaml", BASIC);
    let reordered = BASIC
        .replace(
            "{ value: 2.0e-5, n: 5 }",
            "\n      n: 5\n      value: 20e-6",
        )
        .replace("{ factor: 2 }", "{ factor: 2.0, sleep_ms: 0 }");
    let b = load(t.path(), "b.yaml", &reordered);
    assert_eq!(keys(&a, t.path()), keys(&b, t.path()));
    let changed = load(t.path(), "c.yaml", &BASIC.replace("factor: 2", "factor: 3"));
    let (ka, kc) = (keys(&a, t.path()), keys(&changed, t.path()));
    assert_eq!(
        ka[0], kc[0],
        "the upstream key does not depend on downstream params"
    );
    assert_ne!(ka[1], kc[1]);
}

#[test]
fn changes_invalidate_exactly_what_depends_on_them() {
    let t = tempfile::tempdir().unwrap();
    let csv = write(t.path(), "x.csv", "x\n1.5\n2.5\n");
    let text = BASIC.replace("n: 5 }", "n: 5, path: x.csv }");
    let p = load(t.path(), "p.yaml", &text);
    let o = options(t.path());
    let first = run(&p, &o).unwrap();
    assert_eq!(first.computed(), 2);

    // Input file edited: both stages rerun, the plan says why.
    std::fs::write(&csv, "x\n1.5\n2.75\n").unwrap();
    let plan = dry_plan(&p, &o);
    assert!(matches!(&plan.stages[0].reason, Reason::FilesChanged(f) if f[0].ends_with("x.csv")));
    assert!(
        matches!(&plan.stages[1].reason, Reason::InputsChanged(i) if i[0].contains("src reruns"))
    );
    run(&p, &o).unwrap();

    // Parameter change downstream: only that stage.
    let mut q = p.clone();
    q.set("double.factor=4").unwrap();
    let plan = dry_plan(&q, &o);
    assert_eq!(plan.stages[0].reason, Reason::Cached);
    assert!(
        matches!(&plan.stages[1].reason, Reason::ParamsChanged(c) if c[0].starts_with("factor"))
    );

    // Version change: same kind name, new implementation version.
    let mut r2 = hypercontact_core::Registry::new();
    r2.add(common::Source).add(Scale2);
    let p2 = Pipeline::load(&t.path().join("p.yaml"), &r2).unwrap();
    let plan = dry_plan(&p2, &o);
    assert_eq!(plan.stages[0].reason, Reason::Cached);
    assert_eq!(
        plan.stages[1].reason,
        Reason::VersionChanged { from: 1, to: 2 }
    );
}

/// `scale` with a bumped version.
struct Scale2;
impl hypercontact_core::Stage for Scale2 {
    type Params = common::ScaleParams;
    fn info(&self) -> &'static hypercontact_core::StageInfo {
        static INFO: std::sync::OnceLock<hypercontact_core::StageInfo> = std::sync::OnceLock::new();
        INFO.get_or_init(|| hypercontact_core::StageInfo {
            version: 2,
            ..*hypercontact_core::Stage::info(&common::Scale)
        })
    }
    fn run(
        &self,
        p: &hypercontact_core::Checked<Self::Params>,
        i: &hypercontact_core::Inputs,
        c: &hypercontact_core::Context,
    ) -> Result<hypercontact_core::Outputs, hypercontact_core::StageError> {
        hypercontact_core::Stage::run(&common::Scale, p, i, c)
    }
}

#[test]
fn second_run_is_all_hits_with_identical_outputs() {
    let t = tempfile::tempdir().unwrap();
    let p = load(t.path(), "p.yaml", BASIC);
    let o = options(t.path());
    run(&p, &o).unwrap();
    let files = [
        "src/t.parquet",
        "double/t.parquet",
        "double/map.npy",
        "double/map.grid.json",
        "double/note.txt",
    ];
    let before: Vec<Vec<u8>> = files
        .iter()
        .map(|f| std::fs::read(o.out_dir.join(f)).unwrap())
        .collect();
    let again = run(&p, &o).unwrap();
    assert_eq!(again.hits(), 2);
    assert_eq!(again.computed(), 0);
    let after: Vec<Vec<u8>> = files
        .iter()
        .map(|f| std::fs::read(o.out_dir.join(f)).unwrap())
        .collect();
    assert_eq!(before, after);
    let prov: serde_json::Value =
        serde_json::from_slice(&std::fs::read(o.out_dir.join("provenance.json")).unwrap()).unwrap();
    assert_eq!(prov["stages"]["double"]["cache"], "hit");
    assert_eq!(prov["stages"]["double"]["inputs"]["t"]["from"], "src.t");
    assert!(prov["stages"]["src"]["outputs"]["src/t.parquet"].is_string());
}

#[test]
fn a_crash_mid_write_leaves_no_entry_and_the_next_run_recovers() {
    let t = tempfile::tempdir().unwrap();
    let p = load(t.path(), "p.yaml", BASIC);
    let o = options(t.path());
    let crashed = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let mut written = 0;
        hypercontact_runner::exec::run_with_hook(&p, &o, &mut |_| {
            written += 1;
            if written == 3 {
                panic!("simulated kill after the third file");
            }
        })
    }));
    assert!(crashed.is_err());
    let cache = Cache::open(&o.cache_dir).unwrap();
    let ks = keys(&p, t.path());
    assert!(
        matches!(cache.check(&ks[0]), EntryState::Valid(_)),
        "src finished before the crash"
    );
    assert!(
        matches!(cache.check(&ks[1]), EntryState::Missing),
        "no half-written entry"
    );
    assert!(
        std::fs::read_dir(o.cache_dir.join("tmp")).unwrap().count() > 0,
        "debris stays in tmp/"
    );
    let report = run(&p, &o).unwrap();
    assert_eq!((report.hits(), report.computed()), (1, 1));
    assert!(matches!(cache.check(&ks[1]), EntryState::Valid(_)));
}

#[test]
fn a_corrupt_entry_is_detected_and_recomputed() {
    let t = tempfile::tempdir().unwrap();
    let p = load(t.path(), "p.yaml", BASIC);
    let o = options(t.path());
    run(&p, &o).unwrap();
    // The run that wrote an entry stamps it after exporting it; from then
    // on only changed stat data makes a check read the files again.
    let key = &keys(&p, t.path())[1];
    let stamps = o.cache_dir.join("stamps").join(format!("{key}.json"));
    let written = std::fs::read(&stamps).unwrap();
    run(&p, &o).unwrap();
    assert_eq!(
        std::fs::read(&stamps).unwrap(),
        written,
        "a hit needs no new stamp"
    );
    let victim: PathBuf = o.cache_dir.join("entries").join(key).join("t.parquet");
    let modified = std::fs::metadata(&victim).unwrap().modified().unwrap();
    let mut perms = std::fs::metadata(&victim).unwrap().permissions();
    #[allow(clippy::permissions_set_readonly_false)]
    perms.set_readonly(false);
    std::fs::set_permissions(&victim, perms).unwrap();
    let mut bytes = std::fs::read(&victim).unwrap();
    let mid = bytes.len() / 2;
    bytes[mid] ^= 0xff;
    std::fs::write(&victim, &bytes).unwrap();
    // Same size, mtime set back: only the ctime tells, and it does.
    std::fs::File::options()
        .append(true)
        .open(&victim)
        .unwrap()
        .set_modified(modified)
        .unwrap();

    let plan = dry_plan(&p, &o);
    assert!(
        matches!(&plan.stages[1].reason, Reason::NotInCache(why) if why.contains("hash")),
        "{:?}",
        plan.stages[1].reason
    );
    let report = run(&p, &o).unwrap();
    assert_eq!(report.provenance.stages["double"].cache, CacheUse::Miss);
    let cache = Cache::open(&o.cache_dir).unwrap();
    assert!(matches!(cache.check(key), EntryState::Valid(_)));
}

/// An entry of the format before tables carried their units (1) is not
/// served: the stage is computed again and its table now has its units.
#[test]
fn an_entry_of_an_older_format_is_recomputed_with_units() {
    let t = tempfile::tempdir().unwrap();
    let p = load(t.path(), "p.yaml", BASIC);
    let o = options(t.path());
    run(&p, &o).unwrap();
    let key = &keys(&p, t.path())[1];
    let entry = o.cache_dir.join("entries").join(key);
    let manifest_path = entry.join("manifest.json");
    let mut manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&manifest_path).unwrap()).unwrap();
    assert_eq!(manifest["format"], MANIFEST_FORMAT);
    manifest["format"] = (MANIFEST_FORMAT - 1).into();
    let mut perms = std::fs::metadata(&manifest_path).unwrap().permissions();
    #[allow(clippy::permissions_set_readonly_false)]
    perms.set_readonly(false);
    std::fs::set_permissions(&manifest_path, perms).unwrap();
    std::fs::write(&manifest_path, manifest.to_string()).unwrap();

    let report = run(&p, &o).unwrap();
    assert_eq!(report.provenance.stages["double"].cache, CacheUse::Miss);
    assert_eq!(report.provenance.stages["src"].cache, CacheUse::Hit);
    let cache = Cache::open(&o.cache_dir).unwrap();
    assert!(matches!(cache.check(key), EntryState::Valid(_)));
    let file = std::fs::File::open(entry.join("t.parquet")).unwrap();
    let meta = hypercontact_io::parquet_columns_meta(file).unwrap();
    assert_eq!(
        (meta.len(), meta[0].name.as_str(), meta[0].unit.as_str()),
        (1, "x", "m")
    );
}

#[test]
fn two_concurrent_runs_compute_each_entry_once() {
    let t = tempfile::tempdir().unwrap();
    let text = BASIC.replace("{ factor: 2 }", "{ factor: 7, sleep_ms: 400 }");
    let p = load(t.path(), "p.yaml", &text);
    let before = SCALE_RUNS.load(Ordering::SeqCst);
    let handles: Vec<_> = (0..2)
        .map(|i| {
            let p = p.clone();
            let mut o = options(t.path());
            o.out_dir = t.path().join(format!("out{i}"));
            std::thread::spawn(move || run(&p, &o).unwrap())
        })
        .collect();
    let reports: Vec<_> = handles.into_iter().map(|h| h.join().unwrap()).collect();
    // Other tests run `scale` too, with other factors; count this key only.
    let computed: usize = reports
        .iter()
        .map(|r| (r.provenance.stages["double"].cache == CacheUse::Miss) as usize)
        .sum();
    assert_eq!(computed, 1, "exactly one run computed the shared entry");
    assert!(SCALE_RUNS.load(Ordering::SeqCst) - before >= 1);
    let a = std::fs::read(t.path().join("out0/double/t.parquet")).unwrap();
    let b = std::fs::read(t.path().join("out1/double/t.parquet")).unwrap();
    assert_eq!(a, b);
}

#[test]
fn a_nested_input_reaches_the_stage_by_sample_and_model() {
    let t = tempfile::tempdir().unwrap();
    let text = format!(
        "{BASIC}  other:\n    uses: source\n    with: {{ n: 3 }}\n  grid:\n    uses: collect-nested\n    inputs:\n      parts:\n        T2: {{ icm: other }}\n        T1: {{ icm: double.t, bem-linear: other }}\n"
    );
    let p = load(t.path(), "p.yaml", &text);
    let o = options(t.path());
    run(&p, &o).unwrap();
    let rows = hypercontact_io::read_parquet_file(&o.out_dir.join("grid/rows.parquet")).unwrap();
    assert_eq!(rows.str("sample").unwrap(), ["T1", "T1", "T2"]);
    assert_eq!(rows.str("model").unwrap(), ["bem-linear", "icm", "icm"]);
}

#[test]
fn force_only_and_many_inputs() {
    let t = tempfile::tempdir().unwrap();
    let text = format!(
        "{BASIC}  other:\n    uses: source\n    with: {{ n: 3 }}\n  all:\n    uses: gather\n    inputs:\n      parts: {{ b: double.t, a: other }}\n"
    );
    let p = load(t.path(), "p.yaml", &text);
    let o = options(t.path());
    let report = run(&p, &o).unwrap();
    assert_eq!(report.computed(), 4);
    let rows = hypercontact_io::read_parquet_file(&o.out_dir.join("all/rows.parquet")).unwrap();
    assert_eq!(rows.str("label").unwrap(), ["a", "b"]);
    assert_eq!(rows.i64("n").unwrap(), &[3, 5]);

    let forced = RunOptions {
        plan: PlanOptions {
            force: vec!["double".into()],
            only: None,
            prune: false,
        },
        ..o.clone()
    };
    let report = run(&p, &forced).unwrap();
    assert_eq!(report.provenance.stages["double"].cache, CacheUse::Forced);
    assert_eq!(
        report.provenance.stages["all"].cache,
        CacheUse::Hit,
        "same output, same key downstream"
    );

    let only = RunOptions {
        plan: PlanOptions {
            force: vec![],
            only: Some("double".into()),
            prune: false,
        },
        dry_run: true,
        ..o
    };
    let plan = run(&p, &only).unwrap().plan;
    assert_eq!(plan.stage("other").unwrap().reason, Reason::NotSelected);
    assert_eq!(plan.stage("all").unwrap().reason, Reason::NotSelected);
    assert_eq!(plan.stage("src").unwrap().reason, Reason::Cached);
}

#[test]
fn a_study_shares_upstream_stages_and_gathers_tables() {
    let t = tempfile::tempdir().unwrap();
    let text = format!(
        "{BASIC}study:\n  grid:\n    double.factor: [1, 2, 3]\n    src.n: [2, 4]\n  collect: [double.t]\n"
    );
    let p = load(t.path(), "p.yaml", &text);
    let o = options(t.path());
    let report = hypercontact_runner::study::run_study(&p, &o).unwrap();
    assert_eq!(report.runs.len(), 6);
    let computed: usize = report.runs.iter().map(|(_, r)| r.computed()).sum();
    assert_eq!(computed, 2 + 6, "two sources, six scales");
    let table = hypercontact_io::read_parquet_file(&o.out_dir.join("double.t.parquet")).unwrap();
    assert_eq!(
        table.column_names(),
        ["variant", "double.factor", "src.n", "x"]
    );
    assert_eq!(table.n_rows(), 3 * (2 + 4));
    assert_eq!(table.i64("double.factor").unwrap()[table.n_rows() - 1], 3);
    assert_eq!(table.i64("variant").unwrap()[table.n_rows() - 1], 6);
}

/// Issue #37, item 2: a stage the varied parameter does not reach has the
/// same entry in every variant, and its rows come once (under variant 1,
/// with no parameter column); the varied stage's rows come per variant
/// with `variant` and the parameter. Variants export to
/// `<study>/variants/001…`, `study.json` numbers them the same way, and a
/// dry run shows the shared entry as RUN once and then as shared.
#[test]
fn a_study_collects_each_entry_once_with_its_variant() {
    let t = tempfile::tempdir().unwrap();
    let text = format!(
        "{BASIC}study:\n  grid:\n    double.factor: [1, 2, 3]\n  collect: [src.t, double.t]\n"
    );
    let p = load(t.path(), "p.yaml", &text);
    let o = RunOptions::in_folders(t.path().join("study"), t.path().join("cache"));
    let dry = hypercontact_runner::study::run_study(
        &p,
        &RunOptions {
            dry_run: true,
            ..o.clone()
        },
    )
    .unwrap()
    .describe();
    let src_lines: Vec<&str> = dry.lines().filter(|l| l.contains(" src ")).collect();
    assert_eq!(src_lines.len(), 3, "{dry}");
    assert!(src_lines[0].trim_start().starts_with("RUN"), "{dry}");
    for line in &src_lines[1..] {
        assert!(
            line.trim_start().starts_with("shared")
                && line.ends_with("computed once, by variant 1"),
            "{dry}"
        );
    }
    assert!(dry.starts_with("variant 1/3: double.factor=1\n"), "{dry}");
    assert!(
        dry.ends_with(
            "study: 4 entries to compute (1 of them shared by several variants), 0 cached\n"
        ),
        "{dry}"
    );

    let report = hypercontact_runner::study::run_study(&p, &o).unwrap();
    assert_eq!(report.dir, o.out_dir);
    let src = hypercontact_io::read_parquet_file(&o.out_dir.join("src.t.parquet")).unwrap();
    assert_eq!(src.column_names(), ["variant", "x"]);
    assert_eq!(src.n_rows(), 5, "one source, not three copies of it");
    assert_eq!(src.i64("variant").unwrap(), [1; 5]);
    let double = hypercontact_io::read_parquet_file(&o.out_dir.join("double.t.parquet")).unwrap();
    assert_eq!(double.column_names(), ["variant", "double.factor", "x"]);
    assert_eq!(double.n_rows(), 15);
    assert_eq!(double.i64("variant").unwrap()[5..10], [2; 5]);
    assert_eq!(double.i64("double.factor").unwrap()[10..], [3; 5]);
    // x = 2e-5·i times the factor, the third variant's.
    assert_eq!(double.f64("x").unwrap()[14], 3.0 * 4.0 * 2.0e-5);
    for k in ["001", "002", "003"] {
        assert!(
            o.out_dir
                .join("variants")
                .join(k)
                .join("double/t.parquet")
                .is_file()
        );
    }
    let record: serde_json::Value =
        serde_json::from_slice(&std::fs::read(o.out_dir.join("study.json")).unwrap()).unwrap();
    assert_eq!(record[2]["index"], 3);
    assert_eq!(record[2]["values"]["double.factor"], 3);
}

/// Two independent branches under one pipeline: `bad` fails at run time
/// (its CSV has no column x) and `after` depends on it through `later`;
/// `src` and `double` do not depend on it.
const BRANCHES: &str = "\
name: branches
stages:
  bad:
    uses: source
    with: { n: 1, path: y.csv }
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

#[test]
fn thousands_of_failures_are_counted_past_the_first_twenty() {
    // #50: 1 041 failed crops of a generated pipeline printed 1 041 lines.
    let t = tempfile::tempdir().unwrap();
    write(t.path(), "y.csv", "y\n1\n");
    let mut text = String::from("name: many\nstages:\n");
    for i in 0..25 {
        text.push_str(&format!(
            "  bad{i}:\n    uses: source\n    with: {{ n: {}, path: y.csv }}\n  \
             later{i}:\n    uses: scale\n    inputs: {{ t: bad{i} }}\n",
            i + 1
        ));
    }
    let p = load(t.path(), "p.yaml", &text);
    let hypercontact_runner::RunError::Failed(report) = run(&p, &options(t.path())).unwrap_err()
    else {
        panic!("a run with failed stages is an error");
    };
    let said = report.failure_text();
    assert!(said.contains(": 25 stages failed, 25 not run"), "{said}");
    assert_eq!(said.matches("\n  stage `bad").count(), 20, "{said}");
    assert_eq!(
        said.matches(" not run: it depends on ").count(),
        20,
        "{said}"
    );
    assert!(
        said.contains("\n  … and 5 more failures: provenance.json lists each under `failed`"),
        "{said}"
    );
    assert!(said.ends_with("\n  … and 5 more stages not run"), "{said}");
}

/// Issue #37, item 1: a run keeps going past a failed stage (the default):
/// the independent branch is computed, cached and exported with its
/// provenance, the failure is listed with its cause and the stages that
/// depend on it as not run, nothing of the failed stage is in the cache,
/// and the run is an error. With `keep_going` off, the run stops at the
/// failure: the other branch (later in the order) is not run.
#[test]
fn a_run_keeps_going_past_a_failed_branch() {
    let t = tempfile::tempdir().unwrap();
    write(t.path(), "y.csv", "y\n1\n");
    let p = load(t.path(), "p.yaml", BRANCHES);
    let o = options(t.path());
    let order: Vec<String> = dry_plan(&p, &o)
        .stages
        .into_iter()
        .map(|s| s.name)
        .collect();
    assert_eq!(order, ["bad", "later", "src", "after", "double"]);

    let stopped = run(
        &p,
        &RunOptions {
            keep_going: false,
            ..o.clone()
        },
    )
    .unwrap_err();
    assert!(
        matches!(stopped, hypercontact_runner::RunError::Stage { .. }),
        "{stopped}"
    );
    assert!(
        !o.out_dir.join("src").exists(),
        "nothing after the failure ran"
    );

    let hypercontact_runner::RunError::Failed(report) = run(&p, &o).unwrap_err() else {
        panic!("a run with a failed stage is an error");
    };
    let failed: Vec<(&str, &str)> = (report.failures.iter())
        .map(|f| (f.stage.as_str(), f.kind.as_str()))
        .collect();
    assert_eq!(failed, [("bad", "source")]);
    assert_eq!(report.failures[0].cause, "no column `x` (the table has: y)");
    let blocked: Vec<(&str, &str)> = (report.blocked.iter())
        .map(|b| (b.stage.as_str(), b.because.as_str()))
        .collect();
    assert_eq!(blocked, [("later", "bad"), ("after", "bad")]);
    assert_eq!(report.computed(), 2, "src and double");
    let cache = Cache::open(&o.cache_dir).unwrap();
    for name in ["src", "double"] {
        let key = &report.plan.stage(name).unwrap().key;
        assert!(
            matches!(cache.check(key), EntryState::Valid(_)),
            "{name} cached"
        );
        assert_eq!(report.provenance.stages[name].cache, CacheUse::Miss);
    }
    assert!(o.out_dir.join("double/t.parquet").is_file());
    let bad_key = &report.plan.stage("bad").unwrap().key;
    assert!(matches!(cache.check(bad_key), EntryState::Missing));
    let debris: Vec<_> = walk(&o.cache_dir)
        .into_iter()
        .filter(|f| f.to_string_lossy().contains(bad_key.as_str()))
        // Its lock file is no entry (gc removes it with the debris).
        .filter(|f| !f.starts_with(o.cache_dir.join("locks")))
        .collect();
    assert!(debris.is_empty(), "{debris:?}");
    let recorded: serde_json::Value =
        serde_json::from_slice(&std::fs::read(o.out_dir.join("provenance.json")).unwrap()).unwrap();
    assert_eq!(recorded["stages"]["double"]["cache"], "miss");
    assert!(recorded["stages"].get("bad").is_none());
    // Issue #50, item 10: the failed stage is recorded with its time and
    // error, and `timings` lists it.
    assert_eq!(recorded["format"], 2);
    assert_eq!(recorded["failed"]["bad"]["kind"], "source");
    assert_eq!(
        recorded["failed"]["bad"]["error"],
        "no column `x` (the table has: y)"
    );
    let failed_s = recorded["failed"]["bad"]["wall_s"].as_f64().unwrap();
    assert!(
        failed_s >= 0.0 && failed_s <= recorded["wall_s"].as_f64().unwrap(),
        "{failed_s}"
    );
    let record = hypercontact_runner::provenance::Provenance::load_with_times(
        &o.out_dir.join("provenance.json"),
    )
    .unwrap();
    let table = hypercontact_runner::timings::table(&record);
    assert!(
        table
            .lines()
            .any(|l| l.starts_with("bad ") && l.contains(" FAILED ")),
        "{table}"
    );
    assert!(
        table.contains("3 stages: 2 computed, 0 cached, 1 failed;"),
        "{table}"
    );
    // The summary and the error say it all.
    let summary = report.summary();
    assert!(summary.contains("  FAILED  bad "), "{summary}");
    assert!(
        summary.contains(" not run  after ") && summary.contains("(`bad` failed)"),
        "{summary}"
    );
    let said = hypercontact_runner::RunError::Failed(report).to_string();
    assert!(
        said.starts_with(&format!("{}: 1 stage failed, 2 not run", p.file.display()))
            && said.contains(": 1 stage failed, 2 not run because they depend on a failed one; every other stage ran and is cached\n  stage `bad` (source): "),
        "{said}"
    );
    assert!(
        said.ends_with("\n  `after` not run: it depends on `bad`, which failed"),
        "{said}"
    );

    // Fixed: what ran is cached, the rest runs now, and the record has
    // no failure left.
    write(t.path(), "y.csv", "x\n1\n");
    let fixed = run(&p, &o).unwrap();
    assert_eq!((fixed.computed(), fixed.hits()), (3, 2));
    assert!(fixed.provenance.failed.is_empty());
}

/// A study keeps going past a failed variant, computes a failing entry
/// its variants share only once, gathers the variants that ran, and
/// fails naming the variants.
#[test]
fn a_study_keeps_going_past_a_failed_variant() {
    let t = tempfile::tempdir().unwrap();
    write(t.path(), "y.csv", "y\n1\n");
    let text = format!(
        "{BRANCHES}study:\n  grid:\n    double.factor: [1, 2]\n  collect: [double.t, after.rows]\n"
    );
    let p = load(t.path(), "p.yaml", &text);
    let o = RunOptions::in_folders(t.path().join("study"), t.path().join("cache"));
    let err = hypercontact_runner::study::run_study(&p, &o).unwrap_err();
    let hypercontact_runner::RunError::StudyFailed(report) = &err else {
        panic!("{err}");
    };
    let second = &report.runs[1].1.failures[0];
    assert!(
        second
            .cause
            .contains("failed in an earlier variant; not run again"),
        "{}",
        second.cause
    );
    let said = err.to_string();
    assert!(said.starts_with("variant 1/2: "), "{said}");
    assert!(said.contains("p.yaml: 1 stage failed"), "{said}");
    assert!(said.contains("\nvariant 2/2: "), "{said}");
    let double = hypercontact_io::read_parquet_file(&o.out_dir.join("double.t.parquet")).unwrap();
    assert_eq!(double.i64("variant").unwrap(), [[1; 5], [2; 5]].concat());
    assert!(
        !o.out_dir.join("after.rows.parquet").exists(),
        "no variant ran `after`"
    );
    assert_eq!(report.tables.len(), 1);
    let record: serde_json::Value =
        serde_json::from_slice(&std::fs::read(o.out_dir.join("study.json")).unwrap()).unwrap();
    assert_eq!(record[0]["failed"], serde_json::json!(["bad"]));
    assert_eq!(record[1]["not_run"], serde_json::json!(["later", "after"]));
}

fn error_of(text: &str, files: &[(&str, &str)]) -> String {
    let t = tempfile::tempdir().unwrap();
    for (name, content) in files {
        write(t.path(), name, content);
    }
    let path = write(t.path(), "bad.yaml", text);
    let result = Pipeline::load(&path, &registry()).and_then(|p| {
        let cache = Cache::open(&t.path().join("cache")).unwrap();
        Plan::build(&p, &cache, &PlanOptions::default(), None).map(|_| ())
    });
    let e = result
        .expect_err("the pipeline should be refused")
        .to_string();
    assert!(e.contains("bad.yaml"), "{e}");
    e
}

#[test]
fn yaml_errors_name_file_line_and_stage() {
    let cyclic = "name: c\nstages:\n  a:\n    uses: scale\n    inputs: { t: b }\n  b:\n    uses: scale\n    inputs: { t: a }\n";
    // Each broken pipeline and what its error must say.
    let cases: [(String, &[&str]); 10] = [
        (
            BASIC.replace("uses: scale", "uses: scael"),
            &[
                "bad.yaml:7:",
                "unknown stage kind `scael`",
                "gather, scale, source",
            ],
        ),
        (
            BASIC.replace("factor: 2", "factr: 2"),
            &["bad.yaml:9:", "unknown field `factr`", "`double`"],
        ),
        (
            BASIC.replace("n: 5", "n: five"),
            &["bad.yaml:5:", "invalid type", "`src`"],
        ),
        (
            BASIC.replace("n: 5", "n: 5000000"),
            &["bad.yaml:5", "parameter `n`"],
        ),
        (
            BASIC.replace("    inputs: { t: src }\n", ""),
            &["bad.yaml:6", "stage `double`", "missing input `t`"],
        ),
        (
            BASIC.replace("{ t: src }", "{ t: srcc }"),
            &["bad.yaml:8", "unknown stage `srcc`"],
        ),
        (cyclic.to_string(), &["cycle", "a → b → a"]),
        (
            BASIC.replace("n: 5 }", "n: 5, path: nowhere.csv }"),
            &["bad.yaml:5", "parameter `path`", "nowhere.csv"],
        ),
        (
            "name: x\nstages:\n  a:\n    use: source\n".to_string(),
            &["bad.yaml:4:", "unknown field `use`"],
        ),
        (
            BASIC.replace("{ t: src }", "{ t: src.nope }"),
            &["has no output `nope`", "its outputs: t"],
        ),
    ];
    for (text, parts) in &cases {
        let e = error_of(text, &[]);
        for part in *parts {
            assert!(e.contains(part), "{part:?} not in: {e}");
        }
    }
}

#[test]
fn set_errors_name_the_assignment() {
    let t = tempfile::tempdir().unwrap();
    let mut p = load(t.path(), "p.yaml", BASIC);
    let e = p.set("double.factor=abc").unwrap_err().to_string();
    assert!(
        e.contains("--set `double.factor=abc`") && e.contains("invalid type"),
        "{e}"
    );
    let e = p.set("nostage.x=1").unwrap_err().to_string();
    assert!(e.contains("no stage `nostage`"), "{e}");
    let e = p.set("double.bogus=1").unwrap_err().to_string();
    assert!(e.contains("unknown field `bogus`"), "{e}");
    // Issue 12: empty names were reported as "no stage ``" / "unknown field ``".
    for empty in [
        ".factor=1",
        "double.=1",
        "=1",
        "double..factor=1",
        "double.factor.=1",
    ] {
        let e = p.set(empty).unwrap_err().to_string();
        assert!(
            e.contains("STAGE.PARAM") && !e.contains("``"),
            "{empty}: {e}"
        );
    }
    p.set("double.factor=5").unwrap();
}

#[test]
fn with_file_supplies_parameters_that_with_overrides() {
    let t = tempfile::tempdir().unwrap();
    write(t.path(), "recipe.yaml", "# a recipe\nvalue: 3.0e-5\nn: 7\n");
    let text = BASIC.replace(
        "    with: { value: 2.0e-5, n: 5 }\n",
        "    with_file: recipe.yaml\n    with: { n: 9 }\n",
    );
    assert_ne!(text, BASIC, "the test edits the source stage");
    let p = load(t.path(), "p.yaml", &text);
    let src = p.stage("src").unwrap();
    assert_eq!(src.raw_params["value"], 3.0e-5);
    assert_eq!(src.raw_params["n"], 9);

    // The recipe's content enters the key: editing it reruns the stage.
    let before = keys(&p, t.path());
    write(t.path(), "recipe.yaml", "value: 4.0e-5\nn: 7\n");
    let edited = load(t.path(), "p.yaml", &text);
    assert_ne!(keys(&edited, t.path())[0], before[0]);

    // Errors name the recipe file and line, or the with_file key.
    let text = text.replace("    with: { n: 9 }\n", "");
    let e = error_of(&text, &[("recipe.yaml", "value: 3.0e-5\nn: 5000000\n")]);
    assert!(
        e.contains("recipe.yaml:2") && e.contains("parameter `n`"),
        "{e}"
    );
    let e = error_of(&text, &[("recipe.yaml", "value: 1\nnn: 2\n")]);
    assert!(
        e.contains("recipe.yaml:2") && e.contains("unknown field `nn`"),
        "{e}"
    );
    let e = error_of(&text, &[]);
    assert!(
        e.contains("bad.yaml:5") && e.contains("cannot read") && e.contains("recipe.yaml"),
        "{e}"
    );
}

#[test]
fn a_declared_file_parameter_reruns_its_stage_when_the_file_changes() {
    let t = tempfile::tempdir().unwrap();
    let mut registry = registry();
    registry.add(common::CountLines);
    write(t.path(), "a.txt", "1\n2\n");
    write(t.path(), "b.txt", "1\n");
    let lookup = write(t.path(), "lookup.txt", "x\n");
    let path = write(
        t.path(),
        "p.yaml",
        "name: files\nstages:\n  count:\n    uses: count-lines\n    with:\n      extra: [a.txt, b.txt]\n      lookup: { table: lookup.txt }\n",
    );
    let o = options(t.path());
    let plan_of = || {
        let p = Pipeline::load(&path, &registry).unwrap();
        dry_plan(&p, &o)
    };
    let first = run(&Pipeline::load(&path, &registry).unwrap(), &o).unwrap();
    assert_eq!(first.computed(), 1);
    assert_eq!(plan_of().stages[0].reason, Reason::Cached);

    // The nested file, then an element of the list: each edit reruns it.
    std::fs::write(&lookup, "x\ny\n").unwrap();
    assert!(
        matches!(&plan_of().stages[0].reason, Reason::FilesChanged(f) if f[0].ends_with("lookup.txt")),
        "{:?}",
        plan_of().stages[0].reason
    );
    run(&Pipeline::load(&path, &registry).unwrap(), &o).unwrap();
    write(t.path(), "b.txt", "1\n2\n3\n");
    assert!(
        matches!(&plan_of().stages[0].reason, Reason::FilesChanged(f) if f[0].ends_with("b.txt"))
    );
    let again = run(&Pipeline::load(&path, &registry).unwrap(), &o).unwrap();
    assert_eq!(again.computed(), 1);
    assert_eq!(plan_of().stages[0].reason, Reason::Cached);

    // A missing file is named with its parameter path and line.
    std::fs::remove_file(t.path().join("b.txt")).unwrap();
    let p = Pipeline::load(&path, &registry).unwrap();
    let cache = Cache::open(&t.path().join("cache")).unwrap();
    let e = Plan::build(&p, &cache, &PlanOptions::default(), None)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("p.yaml:6:") && e.contains("parameter `extra.1`") && e.contains("b.txt"),
        "{e}"
    );
}

#[test]
fn a_changed_value_with_multi_byte_characters_is_shown_without_panicking() {
    let t = tempfile::tempdir().unwrap();
    // In the plan's JSON text, `µ` (two bytes) straddles byte 40.
    let title = format!("{}µµµµ", "a".repeat(38));
    let text = BASIC.replace("n: 5 }", &format!("n: 5, label: \"{title}\" }}"));
    let p = load(t.path(), "p.yaml", &text);
    let o = options(t.path());
    run(&p, &o).unwrap();
    let mut q = p.clone();
    q.set(&format!("src.label=\"{title}µ\"")).unwrap();
    let plan = dry_plan(&q, &o);
    let Reason::ParamsChanged(changes) = &plan.stages[0].reason else {
        panic!("{:?}", plan.stages[0].reason)
    };
    assert!(
        changes[0].starts_with("label: ") && changes[0].contains('…'),
        "{changes:?}"
    );
    assert!(plan.describe().contains("params changed: label"));
}

/// `src` temporary, read by `double` and by `triple` (two consumers).
const TEMP: &str = "\
name: temp
stages:
  src:
    uses: source
    temp: true
    with: { value: 2.0e-5, n: 5 }
  double:
    uses: scale
    inputs: { t: src }
    with: { factor: 2 }
  triple:
    uses: scale
    inputs: { t: src }
    with: { factor: 3 }
";

fn entry_exists(dir: &Path, key: &str) -> bool {
    Cache::open(&dir.join("cache"))
        .unwrap()
        .entry_dir(key)
        .exists()
}

#[test]
fn a_temporary_entry_is_dropped_once_its_readers_have_theirs_and_regenerated_when_needed() {
    let t = tempfile::tempdir().unwrap();
    let p = load(t.path(), "p.yaml", TEMP);
    let o = options(t.path());
    let first = run(&p, &o).unwrap();
    assert_eq!(first.computed(), 3);
    let src_key = first.plan.stage("src").unwrap().key.clone();
    assert!(
        !entry_exists(t.path(), &src_key),
        "dropped after both readers"
    );
    assert!(entry_exists(
        t.path(),
        &first.plan.stage("double").unwrap().key
    ));
    assert!(
        !o.out_dir.join("src").exists(),
        "a temporary stage is not exported"
    );
    assert!(first.provenance.stages["src"].temp);
    let double = std::fs::read(o.out_dir.join("double/t.parquet")).unwrap();

    // Warm: the readers are cached, so the temporary stage is not rerun.
    let warm = run(&p, &o).unwrap();
    assert_eq!(warm.computed(), 0);
    assert_eq!(
        warm.plan.stage("src").unwrap().reason,
        Reason::TempNotNeeded
    );
    assert!(warm.plan.describe().contains("temporary, not needed"));
    assert!(!entry_exists(t.path(), &src_key));

    // A reader's parameter changes: the temporary entry comes back from its
    // key (same bytes for `double`), then goes again.
    let changed = load(t.path(), "q.yaml", &TEMP.replace("factor: 3", "factor: 4"));
    let again = run(&changed, &o).unwrap();
    assert_eq!(again.computed(), 2, "src and triple");
    assert_eq!(again.plan.stage("src").unwrap().key, src_key);
    assert!(!entry_exists(t.path(), &src_key));
    assert_eq!(
        std::fs::read(o.out_dir.join("double/t.parquet")).unwrap(),
        double
    );
}

#[test]
fn a_temporary_entry_whose_readers_all_run_now_is_never_written() {
    let t = tempfile::tempdir().unwrap();
    let p = load(t.path(), "p.yaml", TEMP);
    let o = options(t.path());
    let src_key = dry_plan(&p, &o).stage("src").unwrap().key.clone();
    let mut written = Vec::new();
    let report = hypercontact_runner::exec::run_with_hook(&p, &o, &mut |path| {
        written.push(path.to_path_buf())
    })
    .unwrap();
    assert_eq!(report.computed(), 3);
    assert!(
        !written.is_empty(),
        "the readers' files are written and seen by the hook"
    );
    let src_files: Vec<_> = written
        .iter()
        .filter(|f| f.to_string_lossy().contains(src_key.as_str()))
        .collect();
    assert!(src_files.is_empty(), "{src_files:?}");
    // No stamp, lock or staging folder of it is left either.
    let cache = t.path().join("cache");
    let left: Vec<_> = walk(&cache)
        .into_iter()
        .filter(|f| f.to_string_lossy().contains(src_key.as_str()))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

#[test]
fn a_run_stopped_by_an_error_writes_the_temporary_entries_its_readers_still_need() {
    // `bad` fails at run time (its CSV has no column x) after `double` has
    // read `src` and before `triple` has: the stages run in file order.
    let failing = TEMP.replace(
        "  triple:\n",
        "  bad:\n    uses: source\n    with: { n: 1, path: y.csv }\n  triple:\n",
    );
    let t = tempfile::tempdir().unwrap();
    write(t.path(), "y.csv", "y\n1\n");
    let o = options(t.path());
    let p = load(t.path(), "p.yaml", &failing);
    let plan = dry_plan(&p, &o);
    let order: Vec<&str> = plan.stages.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(order, ["src", "double", "bad", "triple"]);
    let src_key = plan.stage("src").unwrap().key.clone();
    let o = RunOptions {
        keep_going: false,
        ..o
    };
    let err = run(&p, &o).unwrap_err().to_string();
    assert!(err.contains("bad"), "{err}");
    assert!(entry_exists(t.path(), &src_key), "written for `triple`");
    // Fixed: `src` is a cache hit, `triple` reads it, and then it goes.
    let fixed = load(
        t.path(),
        "q.yaml",
        &failing.replace("path: y.csv", "value: 1.0"),
    );
    let report = run(&fixed, &o).unwrap();
    assert_eq!(report.provenance.stages["src"].cache, CacheUse::Hit);
    assert_eq!(report.computed(), 2, "bad and triple");
    assert!(!entry_exists(t.path(), &src_key));
}

/// Every file under `dir`, recursively.
fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let path = entry.path();
        out.push(path.clone());
        if path.is_dir() {
            out.extend(walk(&path));
        }
    }
    out
}

#[test]
fn a_temporary_entry_stays_while_a_reader_is_not_part_of_the_run() {
    let t = tempfile::tempdir().unwrap();
    let p = load(t.path(), "p.yaml", TEMP);
    let o = RunOptions {
        plan: PlanOptions {
            only: Some("double".into()),
            ..PlanOptions::default()
        },
        ..options(t.path())
    };
    let report = run(&p, &o).unwrap();
    let src_key = report.plan.stage("src").unwrap().key.clone();
    assert!(entry_exists(t.path(), &src_key), "`triple` will read it");
    let all = run(&p, &options(t.path())).unwrap();
    assert_eq!(all.computed(), 1, "only `triple`");
    assert!(!entry_exists(t.path(), &src_key));
}

#[test]
fn a_study_keeps_temporary_entries_until_its_last_variant_and_refuses_to_collect_them() {
    let t = tempfile::tempdir().unwrap();
    let text =
        format!("{TEMP}study:\n  grid:\n    double.factor: [1, 2, 5]\n  collect: [double.t]\n");
    let p = load(t.path(), "p.yaml", &text);
    let report = hypercontact_runner::study::run_study(&p, &options(t.path())).unwrap();
    let computed: usize = report.runs.iter().map(|(_, r)| r.computed()).sum();
    assert_eq!(computed, 3 + 2, "src once, triple once, three doubles");
    let src_key = &report.runs[0].1.plan.stage("src").unwrap().key;
    assert!(!entry_exists(t.path(), src_key));

    let bad = load(
        t.path(),
        "bad.yaml",
        &text.replace("collect: [double.t]", "collect: [src.t]"),
    );
    let err = hypercontact_runner::study::run_study(&bad, &options(t.path()))
        .unwrap_err()
        .to_string();
    assert!(err.contains("`src` is temporary"), "{err}");
}

#[test]
fn a_temporary_entry_dropped_by_a_concurrent_run_is_regenerated() {
    let t = tempfile::tempdir().unwrap();
    let text = "\
name: race
stages:
  a:
    uses: source
    with: { value: 1.0, n: 3 }
  b:
    uses: scale
    inputs: { t: a }
    with: { factor: 2 }
  src:
    uses: source
    temp: true
    with: { value: 2.0, n: 4 }
  triple:
    uses: scale
    inputs: { t: src }
    with: { factor: 3 }
";
    let p = load(t.path(), "p.yaml", text);
    let keep = RunOptions {
        keep_temps: true,
        remote: Default::default(),
        ..options(t.path())
    };
    run(&p, &keep).unwrap();
    let changed = load(
        t.path(),
        "q.yaml",
        &text
            .replace("factor: 2", "factor: 5")
            .replace("factor: 3", "factor: 6"),
    );
    let src_key = run(
        &changed,
        &RunOptions {
            dry_run: true,
            ..options(t.path())
        },
    )
    .unwrap()
    .plan
    .stage("src")
    .unwrap()
    .key
    .clone();
    assert!(entry_exists(t.path(), &src_key));
    // While `b` writes (after the plan found `src` cached), another run
    // drops `src`: `triple` cannot read it, and the run plans again.
    let cache = Cache::open(&t.path().join("cache")).unwrap();
    let mut fired = false;
    let report =
        hypercontact_runner::exec::run_with_hook(&changed, &options(t.path()), &mut |_| {
            if !fired {
                fired = true;
                cache.remove(&src_key).unwrap();
            }
        })
        .unwrap();
    assert!(fired);
    assert_eq!(
        report.provenance.stages["b"].cache,
        CacheUse::Hit,
        "kept from the first try"
    );
    assert_eq!(report.provenance.stages["src"].cache, CacheUse::Miss);
    assert_eq!(report.provenance.stages["triple"].cache, CacheUse::Miss);
    assert!(!entry_exists(t.path(), &src_key));
}

#[test]
fn removing_an_entry_removes_its_lock_and_stamps_and_gc_removes_debris() {
    let t = tempfile::tempdir().unwrap();
    let p = load(t.path(), "p.yaml", BASIC);
    let report = run(&p, &options(t.path())).unwrap();
    // A second run checks the entries and stamps them.
    run(&p, &options(t.path())).unwrap();
    let root = t.path().join("cache");
    let cache = Cache::open(&root).unwrap();
    let key = report.plan.stage("src").unwrap().key.clone();
    assert!(root.join("locks").join(format!("{key}.lock")).exists());
    assert!(root.join("stamps").join(format!("{key}.json")).exists());
    cache.remove(&key).unwrap();
    // Issue 12: 28 lock files remained after `gc` removed 28 entries.
    assert!(!root.join("locks").join(format!("{key}.lock")).exists());
    assert!(!root.join("stamps").join(format!("{key}.json")).exists());
    assert!(!cache.entry_dir(&key).exists());

    // Debris of killed runs: a staging folder, a half-written stamp, an
    // orphan lock; and a staging folder whose writer still holds the lock.
    let dead = "0123456789abcdef0123456789abcdef";
    let live = report.plan.stage("double").unwrap().key.clone();
    std::fs::create_dir_all(root.join("tmp").join(format!("{dead}.77.1"))).unwrap();
    std::fs::create_dir_all(root.join("tmp").join(format!("{live}.78.1"))).unwrap();
    let half = root.join("stamps").join(format!("{dead}.json.5.tmp"));
    std::fs::write(&half, "{").unwrap();
    let old = std::time::SystemTime::now() - std::time::Duration::from_secs(120);
    std::fs::File::options()
        .write(true)
        .open(&half)
        .unwrap()
        .set_modified(old)
        .unwrap();
    std::fs::write(root.join("locks").join(format!("{dead}.lock")), "").unwrap();
    let held = cache.lock(&live).unwrap();
    let n = cache.clean_debris().unwrap();
    assert_eq!(n, 3, "staging, stamp and orphan lock of the dead writer");
    assert!(
        root.join("tmp").join(format!("{live}.78.1")).exists(),
        "its writer holds the lock"
    );
    assert!(!half.exists());
    drop(held);
    assert_eq!(cache.clean_debris().unwrap(), 1);
    assert_eq!(std::fs::read_dir(root.join("tmp")).unwrap().count(), 0);
    assert!(
        root.join("locks").join(format!("{live}.lock")).exists(),
        "its entry exists"
    );
}

#[test]
fn opening_a_missing_cache_to_look_creates_nothing() {
    let t = tempfile::tempdir().unwrap();
    let missing = t.path().join("nowhere/cache");
    assert!(Cache::open_existing(&missing).unwrap().is_none());
    assert!(!t.path().join("nowhere").exists());
}

#[test]
fn the_dry_run_aligns_multi_byte_names() {
    let t = tempfile::tempdir().unwrap();
    let text = BASIC
        .replace("  src:", "  µ-src:")
        .replace("{ t: src }", "{ t: µ-src }");
    let p = load(t.path(), "p.yaml", &text);
    let cache = Cache::open(&t.path().join("cache")).unwrap();
    let plan = Plan::build(&p, &cache, &PlanOptions::default(), None).unwrap();
    let describe = plan.describe();
    // The kind starts in the same column (in characters) on every line.
    let columns: Vec<usize> = describe
        .lines()
        .map(|l| {
            let kind = if l.contains("source") {
                "source"
            } else {
                "scale"
            };
            l[..l.find(kind).unwrap()].chars().count()
        })
        .collect();
    assert!(columns.windows(2).all(|w| w[0] == w[1]), "{describe}");
}

/// `exec-stage`, what each Slurm job runs: one entry from its inputs'
/// entries, refused when an input's entry is missing or the plan's key is
/// not the submitted one; the entries it leaves are what a local run makes.
#[test]
fn a_cluster_job_computes_one_entry_from_cached_inputs() {
    use hypercontact_runner::exec::{JobOutcome, StageJob, exec_stage};
    let t = tempfile::tempdir().unwrap();
    // Beside BASIC, a stage reading a file that goes away: a job plans only
    // its stage and what it reads, so no job hashes (or needs) that file.
    let mut registry = registry();
    registry.add(common::CountLines);
    let lines = write(t.path(), "lines.txt", "1\n2\n");
    let text = format!(
        "{BASIC}  count:\n    uses: count-lines\n    with: {{ lookup: {{ table: lines.txt }} }}\n"
    );
    let p = Pipeline::load(&write(t.path(), "p.yaml", &text), &registry).unwrap();
    let cache_dir = t.path().join("cache");
    let cache = Cache::open(&cache_dir).unwrap();
    let plan = Plan::build(&p, &cache, &PlanOptions::default(), None).unwrap();
    std::fs::remove_file(&lines).unwrap();
    let job = |stage: &str, force: bool| StageJob {
        stage: stage.to_owned(),
        key: plan.stage(stage).unwrap().key.clone(),
        force,
    };

    let e = exec_stage(&p, &cache_dir, &job("double", false)).unwrap_err();
    assert!(
        e.to_string()
            .contains("stage `double` reads `src`, whose entry"),
        "{e}"
    );
    let stale = StageJob {
        key: "0".repeat(32),
        ..job("src", false)
    };
    let e = exec_stage(&p, &cache_dir, &stale).unwrap_err();
    assert!(e.to_string().contains("changed since submission"), "{e}");
    assert!(!cache.entry_dir(&job("src", false).key).exists());

    assert!(matches!(
        exec_stage(&p, &cache_dir, &job("src", false)).unwrap(),
        JobOutcome::Computed { .. }
    ));
    assert!(matches!(
        exec_stage(&p, &cache_dir, &job("double", false)).unwrap(),
        JobOutcome::Computed { .. }
    ));
    assert_eq!(
        exec_stage(&p, &cache_dir, &job("double", false)).unwrap(),
        JobOutcome::AlreadyCached
    );
    assert!(matches!(
        exec_stage(&p, &cache_dir, &job("double", true)).unwrap(),
        JobOutcome::Computed { .. }
    ));

    // A local run then finds every entry, and exports what a run on a
    // fresh cache computes; provenance names the jobs it is told of.
    let p = load(t.path(), "basic.yaml", BASIC);
    let mut o = options(t.path());
    o.remote = [(job("double", false).key, "slurm 7".to_owned())].into();
    let report = run(&p, &o).unwrap();
    assert_eq!(report.hits() + report.computed(), 2);
    let double = &report.provenance.stages["double"];
    assert_eq!(double.cache, CacheUse::Miss);
    assert_eq!(double.job.as_deref(), Some("slurm 7"));
    assert_eq!(report.provenance.stages["src"].cache, CacheUse::Hit);
    let fresh = tempfile::tempdir().unwrap();
    let local = run(&p, &options(fresh.path())).unwrap();
    assert_eq!(local.computed(), 2);
    for stage in ["src", "double"] {
        assert_eq!(
            report.provenance.stages[stage].outputs,
            local.provenance.stages[stage].outputs
        );
    }
}

#[test]
fn writing_to_an_exported_output_reaches_neither_the_cache_nor_another_run() {
    // #31, 3: exports were hard links, so appending to one run's output (as
    // root, past the read-only mode) changed the cache entry and every
    // other run's copy. Failed before with the entry reported corrupt.
    let t = tempfile::tempdir().unwrap();
    let p = load(t.path(), "p.yaml", BASIC);
    let first = options(t.path());
    let second = RunOptions {
        out_dir: t.path().join("out2"),
        ..first.clone()
    };
    run(&p, &first).unwrap();
    assert_eq!(run(&p, &second).unwrap().hits(), 2, "the second run reuses");
    let file = "double/note.txt";
    let untouched = std::fs::read(second.out_dir.join(file)).unwrap();
    use std::io::Write;
    std::fs::File::options()
        .append(true)
        .open(first.out_dir.join(file))
        .expect("an exported output is its run's own file, writable")
        .write_all(b"an edit")
        .unwrap();
    assert_eq!(
        std::fs::read(second.out_dir.join(file)).unwrap(),
        untouched,
        "the other run's output is unchanged"
    );
    let cache = Cache::open(&first.cache_dir).unwrap();
    for key in keys(&p, t.path()) {
        let state = cache.verify(&key);
        assert!(
            matches!(state, EntryState::Valid(_)),
            "entry {key}: {state:?}"
        );
    }
}

#[test]
fn an_entry_names_the_build_that_made_it_and_an_old_manifest_still_reads() {
    // #31, 4: failed before for want of the field.
    let t = tempfile::tempdir().unwrap();
    let p = load(t.path(), "p.yaml", BASIC);
    let o = options(t.path());
    run(&p, &o).unwrap();
    let cache = Cache::open(&o.cache_dir).unwrap();
    let key = &keys(&p, t.path())[0];
    let EntryState::Valid(m) = cache.check(key) else {
        panic!("entry {key} not valid");
    };
    let running = hypercontact_runner::producer::running();
    assert_eq!(m.producer.as_deref(), Some(running));
    let prov: serde_json::Value =
        serde_json::from_slice(&std::fs::read(o.out_dir.join("provenance.json")).unwrap()).unwrap();
    assert_eq!(prov["producer"], running);
    assert_eq!(prov["stages"]["src"]["producer"], running);
    // A manifest written before the field: still a valid entry, listed
    // as made by an unknown build, and reused.
    let path = o.cache_dir.join("entries").join(key).join("manifest.json");
    let mut json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    json.as_object_mut().unwrap().remove("producer");
    let mut perms = std::fs::metadata(&path).unwrap().permissions();
    #[allow(clippy::permissions_set_readonly_false)]
    perms.set_readonly(false);
    std::fs::set_permissions(&path, perms).unwrap();
    std::fs::write(&path, serde_json::to_vec(&json).unwrap()).unwrap();
    let EntryState::Valid(old) = cache.verify(key) else {
        panic!("an old manifest is still valid");
    };
    assert_eq!(
        hypercontact_runner::producer::shown(old.producer.as_deref()),
        "unknown build"
    );
    let listed = cache.list().unwrap();
    assert!(
        listed
            .iter()
            .any(|e| &e.key == key && e.manifest.as_ref().is_some_and(|m| m.producer.is_none()))
    );
    let again = run(&p, &o).unwrap();
    assert_eq!(again.hits(), 2, "the producer is not part of the key");
    let prov: serde_json::Value =
        serde_json::from_slice(&std::fs::read(o.out_dir.join("provenance.json")).unwrap()).unwrap();
    assert_eq!(prov["stages"]["src"]["producer"], "unknown build");
}

/// Python's Ctrl-C sets `cancel` (#50, item 6): no stage starts after it,
/// the run says which stage it stopped before, every entry written is
/// sound, and the next run computes only what was not done.
#[test]
fn a_cancelled_run_starts_no_further_stage_and_leaves_a_sound_cache() {
    use hypercontact_runner::RunError;
    use std::sync::Arc;
    use std::sync::atomic::AtomicBool;

    let t = tempfile::tempdir().unwrap();
    let p = load(t.path(), "p.yaml", BASIC);
    let cancel = Arc::new(AtomicBool::new(false));
    let o = RunOptions {
        cancel: Some(cancel.clone()),
        ..options(t.path())
    };
    // Set while the first stage's entry is written, as a signal arrives
    // while a stage runs.
    let mut set_during_src = |_: &Path| cancel.store(true, Ordering::SeqCst);
    let stopped = hypercontact_runner::exec::run_with_hook(&p, &o, &mut set_during_src);
    match stopped {
        Err(e @ RunError::Interrupted { .. }) => assert_eq!(
            e.to_string(),
            "interrupted before stage `double`: the stages finished before it are in the cache"
        ),
        other => panic!("expected an interruption, got {other:?}"),
    }
    let cache = Cache::open(&t.path().join("cache")).unwrap();
    let entries = cache.list().unwrap();
    assert_eq!(entries.len(), 1, "only `src` ran");
    for entry in &entries {
        assert!(matches!(cache.verify(&entry.key), EntryState::Valid(_)));
    }
    cancel.store(false, Ordering::SeqCst);
    let again = run(&p, &o).unwrap();
    assert_eq!((again.hits(), again.computed()), (1, 1));
}
