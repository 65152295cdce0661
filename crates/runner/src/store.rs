//! Products on disk: a table is `<name>.parquet`, a field `<name>.npy` with
//! its grid in `<name>.grid.json`, and files live under `<name>/`.

use std::collections::BTreeMap;
use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use hypercontact_core::{ColumnSpec, Field, Files, Product, ProductKind};
use serde::{Deserialize, Serialize};

/// A file of a stored product with its checksum.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FileRecord {
    pub blake3: String,
    pub bytes: u64,
}

/// A stored product: its kind and its files (paths relative to the entry).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OutputRecord {
    pub kind: ProductKind,
    pub files: BTreeMap<String, FileRecord>,
}

#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    // The cause is in the message, so not also `source()` (printed twice).
    #[error("{}: {cause}", path.display())]
    Io { path: PathBuf, cause: io::Error },
    #[error("{}: {message}", path.display())]
    Format { path: PathBuf, message: String },
}

fn io_err(path: &Path) -> impl FnOnce(io::Error) -> StoreError + '_ {
    move |cause| StoreError::Io {
        path: path.to_owned(),
        cause,
    }
}

/// Writes a file and returns its record (hashed while written).
fn write_file(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> Result<(), String>,
) -> Result<FileRecord, StoreError> {
    if let Some(parent) = path.parent() {
        fs::create_dir_all(parent).map_err(io_err(parent))?;
    }
    struct Tee<W> {
        inner: W,
        hasher: blake3::Hasher,
        bytes: u64,
    }
    impl<W: Write> Write for Tee<W> {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            let n = self.inner.write(buf)?;
            self.hasher.update(&buf[..n]);
            self.bytes += n as u64;
            Ok(n)
        }
        fn flush(&mut self) -> io::Result<()> {
            self.inner.flush()
        }
    }
    let file = fs::File::create(path).map_err(io_err(path))?;
    let mut tee = Tee {
        inner: BufWriter::new(file),
        hasher: blake3::Hasher::new(),
        bytes: 0,
    };
    write(&mut tee).map_err(|message| StoreError::Format {
        path: path.to_owned(),
        message,
    })?;
    tee.flush().map_err(io_err(path))?;
    Ok(FileRecord {
        blake3: tee.hasher.finalize().to_hex().to_string(),
        bytes: tee.bytes,
    })
}

/// Writes one product into `dir`; `after_file` is called after each file
/// (tests use it to simulate a crash mid-write). `columns` is the output's
/// declaration (`OutputSpec::columns`): a table, or the index of files,
/// carries each declared column's unit and description in its Parquet file.
pub fn write_product(
    dir: &Path,
    name: &str,
    product: &Product,
    columns: &[ColumnSpec],
    after_file: &mut dyn FnMut(&Path),
) -> Result<OutputRecord, StoreError> {
    let mut files = BTreeMap::new();
    let mut put = |rel: String, write: &mut dyn FnMut(&mut dyn Write) -> Result<(), String>| {
        let path = dir.join(&rel);
        let record = write_file(&path, |w| write(w))?;
        after_file(&path);
        files.insert(rel, record);
        Ok::<_, StoreError>(())
    };
    match product {
        Product::Table(table) => put(format!("{name}.parquet"), &mut |w| {
            hypercontact_io::write_parquet_described(table, columns, w).map_err(|e| e.to_string())
        })?,
        Product::Field(field) => {
            put(format!("{name}.npy"), &mut |w| {
                field.write_npy(w).map_err(|e| e.to_string())
            })?;
            put(format!("{name}.grid.json"), &mut |w| {
                w.write_all(&field.grid_json()).map_err(|e| e.to_string())
            })?;
        }
        Product::Files(set) => {
            for (file, bytes) in &set.files {
                if file.contains("..") || file.starts_with('/') || file.is_empty() {
                    return Err(StoreError::Format {
                        path: dir.join(name),
                        message: format!("output file name `{file}` is not a plain relative path"),
                    });
                }
                put(format!("{name}/{file}"), &mut |w| {
                    w.write_all(bytes).map_err(|e| e.to_string())
                })?;
            }
            if let Some(index) = &set.index {
                put(index_name(name), &mut |w| {
                    hypercontact_io::write_parquet_described(index, columns, w)
                        .map_err(|e| e.to_string())
                })?;
            }
        }
    }
    Ok(OutputRecord {
        kind: product.kind(),
        files,
    })
}

/// Reads a product back from `dir`.
pub fn read_product(dir: &Path, name: &str, record: &OutputRecord) -> Result<Product, StoreError> {
    match record.kind {
        ProductKind::Table => Ok(Product::Table(read_table(
            &dir.join(format!("{name}.parquet")),
        )?)),
        ProductKind::Field => Ok(Product::Field(read_field(
            &dir.join(format!("{name}.npy")),
            &dir.join(format!("{name}.grid.json")),
        )?)),
        ProductKind::Files => {
            let mut set = Files::new();
            let prefix = format!("{name}/");
            let index = index_name(name);
            for rel in record.files.keys() {
                let path = dir.join(rel);
                if *rel == index {
                    set.index = Some(read_table(&path)?);
                    continue;
                }
                let bytes = fs::read(&path).map_err(io_err(&path))?;
                let file = rel.strip_prefix(&prefix).unwrap_or(rel);
                set.files.insert(file.to_owned(), bytes);
            }
            Ok(Product::Files(set))
        }
    }
}

/// A field as stored and exported: `.npy` values beside their `.grid.json`.
pub fn read_field(npy: &Path, grid: &Path) -> Result<Field, StoreError> {
    let grid_bytes = fs::read(grid).map_err(io_err(grid))?;
    let file = fs::File::open(npy).map_err(io_err(npy))?;
    Field::read_with_grid(io::BufReader::new(file), &grid_bytes).map_err(|e| StoreError::Format {
        path: npy.to_owned(),
        message: e.to_string(),
    })
}

/// Where the index of files output `name` is stored (and exported, beside
/// the files): the table `<name>.parquet`.
fn index_name(name: &str) -> String {
    format!("{name}.parquet")
}

fn read_table(path: &Path) -> Result<hypercontact_core::Table, StoreError> {
    let file = fs::File::open(path).map_err(io_err(path))?;
    hypercontact_io::read_parquet(file).map_err(|e| StoreError::Format {
        path: path.to_owned(),
        message: e.to_string(),
    })
}

/// Where a stored file lands in a run's output folder: tables and fields
/// keep their names, files drop the output-name prefix.
pub fn export_name(output: &str, record: &OutputRecord, rel: &str) -> String {
    match record.kind {
        ProductKind::Files => rel
            .strip_prefix(&format!("{output}/"))
            .unwrap_or(rel)
            .to_owned(),
        _ => rel.to_owned(),
    }
}

/// Places a copy of `src` at `dst` atomically: copy to a temporary name
/// beside `dst`, then rename over it.
///
/// A copy, never a hard link: a linked output shares its inode with the
/// cache entry and every other run's output, so appending to one (as root,
/// past the read-only mode) changed them all (#31, 3). `fs::copy` asks the
/// kernel to clone where the filesystem can (`copy_file_range` on Linux,
/// which Btrfs and XFS answer with a reflink; `fclonefileat` on macOS), so
/// there the copy shares blocks copy-on-write and costs no space; elsewhere
/// it writes the bytes. The copy is made writable by its owner: it is the
/// run's own file now, and nothing else sees a change to it.
pub fn place(src: &Path, dst: &Path) -> Result<(), StoreError> {
    if let Some(parent) = dst.parent() {
        fs::create_dir_all(parent).map_err(io_err(parent))?;
    }
    let tmp = dst.with_file_name(format!(
        ".{}.{}.tmp",
        dst.file_name()
            .map(|n| n.to_string_lossy())
            .unwrap_or_default(),
        std::process::id()
    ));
    let _ = fs::remove_file(&tmp);
    fs::copy(src, &tmp).map_err(io_err(&tmp))?;
    let mut permissions = fs::metadata(&tmp).map_err(io_err(&tmp))?.permissions();
    owner_writable(&mut permissions);
    fs::set_permissions(&tmp, permissions).map_err(io_err(&tmp))?;
    fs::rename(&tmp, dst).map_err(io_err(dst))
}

/// [`place`], unless `dst` already is a file of its own (one name, not a
/// link) holding the bytes `record` describes: the export of an unchanged
/// entry then writes nothing. A rename over an existing file makes ext4
/// flush it, so 2 000 cached stages took 17 s to rerun, all of it placing
/// the same bytes again (#50, 4). A file edited since, or a hard link an
/// older build left ([`place`]'s doc), is replaced as before.
pub fn place_unless_held(src: &Path, dst: &Path, record: &FileRecord) -> Result<(), StoreError> {
    if holds(dst, record) {
        return Ok(());
    }
    place(src, dst)
}

/// Whether `path` is a regular file of one link with `record`'s size and
/// hash.
fn holds(path: &Path, record: &FileRecord) -> bool {
    let Ok(meta) = fs::symlink_metadata(path) else {
        return false;
    };
    meta.is_file()
        && meta.len() == record.bytes
        && one_link(&meta)
        && crate::hash::file_hash(path).is_ok_and(|h| h == record.blake3)
}

#[cfg(unix)]
fn one_link(meta: &fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    meta.nlink() == 1
}

/// Links are not counted here: every export is placed anew.
#[cfg(not(unix))]
fn one_link(_: &fs::Metadata) -> bool {
    false
}

#[cfg(unix)]
fn owner_writable(permissions: &mut fs::Permissions) {
    use std::os::unix::fs::PermissionsExt;
    permissions.set_mode(permissions.mode() | 0o200);
}

#[cfg(not(unix))]
fn owner_writable(permissions: &mut fs::Permissions) {
    permissions.set_readonly(false);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The message with its `source()` chain, as the CLI prints it (`{:#}`).
    fn chain(e: &dyn std::error::Error) -> String {
        let mut text = e.to_string();
        let mut next = e.source();
        while let Some(cause) = next {
            text.push_str(&format!(": {cause}"));
            next = cause.source();
        }
        text
    }

    const INDEX_COLUMNS: [ColumnSpec; 2] = [
        ColumnSpec::str("file", "which file"),
        ColumnSpec::f64("area_fraction", "", "contact area over nominal area"),
    ];

    #[test]
    fn files_come_back_with_their_index_stored_as_a_table_beside_them() {
        let t = tempfile::tempdir().unwrap();
        let index = hypercontact_core::Table::new()
            .with("file", vec!["a.png", "b.png"])
            .with("area_fraction", vec![0.1, f64::NAN]);
        let files = Files::new()
            .with("a.png", vec![1, 2])
            .with("b.png", vec![3]);
        for product in [
            Product::Files(files.clone()),
            Product::Files(Files {
                index: Some(index),
                ..files
            }),
        ] {
            let record =
                write_product(t.path(), "maps", &product, &INDEX_COLUMNS, &mut |_| {}).unwrap();
            let names: Vec<&str> = record.files.keys().map(String::as_str).collect();
            let Product::Files(set) = &product else {
                unreachable!()
            };
            if set.index.is_some() {
                assert_eq!(names, ["maps.parquet", "maps/a.png", "maps/b.png"]);
                assert_eq!(export_name("maps", &record, "maps.parquet"), "maps.parquet");
            } else {
                assert_eq!(names, ["maps/a.png", "maps/b.png"]);
            }
            let back = read_product(t.path(), "maps", &record).unwrap();
            let (Product::Files(a), Product::Files(b)) = (&back, &product) else {
                panic!("files come back as files")
            };
            assert_eq!(a.files, b.files);
            assert_eq!(a.index.is_some(), b.index.is_some());
            if set.index.is_some() {
                let file = fs::File::open(t.path().join("maps.parquet")).unwrap();
                let meta = hypercontact_io::parquet_columns_meta(file).unwrap();
                let expected: Vec<_> = INDEX_COLUMNS
                    .iter()
                    .map(hypercontact_io::ColumnMeta::from)
                    .collect();
                assert_eq!(meta, expected, "the index carries its declaration");
            }
            if let (Some(x), Some(y)) = (&a.index, &b.index) {
                assert_eq!(x.str("file").unwrap(), y.str("file").unwrap());
                assert_eq!(x.f64("area_fraction").unwrap()[0], 0.1);
                assert!(x.f64("area_fraction").unwrap()[1].is_nan());
            }
        }
    }

    #[test]
    fn an_io_error_is_printed_once() {
        // Issue 12: "ro/surf: Permission denied (os error 13): Permission
        // denied (os error 13)".
        let e = io_err(Path::new("ro/surf"))(io::Error::from(io::ErrorKind::PermissionDenied));
        let text = chain(&e);
        assert_eq!(text.matches("denied").count(), 1, "{text}");
        assert!(text.starts_with("ro/surf: "), "{text}");
    }

    fn record_of(path: &Path) -> FileRecord {
        FileRecord {
            blake3: crate::hash::file_hash(path).unwrap(),
            bytes: fs::metadata(path).unwrap().len(),
        }
    }

    #[cfg(unix)]
    #[test]
    fn an_export_holding_the_entry_bytes_is_left_and_any_other_is_replaced() {
        use std::os::unix::fs::MetadataExt;
        let t = tempfile::tempdir().unwrap();
        let cached = t.path().join("cache.bin");
        let out = t.path().join("run/out.bin");
        fs::write(&cached, b"product").unwrap();
        let record = record_of(&cached);
        place_unless_held(&cached, &out, &record).unwrap();
        assert_eq!(fs::read(&out).unwrap(), b"product");
        // Held: the same inode stays (no copy, no rename).
        let inode = fs::metadata(&out).unwrap().ino();
        place_unless_held(&cached, &out, &record).unwrap();
        assert_eq!(fs::metadata(&out).unwrap().ino(), inode);
        // Edited to other bytes of the same length: replaced.
        fs::write(&out, b"PRODUCT").unwrap();
        place_unless_held(&cached, &out, &record).unwrap();
        assert_eq!(fs::read(&out).unwrap(), b"product");
        // A hard link to the cached file holds its bytes but is replaced.
        fs::remove_file(&out).unwrap();
        fs::hard_link(&cached, &out).unwrap();
        place_unless_held(&cached, &out, &record).unwrap();
        assert_eq!(fs::metadata(&cached).unwrap().nlink(), 1);
        // A symlink to it too.
        fs::remove_file(&out).unwrap();
        std::os::unix::fs::symlink(&cached, &out).unwrap();
        place_unless_held(&cached, &out, &record).unwrap();
        assert!(fs::symlink_metadata(&out).unwrap().is_file());
        assert_eq!(fs::read(&out).unwrap(), b"product");
    }

    #[test]
    fn an_output_exported_by_an_older_build_as_a_hard_link_becomes_its_own_copy() {
        // #31, 3: a run folder exported before by hard link is unlinked
        // from the cache on the next export; failed before (place kept the
        // link, `same_file`), an append then reached the cached file.
        let t = tempfile::tempdir().unwrap();
        let cached = t.path().join("cache.bin");
        let out = t.path().join("run/out.bin");
        fs::write(&cached, b"product").unwrap();
        fs::create_dir_all(out.parent().unwrap()).unwrap();
        fs::hard_link(&cached, &out).unwrap();
        place(&cached, &out).unwrap();
        fs::File::options()
            .append(true)
            .open(&out)
            .unwrap()
            .write_all(b" edited")
            .unwrap();
        assert_eq!(fs::read(&cached).unwrap(), b"product");
        assert_eq!(fs::read(&out).unwrap(), b"product edited");
        let names: Vec<_> = fs::read_dir(out.parent().unwrap()).unwrap().collect();
        assert_eq!(names.len(), 1, "no temporary file left beside the output");
    }
}
