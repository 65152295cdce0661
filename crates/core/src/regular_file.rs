//! The one check before any reader opens a file a user named: it must be a
//! regular file, and a file the command line reads (a pipeline, a Slurm
//! profile, a job file, a run's provenance) must also be no larger than a
//! limit fitting what it holds. A folder, a device such as `/dev/zero` or a
//! pipe is refused before it is opened: opening a pipe blocks until a writer
//! comes, and reading `/dev/zero` never ends (it fills memory). Field
//! reading, every lab-file and table reader and every file the CLI reads go
//! through here, so the refusal reads the same everywhere.

use std::fs::{self, Metadata};
use std::io::{self, Read};
use std::path::{Path, PathBuf};

use crate::StageError;

/// One mebibyte, for limits.
pub const MIB: u64 = 1 << 20;

/// Why a checked read failed: `why` without the path, for callers that put
/// the path where their own messages have it; the whole as `path: why`.
#[derive(Debug, thiserror::Error)]
#[error("{}: {why}", path.display())]
pub struct CheckedReadError {
    pub path: PathBuf,
    pub why: String,
    /// The file is simply not there (callers that treat a missing file as
    /// "none yet" ask).
    pub not_found: bool,
}

impl CheckedReadError {
    fn new(path: &Path, why: impl Into<String>) -> Self {
        Self {
            path: path.to_owned(),
            why: why.into(),
            not_found: false,
        }
    }

    /// Every `why` reads after the file's name: "is …", "does not exist",
    /// "cannot be read: …".
    fn io(path: &Path, e: &io::Error) -> Self {
        let not_found = e.kind() == io::ErrorKind::NotFound;
        Self {
            path: path.to_owned(),
            why: match (not_found, is_symlink_loop(e)) {
                (true, _) => "does not exist".to_owned(),
                (_, true) => "is a symlink loop".to_owned(),
                _ => format!("cannot be read: {e}"),
            },
            not_found,
        }
    }
}

/// The bytes of a regular file of at most `limit_bytes`; `what` names the
/// kind of file, plural, in the refusal ("pipeline files are at most
/// 16 MiB"). Anything but a regular file is refused before it is opened;
/// the read stops one byte past the limit, so a file that grows after the
/// check, or whose stated size lies (files under `/proc`), cannot take more.
pub fn read_checked(
    path: &Path,
    what: &str,
    limit_bytes: u64,
) -> Result<Vec<u8>, CheckedReadError> {
    let meta = regular_metadata(path)?;
    let too_large = |size: String| {
        CheckedReadError::new(
            path,
            format!("is {size}; {what} are at most {}", in_words(limit_bytes)),
        )
    };
    if meta.len() > limit_bytes {
        return Err(too_large(in_words(meta.len())));
    }
    let file = fs::File::open(path).map_err(|e| CheckedReadError::io(path, &e))?;
    // Swapped for a device or a folder between the check and the open.
    let opened = file
        .metadata()
        .map_err(|e| CheckedReadError::io(path, &e))?;
    if let Some(kind) = not_regular_kind(&opened) {
        return Err(CheckedReadError::new(
            path,
            format!("is {}", not_regular(kind)),
        ));
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(limit_bytes + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| CheckedReadError::io(path, &e))?;
    if bytes.len() as u64 > limit_bytes {
        return Err(too_large(format!(
            "more than {} (it grew while read)",
            in_words(limit_bytes)
        )));
    }
    Ok(bytes)
}

/// [`read_checked`] for a text file.
pub fn read_checked_text(
    path: &Path,
    what: &str,
    limit_bytes: u64,
) -> Result<String, CheckedReadError> {
    String::from_utf8(read_checked(path, what, limit_bytes)?)
        .map_err(|e| CheckedReadError::new(path, format!("is not UTF-8 text ({e})")))
}

/// The metadata of `path`, symlinks followed, if it is a regular file;
/// otherwise why not, a symlink loop named as one.
fn regular_metadata(path: &Path) -> Result<Metadata, CheckedReadError> {
    let meta = fs::metadata(path).map_err(|e| CheckedReadError::io(path, &e))?;
    match not_regular_kind(&meta) {
        None => Ok(meta),
        Some(kind) => Err(CheckedReadError::new(
            path,
            format!("is {}", not_regular(kind)),
        )),
    }
}

/// Whether an error is ELOOP, a symlink that leads back to itself
/// (`io::ErrorKind::FilesystemLoop` is not matched on stable Rust).
pub fn is_symlink_loop(e: &io::Error) -> bool {
    #[cfg(target_os = "linux")]
    const ELOOP: i32 = 40;
    #[cfg(not(target_os = "linux"))]
    const ELOOP: i32 = 62; // macOS and the BSDs
    e.raw_os_error() == Some(ELOOP)
}

/// What a file is when it is not a regular one ("a pipe", "a folder"),
/// from its metadata (symlinks followed); `None` for a regular file.
pub fn not_regular_kind(meta: &Metadata) -> Option<&'static str> {
    use std::os::unix::fs::FileTypeExt;
    let t = meta.file_type();
    match () {
        _ if t.is_file() => None,
        _ if t.is_dir() => Some("a folder"),
        _ if t.is_fifo() => Some("a pipe"),
        _ if t.is_char_device() => Some("a character device"),
        _ if t.is_block_device() => Some("a block device"),
        _ if t.is_socket() => Some("a socket"),
        _ => Some("not a file"),
    }
}

/// "not a regular file (a pipe)".
pub fn not_regular(kind: &str) -> String {
    format!("not a regular file ({kind})")
}

/// `16 MiB`, `3.0 GiB`, `312 bytes`.
fn in_words(bytes: u64) -> String {
    match bytes {
        b if b >= 1 << 30 => format!("{:.1} GiB", b as f64 / (1u64 << 30) as f64),
        b if b >= MIB && b % MIB == 0 => format!("{} MiB", b / MIB),
        b if b >= MIB => format!("{:.1} MiB", b as f64 / MIB as f64),
        b if b >= 1 << 10 => format!("{:.1} KiB", b as f64 / 1024.0),
        b => format!("{b} bytes"),
    }
}

/// The bytes of a file a stage reads, refused before reading unless it is a
/// regular file ([`check_regular_file`]).
pub fn read_regular_file(path: &Path) -> Result<Vec<u8>, StageError> {
    check_regular_file(path)?;
    fs::read(path).map_err(|e| StageError::file(path, e.to_string()))
}

/// Refuses anything but a regular file before a reader opens it: a folder,
/// a device such as `/dev/zero`, a pipe, a symlink loop; the message says
/// which.
pub fn check_regular_file(path: &Path) -> Result<(), StageError> {
    let meta = fs::metadata(path).map_err(|e| match is_symlink_loop(&e) {
        true => StageError::file(path, "is a symlink loop"),
        // The system's words, as every stage reader has always said them.
        false => StageError::file(path, e.to_string()),
    })?;
    match not_regular_kind(&meta) {
        None => Ok(()),
        Some(kind) => Err(StageError::file(path, format!("is {}", not_regular(kind)))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folders_and_missing_files_are_named_not_read() {
        let dir = std::env::temp_dir();
        let e = read_regular_file(&dir).unwrap_err().to_string();
        assert!(e.contains("is not a regular file (a folder)"), "{e}");
        let missing = dir.join(format!("hc-missing-{}.npy", std::process::id()));
        let e = check_regular_file(&missing).unwrap_err().to_string();
        assert!(e.starts_with(&missing.display().to_string()), "{e}");
        assert!(
            read_checked(&missing, "test files", 8)
                .unwrap_err()
                .not_found
        );
    }

    /// Each of these would hang (the pipe) or fill memory (`/dev/zero`) if
    /// it were opened and read; each is named for what it is.
    #[test]
    fn pipes_devices_and_symlink_loops_are_refused_before_opening() {
        let t = scratch("odd");
        let fifo = t.join("fifo");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        assert!(made.is_ok_and(|s| s.success()), "mkfifo");
        std::os::unix::fs::symlink("/dev/zero", t.join("zero")).unwrap();
        std::os::unix::fs::symlink(t.join("loop"), t.join("loop")).unwrap();
        std::os::unix::fs::symlink(&t, t.join("folder")).unwrap();
        for (name, says) in [
            ("fifo", "is not a regular file (a pipe)"),
            ("zero", "is not a regular file (a character device)"),
            ("loop", "is a symlink loop"),
            ("folder", "is not a regular file (a folder)"),
        ] {
            let e = read_checked(&t.join(name), "test files", 8).unwrap_err();
            assert!(e.why.starts_with(says), "{name}: {e}");
            assert!(
                e.to_string()
                    .starts_with(&t.join(name).display().to_string())
            );
        }
        fs::remove_dir_all(t).unwrap();
    }

    #[test]
    fn files_over_the_limit_are_refused_with_the_limit_named() {
        let t = scratch("limit");
        let path = t.join("f");
        fs::write(&path, b"12345678").unwrap();
        assert_eq!(read_checked(&path, "test files", 8).unwrap(), b"12345678");
        fs::write(&path, b"123456789").unwrap();
        let e = read_checked(&path, "test files", 8).unwrap_err();
        assert_eq!(e.why, "is 9 bytes; test files are at most 8 bytes");
        // A sparse file: its size, not its blocks, is what a read would take.
        let sparse = fs::File::create(&path).unwrap();
        sparse.set_len(3 << 30).unwrap();
        let e = read_checked(&path, "pipeline files", 16 * MIB).unwrap_err();
        assert_eq!(e.why, "is 3.0 GiB; pipeline files are at most 16 MiB");
        fs::write(&path, [0xff, 0xfe]).unwrap();
        let e = read_checked_text(&path, "test files", 8).unwrap_err();
        assert!(e.why.starts_with("is not UTF-8 text"), "{e}");
        fs::remove_dir_all(t).unwrap();
    }

    fn scratch(tag: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("hc-regular-{tag}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }
}
