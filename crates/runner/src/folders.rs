//! Whether one folder lies inside another as the user means it: paths
//! compared absolute, with `.` and `..` taken by name, and again through
//! symbolic links where the folders exist. `run` refuses an output folder
//! that overlaps the cache with these; `export` refuses one inside a cache
//! or inside the run it exports.

use std::path::{Path, PathBuf};

use crate::cache::MARKER;

/// The part of `path` below `folder` (empty when they are the same
/// folder), or None when `path` is not inside `folder` by name nor through
/// symbolic links.
pub fn part_within(path: &Path, folder: &Path) -> Option<PathBuf> {
    let (path_abs, folder_abs) = (lexical_absolute(path), lexical_absolute(folder));
    let resolved = |p: &Path| nearest_existing(p).unwrap_or_else(|| p.to_owned());
    let below = |p: &Path, f: &Path| p.strip_prefix(f).ok().map(Path::to_owned);
    below(&path_abs, &folder_abs).or_else(|| below(&resolved(&path_abs), &resolved(&folder_abs)))
}

/// Whether `path` is `folder` or lies inside it.
pub fn is_within(path: &Path, folder: &Path) -> bool {
    part_within(path, folder).is_some()
}

/// The cache that `path` is the root of or lies inside, if any: the
/// nearest folder at or above it (by name, then through symbolic links)
/// that holds a cache's [`MARKER`] or the bare layout of a cache made
/// before the marker.
pub fn enclosing_cache(path: &Path) -> Option<PathBuf> {
    let path_abs = lexical_absolute(path);
    let resolved = nearest_existing(&path_abs);
    [Some(path_abs), resolved]
        .into_iter()
        .flatten()
        .find_map(|p| p.ancestors().find(|a| is_cache_root(a)).map(Path::to_owned))
}

/// Whether `dir` is a cache's root folder.
fn is_cache_root(dir: &Path) -> bool {
    dir.join(MARKER).is_file()
        || ["entries", "tmp", "locks"]
            .iter()
            .all(|sub| dir.join(sub).is_dir())
}

/// `path` made absolute, `.` dropped and `..` taken back by name.
pub fn lexical_absolute(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_owned());
    let mut out = PathBuf::new();
    for part in absolute.components() {
        match part {
            std::path::Component::CurDir => {}
            std::path::Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// `path` with its longest existing ancestor resolved through symbolic
/// links, the rest appended as named.
fn nearest_existing(path: &Path) -> Option<PathBuf> {
    let mut rest = Vec::new();
    let mut head = path;
    loop {
        if let Ok(real) = head.canonicalize() {
            return Some(rest.iter().rev().fold(real, |p, part| p.join(part)));
        }
        rest.push(head.file_name()?.to_owned());
        head = head.parent()?;
    }
}
