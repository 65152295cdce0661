//! The `hypercontact` binary end to end on the shipped sample map.

use std::path::{Path, PathBuf};
use std::process::Output;

use hypercontact_core::Schema;

use crate::common;
use common::{bin, repo, text};

/// The demo pipeline, pointed at the repository's sample from a temp folder.
fn demo_in(dir: &Path) -> PathBuf {
    let sample = repo().join("data/samples/self-affine-256.npy");
    let yaml = std::fs::read_to_string(repo().join("pipelines/demo.yaml"))
        .unwrap()
        .replace(
            "../data/samples/self-affine-256.npy",
            &sample.display().to_string(),
        );
    let path = dir.join("demo.yaml");
    std::fs::write(&path, yaml).unwrap();
    path
}

fn run(dir: &Path, args: &[&str]) -> Output {
    let pipeline = demo_in(dir);
    bin()
        .arg("run")
        .arg(&pipeline)
        .arg("--out")
        .arg(dir.join("out"))
        .args(args)
        .output()
        .unwrap()
}

/// The declared columns of `kind`'s output `output`, as `hypercontact
/// stages KIND --json` prints them.
fn declared_columns(kind: &str, output: &str) -> Vec<hypercontact_io::ColumnMeta> {
    let out = bin().args(["stages", kind, "--json"]).output().unwrap();
    assert!(out.status.success(), "{}", text(&out));
    let stages: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let spec = stages[0]["outputs"]
        .as_array()
        .unwrap()
        .iter()
        .find(|o| o["name"] == output)
        .unwrap_or_else(|| panic!("{kind} declares no output `{output}`"));
    serde_json::from_value(spec["columns"].clone()).unwrap()
}

fn columns_meta(path: &Path) -> Vec<hypercontact_io::ColumnMeta> {
    hypercontact_io::parquet_columns_meta(std::fs::File::open(path).unwrap()).unwrap()
}

/// Issue #34, units travel with the data: every table a run exports (and
/// the cache serves again) carries its stage's declared units and docs.
/// Checked once by hand with pyarrow 26.0.1 on every table of
/// tests/guard/pipeline.yaml's run: `json.loads(pq.read_metadata(p)
/// .metadata[b"hypercontact:columns"])` parsed, bem's `load_n` in "N",
/// and `pq.read_table` gave the values of the build before, NaN for NaN.
/// (`pq.read_schema(p).metadata` is None: pyarrow takes it from the
/// `ARROW:schema` polars stores, which holds no metadata.)
fn assert_exported_tables_carry_their_units(out: &Path) {
    for (stage, kind, output) in [
        ("trunc", "truncation", "profile"),
        ("trunc", "truncation", "patch_sizes"),
        ("epdm", "material-preset", "material"),
        ("contact", "icm", "response"),
        ("contact-linear", "icm", "response"),
    ] {
        let path = out.join(format!("{stage}/{output}.parquet"));
        let table = hypercontact_io::read_parquet_file(&path).unwrap();
        let meta = columns_meta(&path);
        let names: Vec<&str> = meta.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, table.column_names(), "{}", path.display());
        assert_eq!(meta, declared_columns(kind, output), "{}", path.display());
    }
    let response = columns_meta(&out.join("contact/response.parquet"));
    let load = response.iter().find(|m| m.name == "load_n").unwrap();
    assert_eq!(load.unit, "N");
}

#[test]
fn run_twice_then_everything_is_cached_and_identical() {
    let t = tempfile::tempdir().unwrap();
    let first = run(t.path(), &[]);
    assert!(first.status.success(), "{}", text(&first));
    assert!(text(&first).contains("5 ran, 0 cached"), "{}", text(&first));
    assert_exported_tables_carry_their_units(&t.path().join("out"));
    let response = t.path().join("out/contact/response.parquet");
    let bytes = std::fs::read(&response).unwrap();
    let second = run(t.path(), &[]);
    assert!(
        text(&second).contains("0 ran, 5 cached"),
        "{}",
        text(&second)
    );
    assert_eq!(bytes, std::fs::read(&response).unwrap());
    let prov: serde_json::Value =
        serde_json::from_slice(&std::fs::read(t.path().join("out/provenance.json")).unwrap())
            .unwrap();
    assert_eq!(prov["stages"]["trunc"]["cache"], "hit");
    assert_eq!(prov["stages"]["trunc"]["params"]["levels"], 1000);
    // The cache sits next to the pipeline file by default.
    assert!(t.path().join(".hypercontact/cache/entries").is_dir());
}

/// Where a run's time went: `run --timings` and `timings RUN_DIR` print the
/// same table, every stage of the record once, totals per kind, the run.
#[test]
fn timings_list_every_stage_with_kind_totals_and_peak_memory() {
    let t = tempfile::tempdir().unwrap();
    let out = run(t.path(), &["--timings"]);
    assert!(out.status.success(), "{}", text(&out));
    let printed = String::from_utf8(out.stdout.clone()).unwrap();
    let table = &printed[printed.find("stage ").expect("the table's header")..];
    let prov: serde_json::Value =
        serde_json::from_slice(&std::fs::read(t.path().join("out/provenance.json")).unwrap())
            .unwrap();
    let stages = prov["stages"].as_object().unwrap();
    for (name, record) in stages {
        let line = table
            .lines()
            .find(|l| l.split_whitespace().next() == Some(name.as_str()))
            .unwrap_or_else(|| panic!("{name} missing from {table}"));
        let seconds: f64 = line.split_whitespace().nth(3).unwrap().parse().unwrap();
        let recorded = record["wall_s"].as_f64().unwrap();
        assert!(
            (seconds - recorded).abs() <= 0.005,
            "{line} against {recorded}"
        );
    }
    assert!(table.contains("\nby kind:\n  "), "{table}");
    assert!(table.contains("  icm "), "{table}");
    let peak_mb = prov["peak_rss_mb"].as_f64().expect("peak memory recorded");
    assert!(peak_mb > 1.0 && peak_mb < 4096.0, "{peak_mb}");
    assert!(
        table.contains(&format!(
            "{} stages: {} computed, 0 cached",
            stages.len(),
            stages.len()
        )),
        "{table}"
    );
    // The same table from the record alone.
    let again = bin()
        .arg("timings")
        .arg(t.path().join("out"))
        .output()
        .unwrap();
    assert!(again.status.success(), "{}", text(&again));
    assert_eq!(
        String::from_utf8(again.stdout).unwrap().trim_end(),
        table.trim_end()
    );
    let missing = bin().arg("timings").arg(t.path()).output().unwrap();
    assert!(!missing.status.success());
    assert!(
        text(&missing).contains("no provenance.json"),
        "{}",
        text(&missing)
    );
}

#[test]
fn dry_run_set_force_and_only() {
    let t = tempfile::tempdir().unwrap();
    assert!(run(t.path(), &["-q"]).status.success());
    let plan = text(&run(t.path(), &["--dry-run", "--set", "trunc.levels=500"]));
    assert!(
        plan.contains("params changed: levels: 1000 → 500"),
        "{plan}"
    );
    assert!(
        plan.contains("input changed: profile (trunc reruns)"),
        "{plan}"
    );
    assert!(
        plan.lines()
            .any(|l| l.contains("cached") && l.contains("surf")),
        "{plan}"
    );

    let forced = text(&run(t.path(), &["--force", "epdm"]));
    assert!(
        forced.contains("forced") && forced.contains("1 ran, 4 cached"),
        "{forced}"
    );

    let only = text(&run(t.path(), &["--dry-run", "--only", "trunc"]));
    assert!(
        only.lines()
            .any(|l| l.starts_with("  skip") && l.contains("contact-linear")),
        "{only}"
    );

    let bad = run(t.path(), &["--set", "trunc.levels=lots"]);
    assert!(!bad.status.success());
    assert!(
        text(&bad).contains("--set `trunc.levels=lots`"),
        "{}",
        text(&bad)
    );
}

#[test]
fn a_study_gathers_one_table() {
    let t = tempfile::tempdir().unwrap();
    let pipeline = demo_in(t.path());
    let out = bin()
        .arg("study")
        .arg(&pipeline)
        .arg("--out")
        .arg(t.path().join("study"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out));
    assert!(text(&out).contains("variant 3"), "{}", text(&out));
    let table =
        hypercontact_io::read_parquet_file(&t.path().join("study/contact.response.parquet"))
            .unwrap();
    assert_eq!(
        &table.column_names()[..3],
        ["variant", "contact.scheme", "trunc.levels"]
    );
    let levels = table.i64("trunc.levels").unwrap();
    assert!(levels.contains(&250) && levels.contains(&1000));
    // The varied parameters are not declared by icm, so only its columns
    // are described, in the table's order.
    let meta = columns_meta(&t.path().join("study/contact.response.parquet"));
    assert_eq!(meta, declared_columns("icm", "response"));
    assert_eq!(
        table.column_names()[3..],
        meta.iter().map(|m| m.name.as_str()).collect::<Vec<_>>()[..]
    );
    // Notes name their variant (stderr is no terminal: plain lines).
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("variant 1/4: trunc 251 planes"), "{err}");
    assert!(err.contains("variant 2/4: trunc 1001 planes"), "{err}");

    // Without --out, the study has its own folder beside the run's.
    let default = bin()
        .arg("study")
        .arg(&pipeline)
        .arg("-q")
        .current_dir(t.path())
        .output()
        .unwrap();
    assert!(default.status.success(), "{}", text(&default));
    let study = t.path().join("runs/demo/study");
    assert!(study.join("contact.response.parquet").is_file());
    assert!(study.join("study.json").is_file());
    assert!(
        study
            .join("variants/004/contact/response.parquet")
            .is_file()
    );
    assert!(!t.path().join("runs/demo/contact.response.parquet").exists());
}

/// Issue #37, item 1, through the binary: the demo with a second branch
/// whose height map is corrupt. By default the run keeps going: the
/// demo's products are written, the summary shows what ran, failed and was
/// not run, the error lists the failure with its cause, and the exit code
/// is 1. `--fail-fast` stops at the failure, before the demo's contact.
#[test]
fn a_failed_branch_leaves_the_others_to_run() {
    let with_bad_branch = |dir: &Path| {
        let pipeline = demo_in(dir);
        let yaml = std::fs::read_to_string(&pipeline).unwrap().replace(
            "  trunc:\n",
            "  bad:\n    uses: height-map\n    with: { path: corrupt.npy, pixel_m: 1.0e-6 }\n  \
             bad-trunc:\n    uses: truncation\n    inputs: { surface: bad }\n  trunc:\n",
        );
        std::fs::write(&pipeline, yaml).unwrap();
        std::fs::write(dir.join("corrupt.npy"), b"\x93NUMPY this is no array").unwrap();
        pipeline
    };
    let t = tempfile::tempdir().unwrap();
    let pipeline = with_bad_branch(t.path());
    let run_it = |args: &[&str]| {
        (bin()
            .arg("run")
            .arg(&pipeline)
            .arg("--out")
            .arg(t.path().join("out")))
        .args(args)
        .output()
        .unwrap()
    };
    let out = run_it(&[]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stdout.contains("  FAILED  bad "), "{stdout}");
    assert!(stdout.contains(" not run  bad-trunc "), "{stdout}");
    assert!(
        stdout.contains("5 ran, 0 cached, 1 failed, 1 not run in "),
        "{stdout}"
    );
    assert!(
        stderr.contains(
            "demo.yaml: 1 stage failed, 1 not run because it depends on a failed one; every other \
             stage ran and is cached\n  stage `bad` (height-map): "
        ),
        "{stderr}"
    );
    assert!(stderr.contains("corrupt.npy"), "{stderr}");
    assert!(
        stderr.contains("`bad-trunc` not run: it depends on `bad`"),
        "{stderr}"
    );
    assert!(t.path().join("out/contact/response.parquet").is_file());
    assert!(t.path().join("out/provenance.json").is_file());

    let t = tempfile::tempdir().unwrap();
    let pipeline = with_bad_branch(t.path());
    let out = bin()
        .arg("run")
        .arg(&pipeline)
        .arg("--fail-fast")
        .arg("--out")
        .arg(t.path().join("out"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
    assert!(
        text(&out).contains("stage `bad` (height-map) failed"),
        "{}",
        text(&out)
    );
    assert!(!t.path().join("out/contact").exists());
    let both = run_it(&["--keep-going", "--fail-fast"]);
    assert_eq!(both.status.code(), Some(2), "{}", text(&both));
}

#[test]
fn bad_pipelines_fail_with_file_and_line() {
    let t = tempfile::tempdir().unwrap();
    let good = std::fs::read_to_string(demo_in(t.path())).unwrap();
    let cases = [
        (
            "uses: icm",
            "uses: icn",
            "demo.yaml:16:",
            "unknown stage kind `icn`",
        ),
        (
            "levels: 1000 }",
            "levls: 1000 }",
            "demo.yaml:11:",
            "unknown field `levls`",
        ),
        (
            "model: linear",
            "model: 3",
            "demo.yaml:22:",
            "unknown variant",
        ),
        (
            "pixel_m: 20.0e-6",
            "pixel_m: -1",
            "demo.yaml:7",
            "parameter `pixel_m`",
        ),
        (
            "self-affine-256.npy",
            "nowhere.npy",
            "demo.yaml:7",
            "cannot read",
        ),
        (
            "profile: trunc, material: epdm",
            "profile: trunc",
            "stage `contact`",
            "missing input `material`",
        ),
    ];
    for (from, to, place, what) in cases {
        let path = t.path().join("demo.yaml");
        std::fs::write(&path, good.replacen(from, to, 1)).unwrap();
        let out = bin()
            .arg("run")
            .arg(&path)
            .arg("--dry-run")
            .output()
            .unwrap();
        let msg = text(&out);
        assert!(!out.status.success(), "{from} → {to} was accepted");
        assert!(
            msg.contains(place) && msg.contains(what),
            "{from} → {to}: {msg}"
        );
        assert!(!msg.contains("panicked"), "{msg}");
    }
}

#[test]
fn stages_lists_every_kind_with_defaults_and_schemas() {
    let out = bin().arg("stages").output().unwrap();
    let listing = text(&out);
    for kind in ["height-map", "truncation", "icm", "bem", "material-preset"] {
        assert!(listing.contains(&format!("{kind} (v")), "{kind} missing");
    }
    let json = bin()
        .args(["stages", "truncation", "--json"])
        .output()
        .unwrap();
    let v: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(v[0]["kind"], "truncation");
    assert_eq!(
        v[0]["params"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["name"] == "levels")
            .unwrap()["default"],
        1000
    );
    // What a Slurm job of the kind asks for: light, or parallel.
    assert_eq!(
        v[0]["resources"],
        serde_json::json!({ "cpus": 1, "mem_mb": 2048, "time_min": 30 })
    );
    let bem = bin().args(["stages", "bem", "--json"]).output().unwrap();
    let v: serde_json::Value = serde_json::from_slice(&bem.stdout).unwrap();
    assert_eq!(v[0]["resources"]["cpus"], 4);
    let bem = bin().args(["stages", "bem"]).output().unwrap();
    assert!(
        text(&bem).contains("slurm job (--executor slurm): cpus 4, mem 8192 MiB, time 120 min")
    );
    let unknown = bin().args(["stages", "nope"]).output().unwrap();
    assert!(!unknown.status.success() && text(&unknown).contains("unknown stage kind"));
}

#[test]
fn cache_ls_gc_and_clean() {
    let t = tempfile::tempdir().unwrap();
    assert!(run(t.path(), &["-q"]).status.success());
    assert!(
        run(t.path(), &["-q", "--set", "trunc.levels=100"])
            .status
            .success()
    );
    let cache = t.path().join(".hypercontact/cache");
    let ls = text(
        &bin()
            .args(["cache", "ls", "--cache"])
            .arg(&cache)
            .output()
            .unwrap(),
    );
    assert!(ls.contains("8 entries"), "{ls}");
    let gc = bin()
        .args(["cache", "gc", "--cache"])
        .arg(&cache)
        .arg("--keep")
        .arg(t.path().join("demo.yaml"))
        .output()
        .unwrap();
    assert!(text(&gc).contains("removed 3 entries"), "{}", text(&gc));
    let again = run(t.path(), &[]);
    assert!(text(&again).contains("0 ran, 5 cached"), "{}", text(&again));
    let clean = bin()
        .args(["cache", "clean", "--cache"])
        .arg(&cache)
        .output()
        .unwrap();
    assert!(clean.status.success() && !cache.exists());
}

#[test]
fn a_killed_run_leaves_a_usable_cache() {
    let t = tempfile::tempdir().unwrap();
    let pipeline = demo_in(t.path());
    // Kill the run at several moments; every later run must succeed and
    // agree with an uninterrupted one.
    for delay_ms in [20, 60, 120] {
        let mut child = bin()
            .arg("run")
            .arg(&pipeline)
            .args(["-q", "--set", &format!("trunc.levels={}", 2000 + delay_ms)])
            .arg("--out")
            .arg(t.path().join("killed"))
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(delay_ms));
        let _ = child.kill();
        let _ = child.wait();
    }
    let out = bin()
        .arg("run")
        .arg(&pipeline)
        .args(["--set", "trunc.levels=2120", "--out"])
        .arg(t.path().join("after"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out));
    let ls = text(
        &bin()
            .args(["cache", "ls", "--cache"])
            .arg(t.path().join(".hypercontact/cache"))
            .output()
            .unwrap(),
    );
    assert!(!ls.contains("(unreadable)"), "{ls}");
}

/// `hypercontact run PIPELINE` into a temp folder's out/ and cache/.
fn run_pipeline(dir: &Path, pipeline: &str, extra: &[&str]) -> Output {
    bin()
        .arg("run")
        .arg(repo().join(pipeline))
        .arg("--out")
        .arg(dir.join("out"))
        .arg("--cache")
        .arg(dir.join("cache"))
        .args(extra)
        .output()
        .unwrap()
}

fn parquet(dir: &Path, file: &str) -> hypercontact_core::Table {
    hypercontact_io::read_parquet_file(&dir.join("out").join(file)).unwrap()
}

/// The unconstrained fit's RMS relative error in `fit`'s comparison.
fn unconstrained_rms(dir: &Path, model: &str) -> f64 {
    let c = parquet(dir, "fit/comparison.parquet");
    let (models, constraints) = (c.str("model").unwrap(), c.str("constraint").unwrap());
    let row = (0..models.len())
        .find(|&i| models[i] == model && constraints[i] == "none")
        .unwrap();
    c.f64("rms_rel_err").unwrap()[row]
}

#[test]
fn the_tensile_csv_pipeline_fits_and_reports() {
    let t = tempfile::tempdir().unwrap();
    let out = run_pipeline(t.path(), "pipelines/tensile-csv.yaml", &[]);
    assert!(out.status.success(), "{}", text(&out));
    assert!(text(&out).contains("3 ran, 0 cached"), "{}", text(&out));
    // Issue 18: the stable fit has every μ_i ≥ 0; the sample is made
    // from the paper's Table 1 (cancelling μ_i), which only the
    // unconstrained fit follows to within its 0.5 % noise.
    let params = parquet(t.path(), "fit/params.parquet");
    let names = params.str("param").unwrap();
    let values = params.f64("value").unwrap();
    assert!(
        (0..names.len())
            .filter(|&i| names[i].starts_with("mu_"))
            .all(|i| values[i] >= 0.0)
    );
    assert!(unconstrained_rms(t.path(), "ogden-6") < 0.0055);
    let html = std::fs::read_to_string(t.path().join("out/report/index.html")).unwrap();
    assert!(html.contains("fig2.svg"));

    // Issue 17: notes reached nobody in a piped run. Without a terminal
    // they are plain stderr lines, and provenance.json keeps them, also
    // when the stage is a cache hit the next time.
    let stderr = String::from_utf8_lossy(&out.stderr);
    let said = stderr
        .lines()
        .find(|l| l.starts_with("fit ") && l.contains("RMS relative error"))
        .unwrap_or_else(|| panic!("the fit's note is not on stderr:\n{stderr}"));
    let notes_in = |dir: &Path| -> Vec<String> {
        let json = std::fs::read_to_string(dir.join("out/provenance.json")).unwrap();
        let v: serde_json::Value = serde_json::from_str(&json).unwrap();
        v["stages"]["fit"]["notes"]
            .as_array()
            .unwrap_or_else(|| panic!("no notes for `fit` in provenance.json:\n{json}"))
            .iter()
            .map(|n| n.as_str().unwrap().to_owned())
            .collect()
    };
    let notes = notes_in(t.path());
    assert!(said.ends_with(notes[0].as_str()), "{said} / {notes:?}");
    let again = run_pipeline(t.path(), "pipelines/tensile-csv.yaml", &[]);
    assert!(text(&again).contains("0 ran, 3 cached"), "{}", text(&again));
    assert_eq!(notes_in(t.path()), notes);
    assert!(!String::from_utf8_lossy(&again.stderr).contains("RMS relative error"));
}

/// The quick version of the paper pipeline, end to end: DIC → fit, T1–T4
/// scans → surface → truncation → ICM → report (issue 7's checks).
/// Issue 49: the page opens with "What this rerun finds", its sentences
/// linked to Figs. 7 and 10 and their tables, with the numbers that
/// summary.json holds under `findings`.
fn the_findings_open_the_page(page: &str, report: &std::path::Path) {
    let section = page
        .split_once("<section id=\"findings\">")
        .and_then(|(before, rest)| {
            assert!(
                !before.contains("<h2>"),
                "findings are not the first section"
            );
            rest.split_once("</section>")
        })
        .map(|(inside, _)| inside)
        .expect("no findings section");
    for part in [
        "The paper compares contact models (icm, bem, persson, gw)",
        "the finite-strain solution (fem) carries the small-strain load to within",
        "with the equibiaxial tangent the models (icm, bem, persson) carry",
        "with linear elasticity (icm-linear, bem-linear, persson-linear)",
        "<a href=\"#fig10\">Fig. 10</a>",
        "<a href=\"#fig10-table\">its table</a>",
        "<a href=\"#fig7\">Fig. 7</a>",
        "<a href=\"#agreement-table\">the agreement table</a>",
        "bem-linear shares it",
    ] {
        assert!(section.contains(part), "{part}\n{section}");
    }
    for anchor in [
        "id=\"fig7\"",
        "id=\"fig10\"",
        "id=\"fig10-table\"",
        "id=\"agreement-table\"",
    ] {
        assert!(page.contains(anchor), "no {anchor}");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(report.join("summary.json")).unwrap())
            .unwrap();
    let f = &summary["findings"];
    let equibiaxial = &f["finite_strain"]["equibiaxial_over_finite"];
    let (lo, hi) = (
        equibiaxial["min"].as_f64().unwrap(),
        equibiaxial["max"].as_f64().unwrap(),
    );
    assert!(0.0 < lo && lo <= hi, "{equibiaxial}");
    // The sentence prints the summary's numbers.
    let shown = format!("{}×", fmt2(lo, hi));
    assert!(section.contains(&shown), "{shown}\n{section}");
    assert!(
        f["finite_strain"]["finite_vs_small_percent"]["max"]
            .as_f64()
            .unwrap()
            >= 0.0
    );
    assert_eq!(f["experiment"]["by_construction"][0], "bem-linear");
    assert!(
        f["experiment"]["equibiaxial_over_experiment"]["min"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    assert!(f["claim"]["equibiaxial_models"].as_array().unwrap().len() >= 3);
    println!("findings section:\n{section}");
}

/// A range as the findings print it, two significant digits.
fn fmt2(lo: f64, hi: f64) -> String {
    let (lo, hi) = (
        hypercontact_report::html::fmt_sig(lo, 2),
        hypercontact_report::html::fmt_sig(hi, 2),
    );
    if lo == hi { lo } else { format!("{lo}–{hi}") }
}

#[test]
fn the_quick_paper_pipeline_writes_the_report() {
    let t = tempfile::tempdir().unwrap();
    let out = run_pipeline(t.path(), "pipelines/quick.yaml", &[]);
    assert!(out.status.success(), "{}", text(&out));
    assert!(text(&out).contains("70 ran, 0 cached"), "{}", text(&out));
    let report = t.path().join("out/report");
    // Issue 33: T1's patch through every model and fem, judged in Fig. 10.
    assert!(report.join("fig10.png").is_file());
    let page = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert!(
        page.contains("Load ratio F_model / F_fem"),
        "no finite-strain table"
    );
    the_findings_open_the_page(&page, &report);
    let fem = parquet(t.path(), "t1-fem/response.parquet");
    let fractions = fem.f64("area_fraction").unwrap();
    assert!(*fractions.last().unwrap() >= 0.3);
    assert!(t.path().join("out/t1-fem/mesh_a0.300.vtk").is_file());

    // Issue 6: the images → DIC → fit chain recovers the generating
    // material's curves within 1 % RMS relative error per mode.
    // Since issue 18 the pipeline's fit is the stable one (μ_i ≥ 0), which
    // cannot follow the paper's cancelling Table 1; the comparison's
    // unconstrained 6-term fit is the paper's, and the check of the chain.
    let rms = unconstrained_rms(t.path(), "ogden-6");
    assert!(
        rms < 0.01,
        "unconstrained ogden-6: RMS relative error {rms}"
    );
    // The bootstrap's bands reach the ICM, the summary and the figures.
    let bands = parquet(t.path(), "t1-icm/bands.parquet");
    let response = parquet(t.path(), "t1-icm/response.parquet");
    assert_eq!(bands.n_rows(), response.n_rows());
    let (lo, mid, hi) = (
        bands.f64("load_norm_p05").unwrap(),
        bands.f64("load_norm_p50").unwrap(),
        bands.f64("load_norm_p95").unwrap(),
    );
    let last = bands.n_rows() - 1;
    assert!(
        lo[last] < mid[last] && mid[last] < hi[last],
        "{} {} {}",
        lo[last],
        mid[last],
        hi[last]
    );
    assert!(bands.i64("replicates").unwrap()[last] >= 36);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(report.join("summary.json")).unwrap())
            .unwrap();
    let at_half = &summary["samples"][0]["load_norm"][1];
    let (p05, value, p95) = (
        at_half["load_norm_p05"]["icm"].as_f64().unwrap(),
        at_half["load_norm"]["icm"].as_f64().unwrap(),
        at_half["load_norm_p95"]["icm"].as_f64().unwrap(),
    );
    assert!(p05 < value && value < p95, "{p05} {value} {p95}");

    // Every figure as a real PNG and SVG, referenced by the page.
    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    for fig in ["fig2", "fig4", "fig7", "fig8", "fig9"] {
        let png = std::fs::read(report.join(format!("{fig}.png"))).unwrap();
        assert!(
            png.starts_with(b"\x89PNG\r\n\x1a\n") && png.len() > 20_000,
            "{fig}.png"
        );
        let decoded = image::load_from_memory(&png).unwrap();
        assert!(
            decoded.width() >= 800,
            "{fig}.png is {} px wide",
            decoded.width()
        );
        let svg = std::fs::read_to_string(report.join(format!("{fig}.svg"))).unwrap();
        assert!(svg.contains("<svg") && svg.trim_end().ends_with("</svg>") && svg.len() > 8_000);
        assert!(
            html.contains(&format!("href=\"{fig}.png\"")),
            "{fig} not linked"
        );
    }
    // The provenance of every upstream stage is on the page.
    for stage in ["ut-dic", "fit", "t4-scan", "t3-trunc", "t1-icm-linear"] {
        assert!(
            html.contains(&format!("<td>{stage}</td>")),
            "{stage} not in provenance"
        );
    }

    // summary.json repeats the upstream tables' numbers.
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(report.join("summary.json")).unwrap()).unwrap();
    let samples = summary["samples"].as_array().unwrap();
    assert_eq!(samples.len(), 4);
    let mut at_half = Vec::new();
    for (k, sample) in samples.iter().enumerate() {
        let label = format!("T{}", k + 1);
        assert_eq!(sample["label"], label.as_str());
        let stats = parquet(t.path(), &format!("t{}/stats.parquet", k + 1));
        for column in ["sigma_m", "rms_slope", "hurst_x", "hurst_y"] {
            assert_eq!(
                sample[column].as_f64().unwrap(),
                stats.f64(column).unwrap()[0],
                "{label} {column}"
            );
        }
        // F/(E0* A0) at A/A0 = 0.5, against the ICM table read directly.
        let response = parquet(t.path(), &format!("t{}-icm/response.parquet", k + 1));
        let (a, f) = (
            response.f64("area_fraction").unwrap(),
            response.f64("load_norm").unwrap(),
        );
        let i = a.iter().position(|&x| x >= 0.5).unwrap();
        let expected = f[i - 1] + (f[i] - f[i - 1]) * (0.5 - a[i - 1]) / (a[i] - a[i - 1]);
        let found = sample["load_norm"]
            .as_array()
            .unwrap()
            .iter()
            .find(|l| l["area_fraction"] == 0.5)
            .unwrap()["load_norm"]["icm"]
            .as_f64()
            .unwrap();
        assert!(
            (found / expected - 1.0).abs() < 1e-12,
            "{label}: {found} vs {expected}"
        );
        at_half.push(found);
        // Issue 13: the boundary-element curves reach A/A0 = 0.9, so the
        // ICM/BEM load ratio is read at every requested area; profile
        // theory needs less load than the coupled half-space (what it
        // leaves out stiffens the surface).
        // Each law against itself: the report's ratio to its reference
        // (bem), and the linear laws' loads divided here.
        for l in sample["load_norm"].as_array().unwrap() {
            let load = |m: &str| l["load_norm"][m].as_f64().unwrap_or(f64::NAN);
            let ratios = [
                (
                    "icm / bem",
                    l["over_reference"]["icm"].as_f64().unwrap_or(f64::NAN),
                ),
                (
                    "icm-linear / bem-linear",
                    load("icm-linear") / load("bem-linear"),
                ),
            ];
            for (key, ratio) in ratios {
                assert!(
                    ratio > 0.1 && ratio < 1.0,
                    "{label} {key} at {}: {ratio}",
                    l["area_fraction"]
                );
            }
        }
    }
    // The paper's ordering: F_T1 > F_T2 > F_T3 > F_T4 at equal area.
    assert!(
        at_half.windows(2).all(|w| w[0] > w[1]),
        "F/(E0* A0) at A/A0 = 0.5: {at_half:?}"
    );

    // Issue 16: the four models on every sample in one pipeline, Fig. 9
    // and its κ table. Persson (Yang & Persson, γ = 0.45) at vanishing load
    // has κ = √(8/π)/√γ on its own h'rms; on the map's h'rms every model's
    // κ at A/A0 = 0.02 is a number, and the linear ICM (no coupling) gives
    // the most area per load, as profile theory does.
    assert!(html.contains("Contact models compared") && html.contains("κ = (A/A0)"));
    for (k, sample) in samples.iter().enumerate() {
        let n = k + 1;
        let persson = parquet(t.path(), &format!("t{n}-persson/summary.parquet"));
        let expected = (8.0 / std::f64::consts::PI).sqrt() / 0.45f64.sqrt();
        let kappa = persson.f64("kappa_small_load").unwrap()[0];
        assert!((kappa / expected - 1.0).abs() < 1e-4, "T{n}: {kappa}");
        for stage in ["persson", "gw"] {
            let r = parquet(t.path(), &format!("t{n}-{stage}/response.parquet"));
            r.conform(hypercontact_core::contact::ResponseTable::COLUMNS)
                .unwrap();
        }
        let at_small = &sample["kappa"][0];
        assert_eq!(at_small["area_fraction"], 0.02);
        let get = |m: &str| at_small["models"][m].as_f64().unwrap_or(f64::NAN);
        for m in ["icm", "icm-linear", "bem", "bem-linear", "persson", "gw"] {
            assert!(get(m) > 0.1 && get(m) < 10.0, "T{n} {m}: {at_small}");
        }
        assert!(get("icm-linear") > get("bem-linear"), "T{n}: {at_small}");
    }

    // Issue 14: the contact experiment's tables for T1–T4, 16 frames each,
    // three before contact, then area and force growing towards A/A0 ≈ 0.9,
    // the clock offset (0.37 s in synth-contact) found from the camera's
    // trigger logged with the force.
    for n in 1..=4 {
        let contact = parquet(t.path(), &format!("t{n}-images/contact.parquet"));
        let area = contact.f64("area_fraction").unwrap();
        let force = contact.f64("force_n").unwrap();
        let time = contact.f64("time_s").unwrap();
        assert_eq!(area.len(), 16, "T{n}");
        assert_eq!(area[..3], [0.0; 3], "T{n}");
        assert!(
            area[3] > 0.0 && area[15] > 0.8 && area[15] < 0.95,
            "T{n}: {area:?}"
        );
        assert!(area[3..].windows(2).all(|w| w[1] > w[0]), "T{n}: {area:?}");
        assert!(
            force[15] > force[5] && force[5] > force[4],
            "T{n}: {force:?}"
        );
        let sync = parquet(t.path(), &format!("t{n}-images/sync.parquet"));
        let offset = sync.f64("clock_offset_s").unwrap()[0];
        assert_eq!(sync.str("source").unwrap()[0], "trigger");
        assert!((offset - 0.37).abs() < 0.01, "T{n}: {offset}");
        assert!(time[1] - time[0] > 0.05, "T{n}: {time:?}");
    }

    // Issue 15: the camera's view registered onto the stitched scan (the
    // lab turned it 2.5° and shifted it by (150, -100) µm against the true
    // surface; the stitched grid sits within about a scan pixel of the
    // truth's), the maps overlapped, and the lab's own physics (since #49
    // the linear BEM, `bem-linear`) marked by construction, not ranked.
    for n in 1..=4 {
        let transform = parquet(t.path(), &format!("t{n}-compare/transform.parquet"));
        assert_eq!(transform.str("against").unwrap()[0], "bem");
        let angle = transform.f64("angle_deg").unwrap()[0];
        let (x, y) = (
            transform.f64("shift_x_m").unwrap()[0],
            transform.f64("shift_y_m").unwrap()[0],
        );
        assert!((angle - 2.5).abs() < 0.2, "T{n}: {angle}°");
        assert!((x - 150e-6).hypot(y + 100e-6) < 25e-6, "T{n}: ({x}, {y})");
        let overlap = parquet(t.path(), &format!("t{n}-compare/overlap.parquet"));
        // Six mapped frames (map_fractions 0.05 … 0.9) × truncation and bem.
        assert_eq!(overlap.str("model").unwrap().len(), 12, "T{n}");
        // Where the lab's physics (bem) predicts contact, the camera mostly
        // sees it (precision 0.83-1 measured; a map placed at random would
        // score about the frame's A/A0). Dice also depends on how near the
        // bem map's A/A0 is to the frame's: T2 at 0.16 against 0.09, 0.37.
        let dice = overlap.f64("dice").unwrap();
        let precision = overlap.f64("precision").unwrap();
        let area = overlap.f64("area_fraction").unwrap();
        for (k, model) in overlap.str("model").unwrap().iter().enumerate() {
            assert!((0.0..=1.0).contains(&dice[k]), "T{n}: {}", dice[k]);
            if model == "bem" && area[k] >= 0.1 {
                assert!(
                    precision[k] > 0.75,
                    "T{n}: bem precision {} at {}",
                    precision[k],
                    area[k]
                );
            }
        }
        let agreement = parquet(t.path(), &format!("t{n}-compare/agreement.parquet"));
        let models = agreement.str("model").unwrap();
        let rank = agreement.i64("rank").unwrap();
        let at = |m: &str| models.iter().position(|x| x == m).unwrap();
        let rank_of = |m: &str| rank[at(m)];
        // Six models scored: the four of issue 15 and Persson and GW (#16).
        assert_eq!(models.len(), 6, "T{n}: {models:?}");
        // #49: the synthetic lab is the linear BEM with the true material
        // (quick.yaml: `model: linear`), named in the tables; `bem-linear`
        // shares its physics, so it is marked by construction and ranked 0,
        // the five others rank 1–5 among themselves. Measured on the quick
        // pipeline (2026-12-07): Persson or ICM first, linear ICM 4th or
        // 5th, the hyperelastic BEM 2nd or 3rd at 1.6–2.3 times the
        // measured load at A/A0 = 0.5 (the tangent modulus' factor).
        let physics = "bem, linear elastic, small-strain modulus, free boundary";
        assert!(
            agreement
                .str("experiment_physics")
                .unwrap()
                .iter()
                .all(|p| p == physics),
            "T{n}"
        );
        let marked = agreement.i64("by_construction").unwrap();
        for (k, model) in models.iter().enumerate() {
            assert_eq!(marked[k], i64::from(model == "bem-linear"), "T{n} {model}");
        }
        assert_eq!(rank_of("bem-linear"), 0, "T{n}: {rank:?}");
        let mut ranked: Vec<i64> = rank.iter().copied().filter(|&r| r > 0).collect();
        ranked.sort_unstable();
        assert_eq!(ranked, [1, 2, 3, 4, 5], "T{n}: {rank:?}");
        assert!(rank_of("icm-linear") >= 4, "T{n}: {models:?} {rank:?}");
        let ratios = parquet(t.path(), &format!("t{n}-compare/load_ratio.parquet"));
        let (ratio_model, ratio_at) = (
            ratios.str("model").unwrap(),
            ratios.f64("area_fraction").unwrap(),
        );
        let bem_at_half = (0..ratio_model.len())
            .find(|&i| ratio_model[i] == "bem" && ratio_at[i] == 0.5)
            .map(|i| ratios.f64("load_ratio").unwrap()[i])
            .unwrap();
        assert!(bem_at_half > 1.4, "T{n}: bem at 0.5 {bem_at_half}");
        assert!(agreement.i64("points").unwrap().iter().all(|p| *p >= 8));
        // The report's summary.json repeats them exactly.
        let json = &samples[n - 1]["agreement"];
        let rms = agreement.f64("rms_log_ratio").unwrap();
        for (k, model) in models.iter().enumerate() {
            assert_eq!(json[k]["model"], model.as_str(), "T{n}");
            assert_eq!(
                json[k]["rms_log_ratio"].as_f64().unwrap(),
                rms[k],
                "T{n} {model}"
            );
            assert_eq!(json[k]["rank"].as_i64().unwrap(), rank[k], "T{n} {model}");
            assert_eq!(json[k]["by_construction"], marked[k], "T{n} {model}");
        }
        assert_eq!(
            samples[n - 1]["transform"]["angle_deg"].as_f64().unwrap(),
            angle
        );
    }
    // Fig. 6 (T1: observed, predicted and overlay maps with a scale bar) and
    // the experiment's points in Fig. 7, with the agreement table under it.
    assert!(html.contains("<figure id=\"fig6\">"), "no Fig. 6");
    for name in [
        "observed_a0.500",
        "overlay_bem_a0.500",
        "predicted_truncation_a0.100",
    ] {
        let png = std::fs::read(report.join(format!("fig6_T1_{name}.png"))).unwrap();
        let image = image::load_from_memory(&png).unwrap();
        assert_eq!((image.width(), image.height()), (512, 512), "{name}");
    }
    assert!(html.contains("Agreement of the models with the contact experiment"));
    // #49: the report names the experiment's physics (under the table, in
    // the experiment's section and the captions of Figs. 7 and 9) and shows
    // bem-linear as "by construction" instead of a rank.
    let named = "The experiment of T1, T2, T3, T4: rendered by <i>bem, linear elastic, \
                 small-strain modulus, free boundary</i>; bem-linear shares it";
    assert_eq!(html.matches(named).count(), 4, "{html}");
    assert_eq!(
        html.matches("<td>by construction</td><td>bem-linear</td>")
            .count(),
        4
    );
    assert!(html.contains("Registration of the camera"));
    let fig7 = std::fs::read_to_string(report.join("fig7.svg")).unwrap();
    assert!(
        fig7.contains(">\nexperiment\n</text>"),
        "Fig. 7 has no experiment key"
    );
    assert!(
        fig7.matches("<circle").count() >= 4 * 12,
        "Fig. 7: too few measured points"
    );
    let otsu = parquet(t.path(), "t1-images-otsu/contact.parquet");
    assert_eq!(otsu.str("method").unwrap()[0], "otsu");

    // A second run is all cache; one sample's truncation changed reruns
    // exactly that sample's downstream stages and the report, and (since
    // #49 its comparison reads the experiment's truth) the temporary stages
    // that make the experiment again: ut-images (its material), t3-scan
    // (its surface) and t3-contact.
    let again = run_pipeline(t.path(), "pipelines/quick.yaml", &[]);
    assert!(
        text(&again).contains("0 ran, 59 cached, 11 temporary not needed"),
        "{}",
        text(&again)
    );
    let changed = run_pipeline(
        t.path(),
        "pipelines/quick.yaml",
        &["--set", "t3-trunc.levels=500"],
    );
    assert!(changed.status.success(), "{}", text(&changed));
    assert!(
        text(&changed).contains("8 ran, 54 cached, 8 temporary not needed"),
        "{}",
        text(&changed)
    );
}

/// A changed title with a multi-byte character across the plan's 40-byte
/// cut is shown, not a panic (the planner used to slice the text by bytes).
#[test]
fn a_multi_byte_title_change_is_planned_without_panicking() {
    let t = tempfile::tempdir().unwrap();
    let title = format!("{}µ-contact", "T".repeat(38));
    let path = t.path().join("title.yaml");
    std::fs::write(
        &path,
        format!("name: title\nstages:\n  report:\n    uses: report\n    with: {{ title: \"{title}\" }}\n"),
    )
    .unwrap();
    let run = |extra: &[&str]| {
        bin()
            .arg("run")
            .arg(&path)
            .arg("--out")
            .arg(t.path().join("out"))
            .args(extra)
            .output()
            .unwrap()
    };
    let first = run(&[]);
    assert!(first.status.success(), "{}", text(&first));
    let changed = format!("report.title=\"{title}µ\"");
    let plan = run(&["--dry-run", "--set", &changed]);
    let shown = text(&plan);
    assert!(plan.status.success(), "{shown}");
    assert!(
        shown.contains("params changed: title") && shown.contains('…'),
        "{shown}"
    );
    assert!(!shown.contains("panicked"), "{shown}");
}

/// Issue 17's "done when": a real file of each instrument format goes
/// through height-map → surface with no conversion, and DIC runs on a
/// folder of 16-bit TIFFs (12-bit counts) with no force log and no
/// frames.csv, giving stretch, strain and the full field.
#[test]
fn lab_files_go_in_as_the_instruments_wrote_them() {
    let t = tempfile::tempdir().unwrap();
    let out = run_pipeline(t.path(), "pipelines/lab-topography.yaml", &[]);
    assert!(out.status.success(), "{}", text(&out));
    let stderr = String::from_utf8_lossy(&out.stderr);
    // Grids and missing points as SurfaceTopography 1.27 reads the files
    // (shared/reference/topography/index.json).
    for (stage, format, nx, ny, dx_m, dy_m, missing) in [
        (
            "plu",
            "Sensofar .plu",
            768,
            576,
            1.6600000858306884e-06,
            1.6600000858306884e-06,
            0,
        ),
        (
            "metropro",
            "Zygo MetroPro .dat",
            640,
            480,
            1.0982520279867458e-06,
            1.0982520279867458e-06,
            0,
        ),
        (
            "x3p",
            "ISO 25178-72 X3P",
            650,
            650,
            1.27656509837346e-07,
            3.14582113527746e-07,
            0,
        ),
        (
            "sur",
            "Digital Surf .sur",
            563,
            484,
            3.4840002190321683e-06,
            3.4840002190321683e-06,
            117,
        ),
        (
            "opd",
            "Wyko .opd",
            640,
            480,
            1.9673303177114576e-07,
            1.9673303177114576e-07,
            116,
        ),
        // Issue 36's instruments (shared/reference/topography/more/index.json).
        (
            "al3d",
            "Alicona .al3d",
            200,
            296,
            4.38027e-07,
            4.38027e-07,
            0,
        ),
        (
            "di",
            "Bruker Nanoscope .di",
            512,
            512,
            9.765625000000002e-10,
            9.765625000000002e-10,
            0,
        ),
        ("frt", "FRT .frt", 500, 500, 2.4e-05, 2.4e-05, 76456),
        (
            "mnt",
            "Digital Surf .mnt",
            960,
            600,
            1.853393117831074e-06,
            1.8545542570951588e-06,
            0,
        ),
        ("nid", "Nanosurf .nid", 256, 256, 7.8125e-08, 7.8125e-08, 0),
        (
            "ibw",
            "Igor .ibw",
            256,
            256,
            7.843137254901961e-08,
            7.843137254901961e-08,
            0,
        ),
        (
            "mi",
            "Molecular Imaging .mi",
            256,
            256,
            7.812499999999999e-08,
            7.812499999999999e-08,
            0,
        ),
        (
            "tmd",
            "TrueMap .tmd",
            300,
            300,
            6.318866729736329e-05,
            6.318866729736329e-05,
            0,
        ),
        (
            "matrix",
            "ASCII matrix",
            650,
            650,
            3.69862e-07,
            3.69862e-07,
            0,
        ),
    ] {
        let stats = parquet(t.path(), &format!("{stage}-surface/stats.parquet"));
        let int = |c: &str| stats.i64(c).unwrap()[0];
        let num = |c: &str| stats.f64(c).unwrap()[0];
        assert_eq!(
            (int("nx_measured"), int("ny_measured")),
            (nx, ny),
            "{stage}"
        );
        assert!((num("dx_measured_m") / dx_m - 1.0).abs() < 1e-9, "{stage}");
        assert!((num("dy_measured_m") / dy_m - 1.0).abs() < 1e-9, "{stage}");
        assert_eq!(int("filled_points"), missing, "{stage}");
        assert!(
            num("sigma_m").is_finite() && num("sigma_m") > 0.0,
            "{stage}"
        );
        let said = format!("{stage} {format}: {nx} × {ny} points");
        assert!(stderr.contains(&said), "no `{said}` in:\n{stderr}");
    }
    // The stylus profile goes through `surface` as a line scan: its PSD
    // along x, Hurst exponent and σ (Rq), with a note saying so.
    let stats = parquet(t.path(), "dektak-surface/stats.parquet");
    let num = |c: &str| stats.f64(c).unwrap()[0];
    assert_eq!(
        (stats.i64("nx").unwrap()[0], stats.i64("ny").unwrap()[0]),
        (9600, 1)
    );
    for column in ["hurst_x", "sigma_m", "rms_slope"] {
        assert!(num(column).is_finite() && num(column) > 0.0, "{column}");
    }
    assert!(num("hurst_y").is_nan() && num("hurst_radial").is_nan());
    let said = "dektak-surface line scan: a profile of 9600 points along x";
    assert!(stderr.contains(said), "no `{said}` in:\n{stderr}");
    // Read only: too small for a PSD. The AFM file's note names the
    // channel read among the four it holds.
    for said in [
        "gwyddion ASCII matrix: 3 × 4 points",
        "nc NetCDF .nc: 5 × 10 points",
        "dektak Dektak .csv: a line scan of 9600 points",
        "di Bruker Nanoscope .di: 512 × 512 points",
        "channel `Height` read (the file's channels: 0: Height; 1: ",
    ] {
        assert!(stderr.contains(said), "no `{said}` in:\n{stderr}");
    }

    let out = run_pipeline(t.path(), "pipelines/lab-dic.yaml", &[]);
    assert!(out.status.success(), "{}", text(&out));
    let tensile = parquet(t.path(), "oht/tensile.parquet");
    let frames = hypercontact_synth::tensile::open_hole::FILE_NUMBERS;
    assert_eq!(tensile.i64("frame").unwrap(), &frames);
    let stretch = tensile.f64("stretch").unwrap();
    let transverse = tensile.f64("stretch_2").unwrap();
    for (k, &l) in hypercontact_synth::tensile::open_hole::STRETCH_Y
        .iter()
        .enumerate()
    {
        assert!((stretch[k] - l).abs() < 3e-4, "frame {k}: {}", stretch[k]);
        let lx = hypercontact_synth::tensile::open_hole::stretch_x(l);
        assert!((transverse[k] - lx).abs() < 3e-4, "frame {k}");
    }
    assert!(tensile.f64("force_n").unwrap().iter().all(|f| f.is_nan()));
    let field = parquet(t.path(), "oht/field.parquet");
    assert_eq!(field.n_rows() % frames.len(), 0);
    let valid = field.i64("valid").unwrap();
    let eyy = field.f64("eyy").unwrap();
    let last = field.n_rows() - field.n_rows() / frames.len();
    // Green–Lagrange E_yy = (λ² − 1)/2 at every valid point of the last frame.
    let expected = (1.08_f64.powi(2) - 1.0) / 2.0;
    let checked = (last..field.n_rows()).filter(|&r| valid[r] == 1).count();
    assert!(checked > 400, "{checked} valid points");
    for r in (last..field.n_rows()).filter(|&r| valid[r] == 1) {
        assert!((eyy[r] - expected).abs() < 2e-3, "row {r}: {}", eyy[r]);
    }
    assert!(String::from_utf8_lossy(&out.stderr).contains("no force.csv"));
}

/// Output into a pipe its reader has closed (`… | head`): the command ends
/// quietly, as one stopped by SIGPIPE, not with a panic (Rust's
/// `println!` panics on a broken pipe).
#[test]
fn a_closed_stdout_pipe_ends_the_command_quietly() {
    let t = tempfile::tempdir().unwrap();
    let pipeline = repo().join("pipelines/quick.yaml");
    for args in [
        vec!["run", "--dry-run"],
        vec!["run", "--dry-run", "--executor", "slurm"],
        vec!["study", "--dry-run"],
    ] {
        let pipeline = if args[0] == "study" {
            repo().join("pipelines/demo.yaml")
        } else {
            pipeline.clone()
        };
        let mut child = bin()
            .args(&args[..1])
            .arg(&pipeline)
            .args(&args[1..])
            .arg("--cache")
            .arg(t.path().join("cache"))
            .arg("--out")
            .arg(t.path().join("out"))
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        // The reader goes before the command has written a line.
        drop(child.stdout.take());
        let o = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_eq!(o.status.code(), Some(0), "{args:?}: {err}");
    }
}

/// `hypercontact cache ARGS --cache DIR`.
fn cache_cmd(cache: &Path, args: &[&str]) -> Output {
    bin()
        .arg("cache")
        .args(args)
        .arg("--cache")
        .arg(cache)
        .output()
        .unwrap()
}

#[test]
fn writing_to_an_exported_output_reaches_neither_the_cache_nor_another_run() {
    // #31, 3: outputs were hard links into the cache, so as root (past
    // the read-only mode) appending to one run's output changed the cache
    // entry and every other run's output. Failed before at `cache verify`
    // ("1 corrupt") and at the second run's bytes.
    let t = tempfile::tempdir().unwrap();
    assert!(run(t.path(), &["-q"]).status.success());
    let second = t.path().join("out2");
    let again = bin()
        .arg("run")
        .arg(t.path().join("demo.yaml"))
        .arg("--out")
        .arg(&second)
        .output()
        .unwrap();
    assert!(text(&again).contains("0 ran, 5 cached"), "{}", text(&again));
    let file = "contact/response.parquet";
    let untouched = std::fs::read(second.join(file)).unwrap();
    use std::io::Write as _;
    std::fs::File::options()
        .append(true)
        .open(t.path().join("out").join(file))
        .expect("a run's output is its own, writable file")
        .write_all(b"appended by hand")
        .unwrap();
    assert_eq!(std::fs::read(second.join(file)).unwrap(), untouched);
    let verify = cache_cmd(&t.path().join(".hypercontact/cache"), &["verify"]);
    assert!(verify.status.success(), "{}", text(&verify));
    assert!(text(&verify).contains(", 0 corrupt"), "{}", text(&verify));
}

/// Each entry's `manifest.json` under `cache`, parsed.
fn manifests(cache: &Path) -> Vec<(PathBuf, serde_json::Value)> {
    let mut out: Vec<_> = std::fs::read_dir(cache.join("entries"))
        .unwrap()
        .map(|e| {
            let path = e.unwrap().path().join("manifest.json");
            let json = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
            (path, json)
        })
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

/// Writes `json` over a (read-only) cache file.
fn rewrite(path: &Path, json: &serde_json::Value) {
    let mut perms = std::fs::metadata(path).unwrap().permissions();
    #[allow(clippy::permissions_set_readonly_false)]
    perms.set_readonly(false);
    std::fs::set_permissions(path, perms).unwrap();
    std::fs::write(path, serde_json::to_vec(json).unwrap()).unwrap();
}

#[test]
fn every_entry_names_the_build_that_made_it_and_verify_lists_other_builds() {
    // #31, 4: a cache key holds no trace of the code; the manifest, the
    // provenance and `cache ls` name the build, and `verify --producer`
    // lists entries made by another (or an unknown) build.
    let t = tempfile::tempdir().unwrap();
    assert!(run(t.path(), &["-q"]).status.success());
    let version = text(&bin().arg("--version").output().unwrap());
    let build = version
        .trim()
        .trim_start_matches("hypercontact ")
        .to_owned();
    assert!(
        build.starts_with(env!("CARGO_PKG_VERSION")) && build.contains("+src."),
        "{version}"
    );
    let cache = t.path().join(".hypercontact/cache");
    let entries = manifests(&cache);
    assert_eq!(entries.len(), 5);
    for (path, m) in &entries {
        assert_eq!(m["producer"], build.as_str(), "{}", path.display());
    }
    let prov: serde_json::Value =
        serde_json::from_slice(&std::fs::read(t.path().join("out/provenance.json")).unwrap())
            .unwrap();
    assert_eq!(prov["producer"], build.as_str());
    assert_eq!(prov["stages"]["trunc"]["producer"], build.as_str());
    let ls = text(&cache_cmd(&cache, &["ls"]));
    assert_eq!(ls.matches(build.as_str()).count(), 5, "{ls}");
    let listed = cache_cmd(&cache, &["verify", "--producer"]);
    assert!(text(&listed).contains("5 entries, 0 made by another build"));

    // One entry from another build, one from before builds were recorded.
    let (other, mut m) = entries[0].clone();
    m["producer"] = "0.0.1+src.0123456789abcdef".into();
    rewrite(&other, &m);
    let (old, mut m) = entries[1].clone();
    m.as_object_mut().unwrap().remove("producer");
    rewrite(&old, &m);
    let listed = cache_cmd(&cache, &["verify", "--producer"]);
    let said = text(&listed);
    assert!(listed.status.success(), "{said}");
    assert!(
        said.contains("5 entries, 2 made by another build"),
        "{said}"
    );
    assert!(
        said.contains("made by 0.0.1+src.0123456789abcdef"),
        "{said}"
    );
    assert!(said.contains("made by unknown build"), "{said}");
    let ls = text(&cache_cmd(&cache, &["ls"]));
    assert!(
        ls.contains("unknown build") && !ls.contains("(unreadable)"),
        "{ls}"
    );
    // The producer is not part of the key: the entries are still reused.
    let again = run(t.path(), &[]);
    assert!(text(&again).contains("0 ran, 5 cached"), "{}", text(&again));
}
