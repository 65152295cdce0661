//! The architecture invariant of the crate doc: core's dependency tree (what
//! every stage crate builds) holds no lab-file decoders and no terminal
//! progress library. Asked of `cargo tree`, so a crate pulled in through
//! another dependency counts too.

use std::collections::BTreeSet;
use std::process::Command;

/// Crates that belong to hypercontact-labfiles (image, tiff, csv,
/// alphanumeric-sort) or to the runner (indicatif).
const NOT_IN_CORE: [&str; 5] = ["image", "tiff", "csv", "alphanumeric-sort", "indicatif"];

#[test]
fn core_builds_no_image_csv_or_progress_crates() {
    let cargo = option_env!("CARGO").unwrap_or("cargo");
    let output = Command::new(cargo)
        .args([
            "tree",
            "--offline",
            "--package",
            "hypercontact-core",
            "--edges",
            "normal,build",
            "--prefix",
            "none",
            "--format",
            "{p}",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("cargo runs");
    let tree = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "cargo tree failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let names: BTreeSet<&str> = tree
        .lines()
        .filter_map(|line| line.split_whitespace().next())
        .collect();
    // The listing is the tree: core itself and a dependency it does have.
    assert!(
        names.contains("hypercontact-core") && names.contains("ndarray"),
        "{tree}"
    );
    for name in NOT_IN_CORE {
        assert!(!names.contains(name), "core depends on {name}:\n{tree}");
    }
}
