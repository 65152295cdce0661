//! Reads a CSV file with a header row into a [`Table`].
//!
//! A column whose every cell is an integer becomes `i64`, one whose cells are
//! numbers (empty or `NaN` cells included, read as NaN) becomes `f64`, and
//! anything else `str`. Lines starting with `#` are comments and blank lines
//! are skipped. Every data row keeps the line it stands on in the file (as an
//! editor numbers it: the header, comments and blank lines counted), so
//! errors here and in the stages that check the values name the file and
//! that line.

use std::path::Path;

use hypercontact_core::regular_file::read_regular_file;
use hypercontact_core::shown::is_name_like;
use hypercontact_core::{ColumnData, StageError, Table};

// Part of a CSV table's API; they live in core, where `ProductReader`
// returns them.
pub use hypercontact_core::row_lines::{RowLines, RowPlace};

/// A CSV file read as a table, with where its rows stand in the file.
#[derive(Clone, Debug, PartialEq)]
pub struct CsvTable {
    pub table: Table,
    /// The line of the header row (1-based).
    pub header_line: u64,
    /// The line of each data row.
    pub lines: RowLines,
}

pub fn read_csv(path: &Path) -> Result<Table, StageError> {
    read_csv_with_lines(path).map(|csv| csv.table)
}

/// [`read_csv`] with the line of every row.
pub fn read_csv_with_lines(path: &Path) -> Result<CsvTable, StageError> {
    let bytes = read_regular_file(path)?;
    read_csv_bytes_with_lines(&bytes, &path.display().to_string())
}

/// The same from bytes already in memory (a file of a `Files` product);
/// `display` names the file in errors. A byte-order mark is skipped, as
/// spreadsheet programs write one.
pub fn read_csv_bytes(bytes: &[u8], display: &str) -> Result<Table, StageError> {
    read_csv_bytes_with_lines(bytes, display).map(|csv| csv.table)
}

/// [`read_csv_bytes`] with the line of every row. A file with no header
/// (empty, or only blank and comment lines) or with a header and no data
/// rows is an error saying so.
pub fn read_csv_bytes_with_lines(bytes: &[u8], display: &str) -> Result<CsvTable, StageError> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let file = CsvFile::new(bytes, display);
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .has_headers(false)
        .from_reader(file.blanked.as_slice());
    let mut records = reader.byte_records();
    let Some(header) = records.next() else {
        return Err(file.fail(if bytes.is_empty() {
            "is empty".into()
        } else {
            "is empty: no header line, only blank or comment lines".into()
        }));
    };
    let (header, header_line) = read_header(&file, header)?;
    let (cells, row_lines) = read_rows(&file, &header, records)?;
    if row_lines.is_empty() {
        return Err(file.fail(format!(
            "no data rows (the header, line {header_line}, is all there is)"
        )));
    }
    Ok(CsvTable {
        table: into_table(&file, header_line, &header, cells)?,
        header_line,
        lines: RowLines::from_lines(row_lines),
    })
}

/// A CSV file being read: its name for errors and the file line of every
/// byte offset the csv crate reports.
struct CsvFile<'d> {
    display: &'d str,
    lines: LineIndex,
    /// The bytes the csv crate reads: the file with its comment lines
    /// blanked. The csv crate's positions skip the bytes of comment lines
    /// it drops itself; blanked lines keep their length, so every offset
    /// stays the file's, and its blank-line skipping drops them.
    blanked: Vec<u8>,
}

impl<'d> CsvFile<'d> {
    fn new(bytes: &[u8], display: &'d str) -> Self {
        CsvFile {
            display,
            lines: LineIndex::new(bytes),
            blanked: blank_comments(bytes),
        }
    }

    fn fail(&self, message: String) -> StageError {
        StageError::file(self.display, message)
    }

    /// The line of the record at `position`. A record's position is where
    /// the reader stood before it: the blank lines above it lie in between.
    fn line_of(&self, position: Option<&csv::Position>) -> u64 {
        let mut offset = position.map_or(0, |p| p.byte() as usize);
        while matches!(self.blanked.get(offset), Some(b'\r' | b'\n')) {
            offset += 1;
        }
        self.lines.line(offset)
    }

    /// A csv crate error as this file's, at its line.
    fn error(&self, e: csv::Error) -> StageError {
        match e.kind() {
            csv::ErrorKind::UnequalLengths {
                pos,
                expected_len,
                len,
            } => self.fail(format!(
                "line {}: {len} fields, the header has {expected_len}",
                self.line_of(pos.as_ref())
            )),
            _ => self.fail(format!("line {}: {e}", self.line_of(e.position()))),
        }
    }
}

/// The column names of the header record and its line.
fn read_header(
    file: &CsvFile,
    record: csv::Result<csv::ByteRecord>,
) -> Result<(Vec<String>, u64), StageError> {
    let record = record.map_err(|e| file.error(e))?;
    let header_line = file.line_of(record.position());
    let header: Vec<String> = record
        .iter()
        .enumerate()
        .map(|(i, name)| {
            String::from_utf8(name.to_vec()).map_err(|_| {
                file.fail(format!(
                    "line {header_line}: the name of column {} is not UTF-8 text",
                    i + 1
                ))
            })
        })
        .collect::<Result<_, _>>()?;
    if let [only] = header.as_slice()
        && let Some((separator, name)) = [(';', "semicolons"), ('\t', "tabs")]
            .into_iter()
            .find(|(c, _)| only.contains(*c))
    {
        // A spreadsheet saved in a decimal-comma locale writes `;`; read
        // with `,` it is one column whose name holds every header field.
        // The line is shown only if its fields read as names.
        let shown = match only.split(separator).all(is_name_like) {
            true => format!(" (`{}`)", only.escape_debug()),
            false => String::new(),
        };
        return Err(file.fail(format!(
            "line {header_line}: the fields are separated by {name}{shown}, not commas: \
             save the file as comma-separated CSV with `.` as the decimal mark \
             (e.g. `time_s,force_n` and `0.5,12.25`)"
        )));
    }
    // Messages name columns by the header's names: a first line that is
    // not a header of names (a password file, a settings file) is refused
    // unshown, so no later message echoes it.
    if let Some(column) = header.iter().position(|name| !is_name_like(name)) {
        return Err(file.fail(format!(
            "line {header_line}: is not a CSV header of column names (field {} of {} is not a \
             name; the line is not shown): a table starts with a line of names such as \
             `time_s,force_n`",
            column + 1,
            header.len()
        )));
    }
    Ok((header, header_line))
}

/// The text of every cell by column, and the line of every data row.
fn read_rows(
    file: &CsvFile,
    header: &[String],
    records: impl Iterator<Item = csv::Result<csv::ByteRecord>>,
) -> Result<(Vec<Vec<String>>, Vec<u64>), StageError> {
    let mut cells: Vec<Vec<String>> = vec![Vec::new(); header.len()];
    let mut row_lines = Vec::new();
    for record in records {
        let record = record.map_err(|e| file.error(e))?;
        let line = file.line_of(record.position());
        for ((column, cell), name) in cells.iter_mut().zip(record.iter()).zip(header) {
            let text = std::str::from_utf8(cell).map_err(|_| {
                file.fail(format!(
                    "line {line}, column `{name}`: the cell is not UTF-8 text"
                ))
            })?;
            column.push(text.to_owned());
        }
        row_lines.push(line);
    }
    Ok((cells, row_lines))
}

/// The columns as a table, each of the type its cells allow ([`infer`]);
/// a name the header gives twice is an error.
fn into_table(
    file: &CsvFile,
    header_line: u64,
    header: &[String],
    cells: Vec<Vec<String>>,
) -> Result<Table, StageError> {
    let mut table = Table::new();
    for (name, column) in header.iter().zip(cells) {
        if table.column(name).is_ok() {
            return Err(file.fail(format!(
                "line {header_line}: the header names column `{name}` twice"
            )));
        }
        table.push(name, infer(column));
    }
    Ok(table)
}

/// The start offset of every line; a line ends at `\n`, `\r\n` or `\r`, as
/// the csv crate reads them.
struct LineIndex(Vec<usize>);

impl LineIndex {
    fn new(bytes: &[u8]) -> Self {
        let mut starts = vec![0];
        let mut i = 0;
        while i < bytes.len() {
            match bytes[i] {
                b'\r' if bytes.get(i + 1) == Some(&b'\n') => {
                    starts.push(i + 2);
                    i += 2;
                    continue;
                }
                b'\r' | b'\n' => starts.push(i + 1),
                _ => {}
            }
            i += 1;
        }
        LineIndex(starts)
    }

    /// The 1-based line holding byte `offset`.
    fn line(&self, offset: usize) -> u64 {
        self.0.partition_point(|&start| start <= offset) as u64
    }
}

/// The bytes with every comment line (a `#` where a record starts, outside
/// quotes) turned into line ends, as many as it had bytes.
fn blank_comments(bytes: &[u8]) -> Vec<u8> {
    #[derive(PartialEq)]
    enum State {
        FieldStart,
        Unquoted,
        Quoted,
        /// A quote inside a quoted field: `""` (an escaped quote) or its end.
        QuoteInQuoted,
    }
    let mut out = bytes.to_vec();
    let mut state = State::FieldStart;
    let mut record_start = true;
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        if record_start && b == b'#' {
            while i < bytes.len() && !matches!(bytes[i], b'\r' | b'\n') {
                out[i] = b'\n';
                i += 1;
            }
            continue;
        }
        if state == State::QuoteInQuoted {
            if b == b'"' {
                state = State::Quoted;
                record_start = false;
                i += 1;
                continue;
            }
            // The quoted part ended; the byte is read as outside quotes.
            state = State::Unquoted;
        }
        record_start = false;
        match (&state, b) {
            (State::Quoted, b'"') => state = State::QuoteInQuoted,
            (State::Quoted, _) => {}
            (State::FieldStart, b'"') => state = State::Quoted,
            (_, b',') => state = State::FieldStart,
            (_, b'\r' | b'\n') => {
                state = State::FieldStart;
                record_start = true;
            }
            _ => state = State::Unquoted,
        }
        i += 1;
    }
    out
}

fn infer(cells: Vec<String>) -> ColumnData {
    if !cells.is_empty() && cells.iter().all(|c| c.parse::<i64>().is_ok()) {
        return ColumnData::I64(
            cells
                .iter()
                .map(|c| c.parse().unwrap_or_default())
                .collect(),
        );
    }
    let numbers: Option<Vec<f64>> = cells
        .iter()
        .map(|c| {
            if c.is_empty() {
                Some(f64::NAN)
            } else {
                c.parse::<f64>().ok()
            }
        })
        .collect();
    match numbers {
        Some(v) if !cells.is_empty() => ColumnData::F64(v),
        _ => ColumnData::Str(cells),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn infers_types_and_reads_nan() {
        let dir = tempdir();
        let path = dir.join("t.csv");
        std::fs::write(
            &path,
            "# a comment\nmode,stretch,frame\nUT,1.0,1\nUT,,2\nBT,1.5,3\n",
        )
        .unwrap();
        let t = read_csv(&path).unwrap();
        assert_eq!(t.str("mode").unwrap(), ["UT", "UT", "BT"]);
        let s = t.f64("stretch").unwrap();
        assert!(s[1].is_nan() && s[2] == 1.5);
        assert_eq!(t.i64("frame").unwrap(), &[1, 2, 3]);
    }

    #[test]
    fn bytes_with_a_byte_order_mark_read_alike() {
        let t = read_csv_bytes(b"\xEF\xBB\xBFtime_s,force_n\n0,1.5\n", "force.csv").unwrap();
        assert_eq!(t.column_names(), ["time_s", "force_n"]);
        let e = read_csv_bytes(b"a,a\n1,2\n", "dup.csv")
            .unwrap_err()
            .to_string();
        assert!(e.contains("dup.csv") && e.contains("twice"), "{e}");
    }

    #[test]
    fn ragged_row_names_file_and_line() {
        let dir = tempdir();
        let path = dir.join("bad.csv");
        std::fs::write(&path, "a,b\n1,2\n3\n").unwrap();
        let err = read_csv(&path).unwrap_err().to_string();
        assert!(err.contains("bad.csv") && err.contains("line 3"), "{err}");
    }

    fn lines_of(text: &str) -> Vec<RowPlace> {
        let csv = read_csv_bytes_with_lines(text.as_bytes(), "t.csv").unwrap();
        (0..csv.table.n_rows())
            .map(|r| csv.lines.place(r))
            .collect()
    }

    #[test]
    fn semicolon_and_tab_separated_files_are_named_as_such() {
        for (text, name) in [
            ("time_s;force_n\n0,5;1,25\n", "semicolons"),
            ("\u{feff}time_s;force_n\r\n0.5;1.25\r\n", "semicolons"),
            ("time_s\tforce_n\n0.5\t1.25\n", "tabs"),
        ] {
            let e = read_csv_bytes(text.as_bytes(), "force.csv")
                .unwrap_err()
                .to_string();
            assert!(
                e.starts_with("force.csv: line 1: the fields are separated by ")
                    && e.contains(name)
                    && e.contains("comma-separated"),
                "{e}"
            );
        }
        // A one-column file with neither is still a table.
        let t = read_csv_bytes(b"time_s\n0.5\n", "t.csv").unwrap();
        assert_eq!(t.f64("time_s").unwrap(), &[0.5]);
        // A semicolon inside a quoted field of a comma file is no separator.
        let t = read_csv_bytes(b"note,x\n\"a;b\",1\n", "t.csv").unwrap();
        assert_eq!(t.str("note").unwrap(), ["a;b"]);
    }

    #[test]
    fn rows_keep_their_file_lines_past_comments_blanks_and_quotes() {
        use RowPlace::Line;
        assert_eq!(lines_of("a,b\n1,2\n3,4"), [Line(2), Line(3)]);
        // Comments and blank lines above, between and below the rows.
        let text = "# made by x\n\n# units: SI\na,b\r\n\n1,2\n# pause\n\n\n3,4\n# end\n";
        assert_eq!(lines_of(text), [Line(6), Line(10)]);
        let csv = read_csv_bytes_with_lines(text.as_bytes(), "t.csv").unwrap();
        assert_eq!(csv.header_line, 4);
        // A quoted cell spanning lines; a `#` inside quotes is no comment;
        // old Mac line ends.
        let text = "a,b\n\"x\n# not a comment\ny\",2\n5,6\r7,8\r\n9,10";
        assert_eq!(lines_of(text), [Line(2), Line(5), Line(6), Line(7)]);
        let t = read_csv_bytes(text.as_bytes(), "t.csv").unwrap();
        assert_eq!(t.str("a").unwrap()[0], "x\n# not a comment\ny");
        // An escaped quote does not end the quoted cell.
        let text = "a,b\n\"say \"\"hi\"\"\n# still quoted\",1\n# comment\n2,3\n";
        assert_eq!(lines_of(text), [Line(2), Line(5)]);
        assert_eq!(RowLines::default().place(2), RowPlace::Row(3));
    }

    #[test]
    fn a_ragged_row_after_comments_is_named_by_its_own_line() {
        let e = read_csv_bytes(b"# c\n\na,b\n# c\n1,2\n\n3\n", "r.csv")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("r.csv: line 7: 1 fields, the header has 2"),
            "{e}"
        );
        let e = read_csv_bytes(b"a,b\n1,2\n\n# c\n3,4,5\n", "r.csv")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("r.csv: line 5: 3 fields, the header has 2"),
            "{e}"
        );
    }

    #[test]
    fn empty_and_header_only_files_say_so() {
        let message = |text: &str| {
            read_csv_bytes(text.as_bytes(), "t.csv")
                .unwrap_err()
                .to_string()
        };
        assert_eq!(message(""), "t.csv: is empty");
        let e = message("\n# only a comment\n\n");
        assert!(
            e.starts_with("t.csv: is empty") && e.contains("comment"),
            "{e}"
        );
        let e = message("# c\nmode,stretch\n\n# c\n");
        assert_eq!(
            e,
            "t.csv: no data rows (the header, line 2, is all there is)"
        );
        let e = read_csv_bytes(b"a,b\n1,\xff\n", "u.csv")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("u.csv: line 2, column `b`") && e.contains("UTF-8"),
            "{e}"
        );
    }

    fn tempdir() -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!(
            "hc-csv-{}-{:?}",
            std::process::id(),
            std::thread::current().id()
        ));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }
}
