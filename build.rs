//! Build identity of the `hypercontact` binary: the package version and a
//! hash of the workspace sources it was built from, as the compile-time
//! variable `HYPERCONTACT_BUILD` (`0.1.0+src.1f2e3d4c5b6a7980`).
//!
//! Cache entries record it as their producer (#31, 4), so entries made by
//! another build can be listed. A hash of the sources rather than a git
//! commit: it also tells a dirty tree from its commit and works in a
//! tarball without `.git`. The binary's own package is rebuilt whenever
//! any crate changes anyway, so hashing here costs no extra compilation.

use std::fs;
use std::path::{Path, PathBuf};

/// FNV-1a, 64 bit: stable across toolchains (unlike `DefaultHasher`) and
/// needs no build dependency. An identity, not a security check.
struct Fnv64(u64);

impl Fnv64 {
    fn update(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
}

/// Every file under `dir`, recursively.
fn files_under(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            files_under(&path, out);
        } else {
            out.push(path);
        }
    }
}

/// What the binary is compiled from: manifests, the lock file, build
/// scripts and every crate's `src/` and `assets/` (the report's font). A
/// crate that joins the binary changes the root `Cargo.toml`.
fn source_files(root: &Path) -> (Vec<PathBuf>, Vec<PathBuf>) {
    let mut watched = vec![
        root.join("Cargo.toml"),
        root.join("Cargo.lock"),
        root.join("build.rs"),
        root.join("src"),
    ];
    if let Ok(crates) = fs::read_dir(root.join("crates")) {
        for krate in crates.flatten() {
            let dir = krate.path();
            watched.extend(["Cargo.toml", "build.rs", "src", "assets"].map(|p| dir.join(p)));
        }
    }
    let mut files = Vec::new();
    for path in &watched {
        if path.is_dir() {
            files_under(path, &mut files);
        } else if path.is_file() {
            files.push(path.clone());
        }
    }
    files.sort();
    (watched, files)
}

fn main() {
    let root = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    let (watched, files) = source_files(&root);
    let mut hash = Fnv64(0xcbf2_9ce4_8422_2325);
    for file in &files {
        let rel = file.strip_prefix(&root).unwrap_or(file);
        // Path and length first, so moving bytes between files changes it.
        let bytes = fs::read(file).unwrap_or_default();
        hash.update(rel.to_string_lossy().as_bytes());
        hash.update(&(bytes.len() as u64).to_le_bytes());
        hash.update(&bytes);
    }
    let version = std::env::var("CARGO_PKG_VERSION").unwrap_or_default();
    println!(
        "cargo::rustc-env=HYPERCONTACT_BUILD={version}+src.{:016x}",
        hash.0
    );
    for path in &watched {
        if path.exists() {
            println!("cargo::rerun-if-changed={}", path.display());
        }
    }
}
