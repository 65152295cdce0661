//! Reads a CSV file with a header row into a [`Table`].
//!
//! A column whose every cell is an integer becomes `i64`, one whose cells are
//! numbers (empty or `NaN` cells included, read as NaN) becomes `f64`, and
//! anything else `str`. Errors name the file and line.

use std::path::Path;

use crate::{ColumnData, StageError, Table};

pub fn read_csv(path: &Path) -> Result<Table, StageError> {
    let bytes = std::fs::read(path).map_err(|e| StageError::file(path, e.to_string()))?;
    read_csv_bytes(&bytes, &path.display().to_string())
}

/// The same from bytes already in memory (a file of a `Files` product);
/// `display` names the file in errors. A byte-order mark is skipped, as
/// spreadsheet programs write one.
pub fn read_csv_bytes(bytes: &[u8], display: &str) -> Result<Table, StageError> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_reader(bytes);
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| StageError::file(display, e.to_string()))?
        .iter()
        .map(str::to_owned)
        .collect();
    let mut cells: Vec<Vec<String>> = vec![Vec::new(); header.len()];
    for record in reader.records() {
        let record = record.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line());
            StageError::file(display, format!("line {line}: {e}"))
        })?;
        for (column, cell) in cells.iter_mut().zip(record.iter()) {
            column.push(cell.to_owned());
        }
    }
    let mut table = Table::new();
    for (name, column) in header.iter().zip(cells) {
        if table.column(name).is_ok() {
            return Err(StageError::file(
                display,
                format!("the header names column `{name}` twice"),
            ));
        }
        table.push(name, infer(column));
    }
    Ok(table)
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
