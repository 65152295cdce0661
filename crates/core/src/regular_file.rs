//! The one check before any reader opens a file a user named: it must be a
//! regular file. A folder, a device such as `/dev/zero` or a pipe is refused,
//! because reading one may never end (and `/dev/zero` never runs out of
//! memory to fill). Field reading here, and every lab-file and table reader,
//! goes through it, so the refusal reads the same everywhere.

use std::path::Path;

use crate::StageError;

/// The bytes of a file a stage reads, refused before reading unless it is a
/// regular file ([`check_regular_file`]).
pub fn read_regular_file(path: &Path) -> Result<Vec<u8>, StageError> {
    check_regular_file(path)?;
    std::fs::read(path).map_err(|e| StageError::file(path, e.to_string()))
}

/// Refuses anything but a regular file before a reader opens it: a folder,
/// a device such as `/dev/zero`, a pipe.
pub fn check_regular_file(path: &Path) -> Result<(), StageError> {
    let meta = std::fs::metadata(path).map_err(|e| StageError::file(path, e.to_string()))?;
    if !meta.is_file() {
        return Err(StageError::file(
            path,
            "is not a regular file (a folder, a device or a pipe)",
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folders_and_missing_files_are_named_not_read() {
        let dir = std::env::temp_dir();
        let e = read_regular_file(&dir).unwrap_err().to_string();
        assert!(e.contains("not a regular file"), "{e}");
        let missing = dir.join(format!("hc-missing-{}.npy", std::process::id()));
        let e = check_regular_file(&missing).unwrap_err().to_string();
        assert!(e.starts_with(&missing.display().to_string()), "{e}");
    }
}
