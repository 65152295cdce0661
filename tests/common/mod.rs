//! What the binary's end-to-end tests share: the binary, a process's text,
//! and a run folder's products.
#![allow(dead_code)] // each test file uses its part

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_hypercontact"))
}

pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A finished process's stdout then stderr.
pub fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// Every file under `root` by its `/`-separated path relative to `root`,
/// with its bytes, except the paths `skip` names.
pub fn products(root: &Path, skip: impl Fn(&str) -> bool) -> BTreeMap<String, Vec<u8>> {
    let mut files = BTreeMap::new();
    let mut folders = vec![root.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
                continue;
            }
            let name = path
                .strip_prefix(root)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            if !skip(&name) {
                files.insert(name, std::fs::read(&path).unwrap());
            }
        }
    }
    files
}

/// A run's own record, with times and folders: `provenance.json` (of a run
/// or of each study variant).
pub fn run_record(name: &str) -> bool {
    name == "provenance.json" || name.ends_with("/provenance.json")
}
