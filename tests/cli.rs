//! The `hypercontact` binary end to end on the shipped sample map.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_hypercontact"))
}

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

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

#[test]
fn run_twice_then_everything_is_cached_and_identical() {
    let t = tempfile::tempdir().unwrap();
    let first = run(t.path(), &[]);
    assert!(first.status.success(), "{}", text(&first));
    assert!(text(&first).contains("5 ran, 0 cached"), "{}", text(&first));
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
        &table.column_names()[..2],
        ["contact.scheme", "trunc.levels"]
    );
    let levels = table.i64("trunc.levels").unwrap();
    assert!(levels.contains(&250) && levels.contains(&1000));
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
    for kind in ["height-map", "truncation", "icm", "material-preset"] {
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

#[test]
fn the_paper_pipeline_runs_from_a_fresh_cache() {
    let t = tempfile::tempdir().unwrap();
    let out = bin()
        .arg("run")
        .arg(repo().join("pipelines/paper.yaml"))
        .arg("--out")
        .arg(t.path().join("out"))
        .arg("--cache")
        .arg(t.path().join("cache"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out));
    assert!(text(&out).contains("7 ran, 0 cached"), "{}", text(&out));
    let fit =
        hypercontact_io::read_parquet_file(&t.path().join("out/fit/quality.parquet")).unwrap();
    assert!(fit.f64("r2").unwrap().iter().all(|r2| *r2 > 0.99));
    let hyper =
        hypercontact_io::read_parquet_file(&t.path().join("out/contact/response.parquet")).unwrap();
    let ratio = hyper.f64("tangent_ratio").unwrap();
    assert!(
        ratio.iter().all(|r| (1.99..3.0).contains(r)),
        "E_t*/E0* outside [2, 3]"
    );
}
