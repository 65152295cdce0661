//! Reads a CSV file with a header row into a [`Table`].
//!
//! A column whose every cell is an integer becomes `i64`, one whose cells are
//! numbers (empty or `NaN` cells included, read as NaN) becomes `f64`, and
//! anything else `str`. Errors name the file and line.

use std::path::Path;

use crate::{ColumnData, StageError, Table};

pub fn read_csv(path: &Path) -> Result<Table, StageError> {
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_path(path)
        .map_err(|e| StageError::file(path, e.to_string()))?;
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| StageError::file(path, e.to_string()))?
        .iter()
        .map(str::to_owned)
        .collect();
    let mut cells: Vec<Vec<String>> = vec![Vec::new(); header.len()];
    for record in reader.records() {
        let record = record.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line());
            StageError::file(path, format!("line {line}: {e}"))
        })?;
        for (column, cell) in cells.iter_mut().zip(record.iter()) {
            column.push(cell.to_owned());
        }
    }
    let mut table = Table::new();
    for (name, column) in header.iter().zip(cells) {
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
