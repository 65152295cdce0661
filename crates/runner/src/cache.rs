//! The content-addressed cache of stage outputs.
//!
//! Layout under the cache root:
//! - `entries/<key>/`: one finished entry: its products and `manifest.json`
//!   (every file's BLAKE3 and size);
//! - `tmp/`: entries being written; a finished one is renamed into
//!   `entries/` in one step, so a run killed mid-write leaves only debris in
//!   `tmp/`, never a half-written entry (the scheme ruff uses for its cache:
//!   write a temporary file, then rename);
//! - `locks/<key>.lock`: an exclusive file lock held while an entry is
//!   computed or removed, so two runs sharing the cache compute it once.
//!   Removing an entry removes its lock file; a locker checks after locking
//!   that the file it locked is still the one at that path, so an unlinked
//!   lock never lets two processes in.
//!
//! - `stamps/<key>.json`: for each file of an entry, the file's size, inode,
//!   ctime and mtime when its hash last matched.
//!
//! An entry is trusted only if its manifest parses and every file matches
//! its recorded size and hash; anything else is recomputed. A file is
//! hashed the first time an entry is reused; later checks hash it again
//! only if its stamp changed. Nothing rewrites a file without changing its
//! ctime (no user tool can set it back), so an edited, replaced or
//! truncated file is still caught, while a warm run of a pipeline with
//! gigabytes of cached tiles costs a `stat` per file instead of reading them
//! all (git's index trusts unchanged stat data the same way).

use std::collections::BTreeMap;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use serde::{Deserialize, Serialize};

use crate::hash::file_hash;
use crate::store::OutputRecord;

/// What an entry records about itself.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub format: u32,
    pub key: String,
    pub kind: String,
    pub version: u32,
    /// The stage's name in the pipeline that first computed it.
    pub stage: String,
    pub created_unix_s: u64,
    /// How long the computation took, seconds.
    pub compute_s: f64,
    pub params: serde_json::Value,
    pub outputs: BTreeMap<String, OutputRecord>,
    /// What the stage said while computing the entry (`Context::note`), so
    /// a cache hit still reports it.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    /// The build that computed the entry (`crate::producer`); None in a
    /// manifest written before builds were recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub producer: Option<String>,
}

/// The layout of an entry. 2: tables carry their columns' units and
/// descriptions in the Parquet file (issue #34); an entry of format 1 has
/// tables without them, so it is recomputed rather than served.
pub const MANIFEST_FORMAT: u32 = 2;

/// The state of an entry on disk.
#[derive(Debug)]
pub enum EntryState {
    Missing,
    Valid(Box<Manifest>),
    /// Present but not trustworthy, with the reason.
    Corrupt(String),
}

#[derive(Clone, Debug)]
pub struct Cache {
    root: PathBuf,
}

/// Holds an entry's lock; released on drop.
pub struct EntryLock {
    _file: fs::File,
}

fn now_unix_s() -> u64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_secs())
}

fn unique_suffix() -> String {
    let nanos = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    format!("{}.{nanos}", std::process::id())
}

/// The file that marks a folder as a hypercontact cache: `cache clean`
/// removes a folder only when it holds this file (or the bare layout of a
/// cache made before the marker), never a folder that merely was named.
pub const MARKER: &str = "HYPERCONTACT_CACHE";

/// The folders of a cache.
const LAYOUT: [&str; 4] = ["entries", "tmp", "locks", "stamps"];

impl Cache {
    /// The cache at `root`, made if `root` is absent or empty. A folder that
    /// holds anything else and no [`MARKER`] is refused (it is not a cache,
    /// and a cache written into it would be cleaned with it).
    pub fn open(root: &Path) -> io::Result<Self> {
        if let Some(why) = not_a_cache(root)? {
            return Err(io::Error::new(io::ErrorKind::InvalidInput, why));
        }
        for sub in LAYOUT {
            fs::create_dir_all(root.join(sub))?;
        }
        let marker = root.join(MARKER);
        if !marker.exists() {
            fs::write(&marker, "hypercontact cache, layout 1\n")?;
        }
        Ok(Self {
            root: root.to_owned(),
        })
    }

    /// The cache at `root` if there is one; `None` rather than creating it
    /// (for commands that only look: `cache ls`, `cache gc`).
    pub fn open_existing(root: &Path) -> io::Result<Option<Self>> {
        if root.join("entries").is_dir() {
            Self::open(root).map(Some)
        } else {
            Ok(None)
        }
    }

    pub fn root(&self) -> &Path {
        &self.root
    }

    pub fn entry_dir(&self, key: &str) -> PathBuf {
        self.root.join("entries").join(key)
    }

    /// Records the current stat stamps of an entry's files. Only for an
    /// entry this run has just verified or written (its files hashed in
    /// this run), after exporting it, so the next run trusts their stat
    /// data instead of hashing them again.
    pub fn restamp(&self, key: &str, manifest: &Manifest) {
        let dir = self.entry_dir(key);
        let mut stamps = BTreeMap::new();
        for record in manifest.outputs.values() {
            for rel in record.files.keys() {
                let Some(s) = fs::metadata(dir.join(rel)).ok().as_ref().and_then(stamp) else {
                    return;
                };
                stamps.insert(rel.clone(), s);
            }
        }
        // Unchanged stamps are not written again: a cached rerun's every
        // stage would otherwise sync a file (#50, 4).
        let path = self.stamps_path(key);
        if let Ok(bytes) = serde_json::to_vec(&stamps)
            && fs::read(&path).ok().as_deref() != Some(&bytes[..])
        {
            let _ = crate::write_atomic(&path, &bytes);
        }
    }

    fn stamps_path(&self, key: &str) -> PathBuf {
        self.root.join("stamps").join(format!("{key}.json"))
    }

    /// Checks an entry: manifest readable, every file present with its size
    /// and hash (a file whose stamp is unchanged since its last check is
    /// trusted without hashing).
    pub fn check(&self, key: &str) -> EntryState {
        self.check_with(key, true)
    }

    /// [`Cache::check`] hashing every file, stamps or not (`cache verify`).
    pub fn verify(&self, key: &str) -> EntryState {
        self.check_with(key, false)
    }

    fn check_with(&self, key: &str, trust_stamps: bool) -> EntryState {
        let dir = self.entry_dir(key);
        if !dir.exists() {
            return EntryState::Missing;
        }
        let manifest: Manifest = match fs::read(dir.join("manifest.json"))
            .map_err(|e| e.to_string())
            .and_then(|b| serde_json::from_slice(&b).map_err(|e| e.to_string()))
        {
            Ok(m) => m,
            Err(e) => return EntryState::Corrupt(format!("manifest unreadable: {e}")),
        };
        if manifest.key != key || manifest.format != MANIFEST_FORMAT {
            return EntryState::Corrupt("manifest belongs to another key or format".into());
        }
        let stamps_path = self.stamps_path(key);
        let old_stamps: BTreeMap<String, String> = fs::read(&stamps_path)
            .ok()
            .and_then(|b| serde_json::from_slice(&b).ok())
            .unwrap_or_default();
        let mut stamps = BTreeMap::new();
        for record in manifest.outputs.values() {
            for (rel, file) in &record.files {
                let path = dir.join(rel);
                let meta = match fs::metadata(&path) {
                    Ok(m) if m.len() == file.bytes => m,
                    Ok(m) => {
                        return EntryState::Corrupt(format!(
                            "{rel} has {} bytes, expected {}",
                            m.len(),
                            file.bytes
                        ));
                    }
                    Err(e) => return EntryState::Corrupt(format!("{rel}: {e}")),
                };
                let stamp = stamp(&meta);
                if let Some(unchanged) = &stamp
                    && trust_stamps
                    && old_stamps.get(rel) == Some(unchanged)
                {
                    stamps.insert(rel.clone(), unchanged.clone());
                    continue;
                }
                match file_hash(&path) {
                    Ok(h) if h == file.blake3 => {}
                    Ok(_) => return EntryState::Corrupt(format!("{rel} fails its hash check")),
                    Err(e) => return EntryState::Corrupt(format!("{rel}: {e}")),
                }
                if let Some(stamp) = stamp {
                    stamps.insert(rel.clone(), stamp);
                }
            }
        }
        if stamps != old_stamps
            && let Ok(bytes) = serde_json::to_vec(&stamps)
        {
            // Best effort: without a stamp the next check hashes again.
            let _ = crate::write_atomic(&stamps_path, &bytes);
        }
        EntryState::Valid(Box::new(manifest))
    }

    fn lock_path(&self, key: &str) -> PathBuf {
        self.root.join("locks").join(format!("{key}.lock"))
    }

    /// Blocks until this process holds the entry's lock.
    pub fn lock(&self, key: &str) -> io::Result<EntryLock> {
        loop {
            let file = self.open_lock(key)?;
            file.lock()?;
            if self.still_linked(key, &file) {
                return Ok(EntryLock { _file: file });
            }
            // The file was removed (with its entry) while we waited: lock
            // the one now at the path instead.
        }
    }

    /// The entry's lock if no one holds it now, without waiting.
    pub fn try_lock(&self, key: &str) -> io::Result<Option<EntryLock>> {
        let file = self.open_lock(key)?;
        match file.try_lock() {
            Ok(()) if self.still_linked(key, &file) => Ok(Some(EntryLock { _file: file })),
            Ok(()) | Err(fs::TryLockError::WouldBlock) => Ok(None),
            Err(fs::TryLockError::Error(e)) => Err(e),
        }
    }

    fn open_lock(&self, key: &str) -> io::Result<fs::File> {
        fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(self.lock_path(key))
    }

    /// Whether `file` is still the lock file at the entry's path.
    #[cfg(unix)]
    fn still_linked(&self, key: &str, file: &fs::File) -> bool {
        use std::os::unix::fs::MetadataExt;
        match (file.metadata(), fs::metadata(self.lock_path(key))) {
            (Ok(held), Ok(at_path)) => held.ino() == at_path.ino() && held.dev() == at_path.dev(),
            _ => false,
        }
    }

    #[cfg(not(unix))]
    fn still_linked(&self, _: &str, _: &fs::File) -> bool {
        true
    }

    /// Removes staging folders of entry `key` left by writers that are gone.
    /// Call with the entry's lock held: no live process is writing it then.
    pub fn clear_staging(&self, key: &str) {
        let Ok(entries) = fs::read_dir(self.root.join("tmp")) else {
            return;
        };
        for entry in entries.flatten() {
            if entry_key(&entry.file_name().to_string_lossy()) == key {
                let _ = remove_tree(&entry.path());
            }
        }
    }

    /// A fresh temporary folder for writing an entry.
    pub fn staging_dir(&self, key: &str) -> io::Result<PathBuf> {
        let dir = self
            .root
            .join("tmp")
            .join(format!("{key}.{}", unique_suffix()));
        fs::create_dir_all(&dir)?;
        Ok(dir)
    }

    /// Finishes an entry written in `staging`: writes its manifest, makes
    /// its files read-only, and renames it into place (replacing a corrupt
    /// entry, if one is there). Call with the entry's lock held.
    pub fn commit(&self, staging: &Path, manifest: &Manifest) -> io::Result<PathBuf> {
        for record in manifest.outputs.values() {
            for rel in record.files.keys() {
                let path = staging.join(rel);
                let mut perms = fs::metadata(&path)?.permissions();
                perms.set_readonly(true);
                fs::set_permissions(&path, perms)?;
            }
        }
        let bytes = serde_json::to_vec_pretty(manifest).map_err(io::Error::other)?;
        fs::write(staging.join("manifest.json"), bytes)?;
        let dst = self.entry_dir(&manifest.key);
        if dst.exists() {
            let trash =
                self.root
                    .join("tmp")
                    .join(format!("{}.trash.{}", manifest.key, unique_suffix()));
            fs::rename(&dst, &trash)?;
            let _ = remove_tree(&trash);
        }
        fs::rename(staging, &dst)?;
        Ok(dst)
    }

    /// Marks an entry as used now (for `cache gc --older-than`).
    pub fn touch(&self, key: &str) {
        let path = self.entry_dir(key).join("manifest.json");
        if let Ok(file) = fs::File::options().append(true).open(&path) {
            let _ = file.set_modified(SystemTime::now());
        }
    }

    /// Every entry with its manifest (or why it is unreadable), size in bytes
    /// and last use.
    pub fn list(&self) -> io::Result<Vec<EntryInfo>> {
        let mut out = Vec::new();
        for entry in fs::read_dir(self.root.join("entries"))? {
            let entry = entry?;
            let key = entry.file_name().to_string_lossy().into_owned();
            let dir = entry.path();
            let manifest = fs::read(dir.join("manifest.json"))
                .ok()
                .and_then(|b| serde_json::from_slice::<Manifest>(&b).ok());
            let last_used = fs::metadata(dir.join("manifest.json"))
                .and_then(|m| m.modified())
                .ok();
            out.push(EntryInfo {
                bytes: tree_size(&dir),
                key,
                manifest,
                last_used,
            });
        }
        out.sort_by(|a, b| a.last_used.cmp(&b.last_used).then(a.key.cmp(&b.key)));
        Ok(out)
    }

    /// Removes one entry, its stamps and its lock file.
    pub fn remove(&self, key: &str) -> io::Result<()> {
        let _lock = self.lock(key)?;
        let trash = self
            .root
            .join("tmp")
            .join(format!("{key}.trash.{}", unique_suffix()));
        let _ = fs::remove_file(self.stamps_path(key));
        if self.entry_dir(key).exists() {
            fs::rename(self.entry_dir(key), &trash)?;
            remove_tree(&trash)?;
        }
        self.clear_staging(key);
        // Unlinked while held: a process waiting on this file sees that it is
        // gone once it gets it, and locks the new one (see `lock`).
        fs::remove_file(self.lock_path(key))?;
        Ok(())
    }

    /// Removes leftovers of interrupted runs: staging and trash folders in
    /// `tmp/` whose entry no process holds locked (their writers are gone),
    /// half-written stamp files older than a minute, and lock files of
    /// entries that no longer exist and no one holds. Returns how many.
    pub fn clean_debris(&self) -> io::Result<usize> {
        let mut n = 0;
        for entry in fs::read_dir(self.root.join("tmp"))? {
            let entry = entry?;
            let key = entry_key(&entry.file_name().to_string_lossy()).to_owned();
            if self.try_lock(&key)?.is_some() {
                remove_tree(&entry.path())?;
                n += 1;
            }
        }
        for entry in fs::read_dir(self.root.join("stamps"))? {
            let entry = entry?;
            let name = entry.file_name().to_string_lossy().into_owned();
            let age_s = entry
                .metadata()?
                .modified()
                .ok()
                .and_then(|t| t.elapsed().ok())
                .map_or(0, |d| d.as_secs());
            if name.ends_with(".tmp") && age_s >= 60 {
                fs::remove_file(entry.path())?;
                n += 1;
            }
        }
        for entry in fs::read_dir(self.root.join("locks"))? {
            let entry = entry?;
            let name = entry.file_name().to_string_lossy().into_owned();
            let Some(key) = name.strip_suffix(".lock") else {
                continue;
            };
            if !self.entry_dir(key).exists()
                && let Some(_held) = self.try_lock(key)?
            {
                fs::remove_file(entry.path())?;
                n += 1;
            }
        }
        Ok(n)
    }

    /// Removes the whole cache (checked again: the folder may have gained
    /// other files since it was opened).
    pub fn clean(&self) -> io::Result<()> {
        if let Some(why) = not_a_cache(&self.root)? {
            return Err(io::Error::new(io::ErrorKind::InvalidInput, why));
        }
        remove_tree(&self.root)
    }
}

/// Why `root` is not a hypercontact cache, or `None` when it is one (it
/// holds [`MARKER`], or only the cache's own folders: a cache made before
/// the marker) or may become one (absent or empty).
pub fn not_a_cache(root: &Path) -> io::Result<Option<String>> {
    let listing = match fs::read_dir(root) {
        Ok(listing) => listing,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(None),
        Err(e) if e.kind() == io::ErrorKind::NotADirectory => {
            return Ok(Some("it is a file, not a folder".to_owned()));
        }
        Err(e) => return Err(e),
    };
    let mut foreign = Vec::new();
    for entry in listing {
        let entry = entry?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if name == MARKER {
            return Ok(None);
        }
        let is_dir = entry.file_type()?.is_dir();
        if !(is_dir && LAYOUT.contains(&name.as_str())) {
            foreign.push(if is_dir { format!("{name}/") } else { name });
        }
    }
    if foreign.is_empty() {
        return Ok(None);
    }
    foreign.sort();
    let shown = foreign.len().min(5);
    let more = match foreign.len() - shown {
        0 => String::new(),
        n => format!(" and {n} more"),
    };
    Ok(Some(format!(
        "not a hypercontact cache: it holds {}{more} and no {MARKER} file; \
         refusing to use or remove it (give --cache an empty or new folder)",
        foreign[..shown].join(", ")
    )))
}

/// The key a `tmp/` name belongs to: `<key>.<pid>.<ns>` or
/// `<key>.trash.<pid>.<ns>` (keys are hex, without dots).
fn entry_key(name: &str) -> &str {
    name.split('.').next().unwrap_or(name)
}

/// The first 12 characters of an entry key, as messages show it: the whole
/// text when shorter, and whole characters always (the key in a job file is
/// whatever the file says).
pub fn short_key(key: &str) -> &str {
    key.char_indices().nth(12).map_or(key, |(at, _)| &key[..at])
}

/// An entry as listed by `cache ls`.
#[derive(Debug)]
pub struct EntryInfo {
    pub key: String,
    pub manifest: Option<Manifest>,
    pub bytes: u64,
    pub last_used: Option<SystemTime>,
}

/// What identifies a file's state without reading it: size, inode, ctime
/// and mtime (ns). None where the platform has no ctime.
#[cfg(unix)]
fn stamp(meta: &fs::Metadata) -> Option<String> {
    use std::os::unix::fs::MetadataExt;
    Some(format!(
        "{}:{}:{}.{:09}:{}.{:09}",
        meta.len(),
        meta.ino(),
        meta.ctime(),
        meta.ctime_nsec(),
        meta.mtime(),
        meta.mtime_nsec()
    ))
}

#[cfg(not(unix))]
fn stamp(_: &fs::Metadata) -> Option<String> {
    None
}

/// Deletes a tree even where files were made read-only.
fn remove_tree(path: &Path) -> io::Result<()> {
    match fs::remove_dir_all(path) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(e),
    }
}

fn tree_size(path: &Path) -> u64 {
    let Ok(entries) = fs::read_dir(path) else {
        return 0;
    };
    entries
        .filter_map(Result::ok)
        .map(|e| match e.file_type() {
            Ok(t) if t.is_dir() => tree_size(&e.path()),
            _ => e.metadata().map_or(0, |m| m.len()),
        })
        .sum()
}

pub(crate) fn unix_now() -> u64 {
    now_unix_s()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_short_key_is_its_first_twelve_characters() {
        let key = blake3::hash(b"entry").to_hex();
        assert_eq!(short_key(&key), &key[..12]);
        assert_eq!(short_key("0123"), "0123");
        assert_eq!(short_key(""), "");
        // Byte 12 falls inside the seventh `é`: slicing bytes panicked there.
        assert_eq!(short_key("aééééééééééééé"), "aééééééééééé");
    }

    #[test]
    fn only_a_cache_is_taken_for_one() {
        let t = tempfile::tempdir().unwrap();
        let dir = t.path();
        // Absent or empty: may become a cache.
        assert_eq!(not_a_cache(&dir.join("new")).unwrap(), None);
        assert_eq!(not_a_cache(dir).unwrap(), None);
        // A cache made before the marker: only its own folders.
        for sub in LAYOUT {
            fs::create_dir(dir.join(sub)).unwrap();
        }
        assert_eq!(not_a_cache(dir).unwrap(), None);
        // Anything else, without the marker, is named; seven strangers
        // show as five and a count.
        for k in 0..6 {
            fs::write(dir.join(format!("note{k}.txt")), "x").unwrap();
        }
        fs::create_dir(dir.join("chapter")).unwrap();
        let why = not_a_cache(dir).unwrap().unwrap();
        assert!(
            why.contains("chapter/, note0.txt, note1.txt, note2.txt, note3.txt and 2 more"),
            "{why}"
        );
        let e = Cache::open(dir).err().unwrap();
        assert!(e.to_string().contains("not a hypercontact cache"), "{e}");
        // A file where the folder should be.
        assert!(
            not_a_cache(&dir.join("note0.txt"))
                .unwrap()
                .unwrap()
                .contains("a file")
        );
        // The marker makes it a cache (a user's file inside one is the
        // cache's to remove).
        fs::write(dir.join(MARKER), "").unwrap();
        assert_eq!(not_a_cache(dir).unwrap(), None);
    }

    #[test]
    fn a_new_cache_carries_the_marker_and_an_old_one_gains_it() {
        let t = tempfile::tempdir().unwrap();
        let fresh = t.path().join("fresh");
        Cache::open(&fresh).unwrap();
        assert!(fresh.join(MARKER).is_file());
        let old = t.path().join("old");
        for sub in LAYOUT {
            fs::create_dir_all(old.join(sub)).unwrap();
        }
        Cache::open(&old).unwrap();
        assert!(old.join(MARKER).is_file());
    }
}
