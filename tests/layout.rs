//! Every integration-test file compiles and runs. The crates list their test
//! binaries (`autotests = false`: one binary per crate, `tests/integration.rs`,
//! which keeps the tests' cold build short, #35), so a new file under some
//! `tests/` that is neither a module of that binary nor a `[[test]]` of its
//! own would be skipped without a word. This test names such a file.

use std::path::Path;

use crate::common::repo;

/// The test files of the package at `dir` that no test target reaches.
fn unreached(dir: &Path) -> Vec<String> {
    let manifest = std::fs::read_to_string(dir.join("Cargo.toml")).unwrap();
    let tests = dir.join("tests");
    if !manifest.contains("autotests = false") || !tests.is_dir() {
        return Vec::new();
    }
    let binary = std::fs::read_to_string(tests.join("integration.rs")).unwrap_or_default();
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(&tests).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        let Some(module) = name.strip_suffix(".rs") else {
            continue;
        };
        let as_module = binary.lines().any(|l| l.trim() == format!("mod {module};"));
        let as_target = manifest.contains(&format!("path = \"tests/{name}\""));
        if !(as_module || as_target) {
            missing.push(format!("{}/tests/{name}", dir.display()));
        }
    }
    missing
}

#[test]
fn every_test_file_belongs_to_a_test_binary() {
    let root = repo();
    let mut packages = vec![root.clone()];
    for entry in std::fs::read_dir(root.join("crates")).unwrap() {
        packages.push(entry.unwrap().path());
    }
    let missing: Vec<String> = packages.iter().flat_map(|p| unreached(p)).collect();
    assert!(
        missing.is_empty(),
        "test files no test target compiles (add `mod NAME;` to that tests/integration.rs): {missing:?}"
    );
}

#[test]
fn a_file_left_out_of_the_binary_is_named() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("tests")).unwrap();
    std::fs::write(
        dir.path().join("Cargo.toml"),
        "[package]\nautotests = false\n\n[[test]]\nname = \"integration\"\n\
         path = \"tests/integration.rs\"\n\n[[test]]\nname = \"kill\"\npath = \"tests/kill.rs\"\n",
    )
    .unwrap();
    for (file, text) in [
        ("integration.rs", "mod listed;\n"),
        ("listed.rs", ""),
        ("kill.rs", ""),
        ("forgotten.rs", ""),
    ] {
        std::fs::write(dir.path().join("tests").join(file), text).unwrap();
    }
    let missing = unreached(dir.path());
    assert_eq!(missing.len(), 1, "{missing:?}");
    assert!(missing[0].ends_with("tests/forgotten.rs"), "{missing:?}");
}
