//! Content hashes and canonical JSON: the ingredients of a cache key.

use std::fs;
use std::io;
use std::path::Path;

use hypercontact_core::regular_file::{is_symlink_loop, not_regular, not_regular_kind};

/// BLAKE3 of a file's bytes, hex. Anything but a regular file (a device
/// such as `/dev/zero`, a pipe) is refused: reading one may never end.
pub fn file_hash(path: &Path) -> io::Result<String> {
    let meta = fs::metadata(path).map_err(|e| match is_symlink_loop(&e) {
        true => io::Error::new(e.kind(), "is a symlink loop"),
        false => e,
    })?;
    if let Some(kind) = not_regular_kind(&meta) {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("is {}", not_regular(kind)),
        ));
    }
    let mut hasher = blake3::Hasher::new();
    hash_reader(fs::File::open(path)?, meta.len(), &mut hasher)?;
    Ok(hasher.finalize().to_hex().to_string())
}

/// Bytes read per chunk: large enough for BLAKE3's parallel tree hashing
/// to keep every core busy on each chunk.
const CHUNK_BYTES: usize = 8 << 20;

/// Chunks shorter than this are hashed on the calling thread: waking the
/// pool costs more than it saves (BLAKE3's docs put the break-even near
/// 128 KiB).
const PARALLEL_BYTES: usize = 1 << 20;

/// Feeds everything `reader` yields to `hasher`, a chunk at a time, each
/// chunk hashed on all cores (the hash does not depend on the chunking).
/// Plain reads rather than a memory map: mapping faults in every page, and
/// on a sparse file (a 6 GB `.npy` of holes from the fault campaign) that
/// took 18 s where reading takes 2.
fn hash_reader(
    mut reader: impl io::Read,
    len_hint: u64,
    hasher: &mut blake3::Hasher,
) -> io::Result<()> {
    // Sized to the file (one more byte to see its end in one chunk): an
    // 8 MiB zeroed buffer for each small file was most of a cached rerun's
    // time (2 000 stages: 15 s, #50, 4).
    let len = usize::try_from(len_hint).unwrap_or(usize::MAX);
    let mut chunk = vec![0u8; len.saturating_add(1).min(CHUNK_BYTES)];
    loop {
        let mut filled = 0;
        while filled < chunk.len() {
            match reader.read(&mut chunk[filled..]) {
                Ok(0) => break,
                Ok(n) => filled += n,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
        if filled == 0 {
            return Ok(());
        }
        if filled >= PARALLEL_BYTES {
            hasher.update_rayon(&chunk[..filled]);
        } else {
            hasher.update(&chunk[..filled]);
        }
    }
}

/// BLAKE3 of a file, or of a folder's relative paths and file hashes
/// (sorted, recursively), so moving a tree does not change its hash.
pub fn path_hash(path: &Path) -> io::Result<String> {
    if path.is_dir() {
        let mut hasher = blake3::Hasher::new();
        hash_dir(path, Path::new(""), &mut hasher)?;
        Ok(hasher.finalize().to_hex().to_string())
    } else {
        file_hash(path)
    }
}

/// Walks real subfolders; an entry that cannot be hashed is named in the
/// error (`<folder>/tile_003.npy is not a regular file (a pipe)`), not
/// left to be blamed on the folder. A symlink to a folder is refused rather
/// than followed: it may lead back up the tree, and the stages that read a
/// folder's files do not enter subfolders.
fn hash_dir(root: &Path, rel: &Path, hasher: &mut blake3::Hasher) -> io::Result<()> {
    let mut entries: Vec<_> = fs::read_dir(root.join(rel))?.collect::<Result<_, _>>()?;
    entries.sort_by_key(|e| e.file_name());
    for entry in entries {
        let name = rel.join(entry.file_name());
        let path = root.join(&name);
        let named = |e: io::Error| {
            let reason = e.to_string();
            io::Error::new(e.kind(), format!("`{}` {reason}", path.display()))
        };
        let kind = entry.file_type().map_err(named)?;
        if kind.is_dir() {
            hash_dir(root, &name, hasher)?;
        } else if kind.is_symlink() && path.is_dir() {
            return Err(named(io::Error::new(
                io::ErrorKind::InvalidInput,
                "is a symlink to a folder, which is not followed: put the files in the folder \
                 itself",
            )));
        } else {
            let hash = file_hash(&path).map_err(named)?;
            hasher.update(name.to_string_lossy().as_bytes());
            hasher.update(&[0]);
            hasher.update(hash.as_bytes());
            hasher.update(&[0]);
        }
    }
    Ok(())
}

/// JSON with object keys sorted at every level and floats in their shortest
/// round-trip form (serde_json's), so `2.0e-5` and `20e-6`, or two key
/// orders, give the same text.
pub fn canonical_json(value: &serde_json::Value) -> String {
    let mut out = String::new();
    write_canonical(value, &mut out);
    out
}

fn write_canonical(value: &serde_json::Value, out: &mut String) {
    use serde_json::Value;
    match value {
        Value::Object(map) => {
            let mut keys: Vec<&String> = map.keys().collect();
            keys.sort();
            out.push('{');
            for (i, k) in keys.into_iter().enumerate() {
                if i > 0 {
                    out.push(',');
                }
                out.push_str(&Value::String(k.clone()).to_string());
                out.push(':');
                write_canonical(&map[k], out);
            }
            out.push('}');
        }
        Value::Array(items) => {
            out.push('[');
            for (i, v) in items.iter().enumerate() {
                if i > 0 {
                    out.push(',');
                }
                write_canonical(v, out);
            }
            out.push(']');
        }
        Value::Number(n) => match (n.as_i64(), n.as_f64()) {
            // 1000 and 1000.0 are the same number in a parameter.
            (None, Some(f)) if f.fract() == 0.0 && f.abs() < 1e15 => {
                out.push_str(&format!("{}", f as i64))
            }
            _ => out.push_str(&n.to_string()),
        },
        other => out.push_str(&other.to_string()),
    }
}

/// Short hex digest of text.
pub fn text_hash(text: &str) -> String {
    blake3::hash(text.as_bytes()).to_hex()[..32].to_owned()
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// Yields its bytes a few at a time, with an interruption between reads.
    struct Trickle<'a> {
        bytes: &'a [u8],
        interrupt: bool,
    }

    impl io::Read for Trickle<'_> {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            self.interrupt = !self.interrupt;
            if self.interrupt {
                return Err(io::Error::from(io::ErrorKind::Interrupted));
            }
            let n = buf.len().min(self.bytes.len()).min(1 << 19);
            buf[..n].copy_from_slice(&self.bytes[..n]);
            self.bytes = &self.bytes[n..];
            Ok(n)
        }
    }

    #[test]
    fn chunked_hashing_is_blake3_of_the_whole() {
        // Lengths about the chunk size, read in short pieces with interruptions.
        let bytes: Vec<u8> = (0..2 * CHUNK_BYTES + 3)
            .map(|i| (i as u32).wrapping_mul(2_654_435_761).to_le_bytes()[3])
            .collect();
        for len in [
            0,
            1,
            CHUNK_BYTES - 1,
            CHUNK_BYTES,
            CHUNK_BYTES + 1,
            bytes.len(),
        ] {
            // The length hint right, too short (a file that grew since its
            // size was read) and too long.
            for hint in [len as u64, 0, 7, u64::MAX] {
                let mut hasher = blake3::Hasher::new();
                let trickle = Trickle {
                    bytes: &bytes[..len],
                    interrupt: false,
                };
                hash_reader(trickle, hint, &mut hasher).unwrap();
                assert_eq!(
                    hasher.finalize(),
                    blake3::hash(&bytes[..len]),
                    "{len} bytes, hint {hint}"
                );
            }
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f.bin");
        std::fs::write(&path, &bytes).unwrap();
        let expected = blake3::hash(&bytes).to_hex().to_string();
        assert_eq!(file_hash(&path).unwrap(), expected);
    }

    #[test]
    fn devices_are_refused_not_read() {
        for path in ["/dev/zero", "/dev/null"] {
            let e = path_hash(Path::new(path)).unwrap_err();
            assert_eq!(e.kind(), io::ErrorKind::InvalidInput, "{path}");
            assert!(e.to_string().contains("not a regular file"), "{e}");
        }
    }

    // Before, each of these failed as "cannot read `<folder>`" with a
    // cause that did not say which entry.
    #[test]
    fn a_folder_names_the_entry_it_cannot_hash() {
        let bad: [(&str, MakeEntry, &str); 4] = [
            ("tile_003.npy", make_fifo, "is not a regular file (a pipe)"),
            (
                "zero.npy",
                |p| std::os::unix::fs::symlink("/dev/zero", p).is_ok(),
                "character device",
            ),
            (
                "loop.npy",
                |p| std::os::unix::fs::symlink(p, p).is_ok(),
                "is a symlink loop",
            ),
            (
                "linked",
                |p| std::os::unix::fs::symlink("/tmp", p).is_ok(),
                "symlink to a folder, which is not followed",
            ),
        ];
        for (name, make, says) in bad {
            let t = tempfile::tempdir().unwrap();
            std::fs::write(t.path().join("a.npy"), "x").unwrap();
            let entry = t.path().join(name);
            assert!(make(&entry), "{name}");
            let e = path_hash(t.path()).unwrap_err().to_string();
            let shown = format!("`{}`", entry.display());
            assert!(e.starts_with(&shown) && e.contains(says), "{name}: {e}");
        }
    }

    /// Makes one odd folder entry; whether it could.
    type MakeEntry = fn(&Path) -> bool;

    fn make_fifo(path: &Path) -> bool {
        std::process::Command::new("mkfifo")
            .arg(path)
            .status()
            .is_ok_and(|s| s.success())
    }

    #[test]
    fn canonical_json_ignores_key_order_and_float_spelling() {
        let a: serde_json::Value =
            serde_json::from_str(r#"{"b": 2.0e-5, "a": {"y": 1, "x": 1000.0}}"#).unwrap();
        let b: serde_json::Value =
            serde_json::from_str(r#"{"a": {"x": 1000, "y": 1}, "b": 20e-6}"#).unwrap();
        assert_eq!(canonical_json(&a), canonical_json(&b));
        assert_ne!(
            canonical_json(&a),
            canonical_json(&json!({"a": {"x": 1001, "y": 1}, "b": 2e-5}))
        );
    }

    #[test]
    fn folder_hash_follows_content_not_location() {
        let t = tempfile::tempdir().unwrap();
        for root in ["one", "two"] {
            std::fs::create_dir_all(t.path().join(root).join("sub")).unwrap();
            std::fs::write(t.path().join(root).join("sub/a.txt"), "x").unwrap();
        }
        let one = path_hash(&t.path().join("one")).unwrap();
        assert_eq!(one, path_hash(&t.path().join("two")).unwrap());
        std::fs::write(t.path().join("two/sub/a.txt"), "y").unwrap();
        assert_ne!(one, path_hash(&t.path().join("two")).unwrap());
    }
}
