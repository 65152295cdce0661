//! Where a stage's raw files come from: a `Files` product (the synthetic
//! lab's) or a folder of real data, read alike. One implementation, so the
//! stages that read tile sets and image sequences name files the same way in
//! every error.

use std::borrow::Cow;
use std::path::{Path, PathBuf};

use crate::csv_table::CsvTable;
use hypercontact_core::regular_file::{
    is_symlink_loop, not_regular, not_regular_kind, read_checked, read_regular_file,
};
use hypercontact_core::{Files, InputPath, Inputs, StageError, Table};

/// Whether `name` stays inside the folder it is joined to: relative, no
/// `..` (the lab's own index files name frames and tiles; they must not
/// reach elsewhere on the disk).
fn inside(name: &str) -> bool {
    let path = Path::new(name);
    !name.is_empty()
        && path.components().all(|c| {
            matches!(
                c,
                std::path::Component::Normal(_) | std::path::Component::CurDir
            )
        })
}

/// Whether a folder entry is one of its files (`true`), a real subfolder,
/// which is not entered (`false`), or something refused by its name.
fn listed(entry: &std::fs::DirEntry) -> Result<bool, StageError> {
    let path = entry.path();
    let own = entry
        .file_type()
        .map_err(|e| StageError::file(&path, e.to_string()))?;
    if own.is_dir() {
        return Ok(false);
    }
    let meta = std::fs::metadata(&path).map_err(|e| match is_symlink_loop(&e) {
        true => StageError::file(&path, "is a symlink loop"),
        false => StageError::file(&path, e.to_string()),
    })?;
    match not_regular_kind(&meta) {
        None => Ok(true),
        Some(_) if meta.is_dir() => Err(StageError::file(
            &path,
            "is a symlink to a folder, which is not followed: put the files in the folder itself",
        )),
        Some(kind) => Err(StageError::file(&path, format!("is {}", not_regular(kind)))),
    }
}

/// A set of named files.
#[derive(Clone, Debug)]
pub enum FileSource<'a> {
    /// A `Files` product, bound to input `input`.
    Files { files: &'a Files, input: String },
    /// A folder on disk.
    Dir(PathBuf),
}

impl<'a> FileSource<'a> {
    /// Exactly one of the `Files` input `input` or the folder parameter
    /// `dir_param` (its value `dir`); anything else is an error naming both.
    pub fn input_or_dir(
        inputs: &'a Inputs,
        input: &str,
        dir_param: &str,
        dir: Option<&InputPath>,
    ) -> Result<Self, StageError> {
        match (inputs.get(input).is_some(), dir) {
            (true, Some(_)) => Err(StageError::invalid(format!(
                "give either the `{input}` input or the parameter `{dir_param}`, not both"
            ))),
            (false, None) => Err(StageError::invalid(format!(
                "no files: connect the `{input}` input or set the parameter `{dir_param}`"
            ))),
            (true, None) => Ok(FileSource::Files {
                files: inputs.files(input)?,
                input: input.to_owned(),
            }),
            (false, Some(dir)) => Ok(FileSource::Dir(dir.path().to_owned())),
        }
    }

    /// How errors name file `name`: `input `tiles`/positions.csv` or its path.
    pub fn display(&self, name: &str) -> String {
        match self {
            FileSource::Files { input, .. } => format!("input `{input}`/{name}"),
            FileSource::Dir(dir) => dir.join(name).display().to_string(),
        }
    }

    pub fn exists(&self, name: &str) -> bool {
        match self {
            FileSource::Files { files, .. } => files.files.contains_key(name),
            FileSource::Dir(dir) => inside(name) && dir.join(name).is_file(),
        }
    }

    /// The bytes of file `name`; a missing file is an error naming it.
    pub fn read(&self, name: &str) -> Result<Cow<'a, [u8]>, StageError> {
        match self {
            FileSource::Files { files, .. } => files
                .files
                .get(name)
                .map(|b| Cow::Borrowed(b.as_slice()))
                .ok_or_else(|| StageError::file(self.display(name), "no such file in the input")),
            FileSource::Dir(dir) if !inside(name) => Err(StageError::file(
                self.display(name),
                "lies outside the folder: names in a folder's files (frames.csv, \
                 positions.csv) must be relative paths without `..`",
            )),
            FileSource::Dir(dir) => read_regular_file(&dir.join(name)).map(Cow::Owned),
        }
    }

    /// [`FileSource::read`], refusing a file larger than `limit_bytes`
    /// before it is read (a folder's file by its size on disk); `what`
    /// names such files, plural, in the refusal ("X3P tiles of at most …").
    pub fn read_at_most(
        &self,
        name: &str,
        what: &str,
        limit_bytes: u64,
    ) -> Result<Cow<'a, [u8]>, StageError> {
        match self {
            FileSource::Dir(dir) if inside(name) => {
                read_checked(&dir.join(name), what, limit_bytes)
                    .map(Cow::Owned)
                    .map_err(|e| StageError::file(&e.path, e.why))
            }
            _ => {
                let bytes = self.read(name)?;
                match bytes.len() as u64 > limit_bytes {
                    true => Err(StageError::file(
                        self.display(name),
                        format!("is {} bytes; {what} are at most {limit_bytes}", bytes.len()),
                    )),
                    false => Ok(bytes),
                }
            }
        }
    }

    /// A CSV file of the source as a table (the one CSV reader,
    /// [`crate::csv_table`]).
    pub fn read_csv(&self, name: &str) -> Result<Table, StageError> {
        self.read_csv_with_lines(name).map(|csv| csv.table)
    }

    /// [`FileSource::read_csv`] with the file line of every row.
    pub fn read_csv_with_lines(&self, name: &str) -> Result<CsvTable, StageError> {
        crate::csv_table::read_csv_bytes_with_lines(&self.read(name)?, &self.display(name))
    }

    /// The file names, sorted (files directly in a folder; subfolders are
    /// not entered). An entry that is neither is refused by its own name,
    /// not skipped: a pipe, a device, a symlink loop, or a symlink to a
    /// folder (not followed, as subfolders are not entered).
    pub fn names(&self) -> Result<Vec<String>, StageError> {
        match self {
            FileSource::Files { files, .. } => Ok(files.files.keys().cloned().collect()),
            FileSource::Dir(dir) => {
                let entries = std::fs::read_dir(dir)
                    .map_err(|e| StageError::file(dir.as_path(), e.to_string()))?;
                let mut names = Vec::new();
                for entry in entries {
                    let entry =
                        entry.map_err(|e| StageError::file(dir.as_path(), e.to_string()))?;
                    if listed(&entry)? {
                        names.push(entry.file_name().to_string_lossy().into_owned());
                    }
                }
                names.sort();
                Ok(names)
            }
        }
    }

    /// The folder, when the source is one.
    pub fn dir(&self) -> Option<&Path> {
        match self {
            FileSource::Dir(dir) => Some(dir),
            FileSource::Files { .. } => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::Product;

    #[test]
    fn files_and_folders_read_alike_and_name_their_files() {
        let files = Files::new()
            .with("b.csv", b"x,y\n1,2.5\n".to_vec())
            .with("a.npy", vec![0]);
        let inputs = Inputs::new().with("tiles", Product::Files(files.clone()));
        let from_files = FileSource::input_or_dir(&inputs, "tiles", "dir", None).unwrap();

        let dir = std::env::temp_dir().join(format!("hc-source-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for (name, bytes) in &files.files {
            std::fs::write(dir.join(name), bytes).unwrap();
        }
        let dir_param = InputPath::new(&dir);
        let no_inputs = Inputs::new();
        let from_dir =
            FileSource::input_or_dir(&no_inputs, "tiles", "dir", Some(&dir_param)).unwrap();

        for source in [&from_files, &from_dir] {
            assert_eq!(source.names().unwrap(), ["a.npy", "b.csv"]);
            assert!(source.exists("b.csv") && !source.exists("c.csv"));
            assert_eq!(source.read_csv("b.csv").unwrap().f64("y").unwrap(), [2.5]);
            let e = source.read("c.csv").unwrap_err().to_string();
            assert!(e.contains("c.csv"), "{e}");
        }
        assert_eq!(from_files.display("b.csv"), "input `tiles`/b.csv");
        assert!(from_dir.display("b.csv").ends_with("b.csv"));

        let both = FileSource::input_or_dir(&inputs, "tiles", "dir", Some(&dir_param));
        assert!(both.unwrap_err().to_string().contains("not both"));
        let neither = FileSource::input_or_dir(&no_inputs, "tiles", "dir", None);
        assert!(neither.unwrap_err().to_string().contains("`dir`"));
        // A folder where a file should be is named, not read.
        std::fs::create_dir_all(dir.join("sub.csv")).unwrap();
        let e = from_dir.read("sub.csv").unwrap_err().to_string();
        assert!(
            e.contains("sub.csv") && e.contains("not a regular file"),
            "{e}"
        );
        // Names reaching out of the folder are refused, not followed.
        std::fs::write(dir.join("../hc-outside.csv"), "x\n1\n").unwrap();
        for name in ["../hc-outside.csv", "/etc/hostname", "a/../../x.csv"] {
            assert!(!from_dir.exists(name), "{name}");
            let e = from_dir.read(name).unwrap_err().to_string();
            assert!(e.contains("outside the folder"), "{name}: {e}");
        }
        std::fs::remove_file(dir.join("../hc-outside.csv")).unwrap();
        std::fs::remove_dir_all(dir).unwrap();
    }

    // Before, `names` skipped these silently (a later step then blamed the
    // folder); now each is refused by its own name.
    #[test]
    fn a_folder_entry_that_is_no_file_is_named() {
        let cases: [(&str, &str); 3] = [
            ("zero.npy", "not a regular file (a character device"),
            ("loop.npy", "is a symlink loop"),
            ("linked", "symlink to a folder, which is not followed"),
        ];
        for (name, says) in cases {
            let dir =
                std::env::temp_dir().join(format!("hc-entries-{}-{name}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(dir.join("real_subfolder")).unwrap();
            std::fs::write(dir.join("tile_000.npy"), "x").unwrap();
            let entry = dir.join(name);
            let target = match name {
                "zero.npy" => PathBuf::from("/dev/zero"),
                "loop.npy" => entry.clone(),
                _ => dir.join("real_subfolder"),
            };
            std::os::unix::fs::symlink(&target, &entry).unwrap();
            let source = FileSource::Dir(dir.clone());
            let e = source.names().unwrap_err().to_string();
            let shown = entry.display().to_string();
            assert!(e.starts_with(&shown) && e.contains(says), "{name}: {e}");
            std::fs::remove_file(&entry).unwrap();
            // A real subfolder is not entered, and not an error.
            assert_eq!(source.names().unwrap(), ["tile_000.npy"]);
            std::fs::remove_dir_all(dir).unwrap();
        }
    }
}
