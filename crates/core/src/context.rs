//! What the runner lends a running stage: progress bars, notes and file
//! readers.

use std::path::Path;
use std::sync::Mutex;

use crate::progress::{Progress, ProgressSink};
use crate::row_lines::RowLines;
use crate::{Field, StageError, Table};

/// Reads the files a loader stage is pointed at. The runner lends one that
/// reads Parquet, CSV and `.npy` (hypercontact-io's, composing
/// hypercontact-labfiles' `LabReader`); [`Context::new`] lends the
/// [`FieldReader`], which reads `.npy` fields only.
pub trait ProductReader: Send + Sync {
    fn read_table(&self, path: &Path) -> Result<Table, StageError>;
    fn read_field(&self, path: &Path, dx_m: f64, dy_m: f64) -> Result<Field, StageError>;

    /// The table with the file line of each row, so a stage checking the
    /// values can name the line of a bad one. The default numbers the rows
    /// of [`ProductReader::read_table`]; a reader of a text format (CSV)
    /// overrides it with the lines.
    fn read_table_with_lines(&self, path: &Path) -> Result<(Table, RowLines), StageError> {
        Ok((self.read_table(path)?, RowLines::default()))
    }
}

/// Reads `.npy` fields, the field type's own format; refuses tables, whose
/// readers (CSV, Parquet) live outside core so that no stage crate builds
/// them.
#[derive(Clone, Copy, Debug, Default)]
pub struct FieldReader;

impl ProductReader for FieldReader {
    fn read_table(&self, path: &Path) -> Result<Table, StageError> {
        Err(StageError::file(
            path,
            format!(
                "cannot read tables from `.{}` files here (no table reader: \
                 hypercontact-labfiles' LabReader reads CSV)",
                extension(path)
            ),
        ))
    }

    fn read_field(&self, path: &Path, dx_m: f64, dy_m: f64) -> Result<Field, StageError> {
        let bytes = crate::regular_file::read_regular_file(path)?;
        Field::read_npy(bytes.as_slice(), dx_m, dy_m)
            .map_err(|e| StageError::file(path, e.to_string()))
    }
}

/// The lowercase extension of a path, or "" if it has none.
pub fn extension(path: &Path) -> String {
    path.extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase()
}

/// The running stage's view of the runner.
pub struct Context<'a> {
    stage: String,
    sink: Option<&'a dyn ProgressSink>,
    reader: &'a dyn ProductReader,
    upstream: Option<serde_json::Value>,
    /// Every note of the run, in order: the runner keeps them with the
    /// cache entry and in provenance.json.
    notes: Mutex<Vec<String>>,
}

impl<'a> Context<'a> {
    /// A context with hidden progress and the [`FieldReader`]: for tests
    /// and library use.
    pub fn new(stage: &str) -> Context<'static> {
        Context {
            stage: stage.to_owned(),
            sink: None,
            reader: &FieldReader,
            upstream: None,
            notes: Mutex::new(Vec::new()),
        }
    }

    /// The runner's context: bars and notes shown by `sink` (None =
    /// quiet), files read by `reader`.
    pub fn with(
        stage: &str,
        sink: Option<&'a dyn ProgressSink>,
        reader: &'a dyn ProductReader,
    ) -> Self {
        Context {
            stage: stage.to_owned(),
            sink,
            reader,
            upstream: None,
            notes: Mutex::new(Vec::new()),
        }
    }

    /// Attaches the record of the stages this one depends on (kinds,
    /// versions, parameters, cache keys, input-file hashes, compute times),
    /// as the runner knows it: what a report prints as its provenance. It is
    /// a function of the upstream cache keys, so it never makes a cached
    /// result stale.
    pub fn with_upstream(mut self, record: serde_json::Value) -> Self {
        self.upstream = Some(record);
        self
    }

    /// The upstream record, when a runner supplied one.
    pub fn upstream(&self) -> Option<&serde_json::Value> {
        self.upstream.as_ref()
    }

    /// The stage's name in the pipeline.
    pub fn stage(&self) -> &str {
        &self.stage
    }

    /// A progress bar over `len` steps, labelled with the stage name.
    pub fn progress(&self, len: u64, what: &str) -> Progress {
        match self.sink {
            Some(sink) => Progress::shown(sink.bar(&self.stage, len, what)),
            None => Progress::hidden(),
        }
    }

    /// Says something the user should know (a choice made for them, a
    /// warning: start it with `warning:`). The sink shows it (the
    /// runner's: above the progress bars on a terminal, a plain line on
    /// stderr when there is none; nothing when quiet); and it is kept: the
    /// runner stores a stage's notes with its cache entry and writes them
    /// into provenance.json, so a cached result still carries them.
    pub fn note(&self, message: &str) {
        if let Some(sink) = self.sink {
            sink.note(&self.stage, message);
        }
        self.notes
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
            .push(message.to_owned());
    }

    /// The notes said so far, in order.
    pub fn notes(&self) -> Vec<String> {
        self.notes
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
            .clone()
    }

    pub fn read_table(&self, path: &Path) -> Result<Table, StageError> {
        self.reader.read_table(path)
    }

    /// [`ProductReader::read_table_with_lines`].
    pub fn read_table_with_lines(&self, path: &Path) -> Result<(Table, RowLines), StageError> {
        self.reader.read_table_with_lines(path)
    }

    pub fn read_field(&self, path: &Path, dx_m: f64, dy_m: f64) -> Result<Field, StageError> {
        self.reader.read_field(path, dx_m, dy_m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::progress::Bar;
    use std::sync::Arc;

    /// `/dev/zero` given as a field was read without end (and without
    /// memory bound); it is refused before reading.
    #[cfg(unix)]
    #[test]
    fn devices_are_refused_not_read_forever() {
        let field = hypercontact_fuzz::within(10, || {
            FieldReader
                .read_field(Path::new("/dev/zero"), 1.0, 1.0)
                .map(|_| ())
        });
        let e = field.unwrap_err().to_string();
        assert!(
            e.contains("/dev/zero") && e.contains("not a regular file"),
            "{e}"
        );
    }

    #[test]
    fn the_field_reader_refuses_tables_and_names_the_file() {
        let e = FieldReader
            .read_table_with_lines(Path::new("data/t.csv"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("data/t.csv: cannot read tables from `.csv`"),
            "{e}"
        );
    }

    /// A sink that logs what it is asked to show.
    #[derive(Default)]
    struct Recorder(Arc<Mutex<Vec<String>>>);

    impl Recorder {
        fn log(&self) -> Vec<String> {
            self.0.lock().unwrap().clone()
        }
    }

    impl ProgressSink for Recorder {
        fn bar(&self, stage: &str, len: u64, what: &str) -> Box<dyn Bar> {
            self.0
                .lock()
                .unwrap()
                .push(format!("bar {stage} {len} {what}"));
            Box::new(Recorder(Arc::clone(&self.0)))
        }

        fn note(&self, stage: &str, message: &str) {
            self.0
                .lock()
                .unwrap()
                .push(format!("note {stage} {message}"));
        }
    }

    impl Bar for Recorder {
        fn inc(&self, n: u64) {
            self.0.lock().unwrap().push(format!("inc {n}"));
        }

        fn set_position(&self, pos: u64) {
            self.0.lock().unwrap().push(format!("position {pos}"));
        }

        fn set_message(&self, what: &str) {
            self.0.lock().unwrap().push(format!("message {what}"));
        }

        fn finish(&self) {
            self.0.lock().unwrap().push("finish".into());
        }
    }

    #[test]
    fn the_sink_sees_every_bar_step_and_note_and_the_context_keeps_the_notes() {
        let sink = Recorder::default();
        let ctx = Context::with("fit", Some(&sink), &FieldReader);
        {
            let bar = ctx.progress(3, "refits");
            bar.inc(2);
            bar.set_position(3);
            bar.set_message("done");
            ctx.note("warning: few points");
        }
        assert_eq!(
            sink.log(),
            [
                "bar fit 3 refits",
                "inc 2",
                "position 3",
                "message done",
                "note fit warning: few points",
                "finish"
            ]
        );
        assert_eq!(ctx.notes(), ["warning: few points"]);
        // Without a sink nothing is shown, and the notes are still kept.
        let quiet = Context::new("fit");
        quiet.progress(2, "refits").inc(1);
        quiet.note("a");
        quiet.note("b");
        assert_eq!(quiet.notes(), ["a", "b"]);
    }
}
