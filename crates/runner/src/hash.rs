//! Content hashes and canonical JSON: the ingredients of a cache key.

use std::fs;
use std::io;
use std::path::Path;

/// BLAKE3 of a file's bytes, hex. Anything but a regular file (a device
/// such as `/dev/zero`, a pipe) is refused: reading one may never end.
pub fn file_hash(path: &Path) -> io::Result<String> {
    if !fs::metadata(path)?.is_file() {
        return Err(not_regular());
    }
    let mut hasher = blake3::Hasher::new();
    hasher.update_mmap_rayon(path)?;
    Ok(hasher.finalize().to_hex().to_string())
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

/// The error for a path that is neither a regular file nor a folder.
pub fn not_regular() -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        "not a regular file or folder (a device or a pipe cannot be read to its end)",
    )
}

fn hash_dir(root: &Path, rel: &Path, hasher: &mut blake3::Hasher) -> io::Result<()> {
    let mut entries: Vec<_> = fs::read_dir(root.join(rel))?.collect::<Result<_, _>>()?;
    entries.sort_by_key(|e| e.file_name());
    for entry in entries {
        let name = rel.join(entry.file_name());
        if entry.file_type()?.is_dir() {
            hash_dir(root, &name, hasher)?;
        } else {
            hasher.update(name.to_string_lossy().as_bytes());
            hasher.update(&[0]);
            hasher.update(file_hash(&root.join(&name))?.as_bytes());
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

    #[test]
    fn devices_are_refused_not_read() {
        for path in ["/dev/zero", "/dev/null"] {
            let e = path_hash(Path::new(path)).unwrap_err();
            assert_eq!(e.kind(), io::ErrorKind::InvalidInput, "{path}");
            assert!(e.to_string().contains("not a regular file"), "{e}");
        }
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
