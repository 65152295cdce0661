//! The lab's [`ProductReader`]: CSV tables (with the file line of every
//! row) and `.npy` fields. The runner's reader (hypercontact-io) adds
//! Parquet and hands every other file to this one.

use std::path::Path;

use hypercontact_core::context::extension;
use hypercontact_core::{Field, FieldReader, ProductReader, RowLines, StageError, Table};

use crate::csv_table::{read_csv, read_csv_with_lines};

/// Reads CSV tables and `.npy` fields.
#[derive(Clone, Copy, Debug, Default)]
pub struct LabReader;

impl ProductReader for LabReader {
    fn read_table(&self, path: &Path) -> Result<Table, StageError> {
        match extension(path).as_str() {
            "csv" => read_csv(path),
            other => Err(StageError::file(
                path,
                format!("cannot read tables from `.{other}` files here (CSV only)"),
            )),
        }
    }

    /// A CSV file keeps its lines; any other table is numbered by row.
    fn read_table_with_lines(&self, path: &Path) -> Result<(Table, RowLines), StageError> {
        match extension(path).as_str() {
            "csv" => read_csv_with_lines(path).map(|csv| (csv.table, csv.lines)),
            _ => Ok((self.read_table(path)?, RowLines::default())),
        }
    }

    fn read_field(&self, path: &Path, dx_m: f64, dy_m: f64) -> Result<Field, StageError> {
        FieldReader.read_field(path, dx_m, dy_m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::RowPlace;

    /// `/dev/zero` given as a table or a field was read without end (and
    /// without memory bound); it is refused before reading.
    #[cfg(unix)]
    #[test]
    fn devices_are_refused_not_read_forever() {
        let (field, table, csv) = hypercontact_fuzz::within(10, || {
            let zero = Path::new("/dev/zero");
            let field = LabReader.read_field(zero, 1.0, 1.0).map(|_| ());
            let table = LabReader.read_table(zero).map(|_| ());
            let csv = read_csv(zero).map(|_| ());
            (field, table, csv)
        });
        let e = table.unwrap_err().to_string();
        assert_eq!(
            e,
            "/dev/zero: cannot read tables from `.` files here (CSV only)"
        );
        for e in [field.unwrap_err(), csv.unwrap_err()] {
            let e = e.to_string();
            assert!(
                e.contains("/dev/zero") && e.contains("not a regular file"),
                "{e}"
            );
        }
    }

    #[test]
    fn csv_rows_keep_their_lines_and_fields_read_as_npy() {
        let dir = std::env::temp_dir().join(format!("hc-labreader-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let csv = dir.join("t.CSV");
        std::fs::write(&csv, "# units: SI\nx\n\n1.5\n2.5\n").unwrap();
        let (table, lines) = LabReader.read_table_with_lines(&csv).unwrap();
        assert_eq!(table.f64("x").unwrap(), [1.5, 2.5]);
        assert_eq!(
            [lines.place(0), lines.place(1)],
            [RowPlace::Line(4), RowPlace::Line(5)]
        );
        assert_eq!(LabReader.read_table(&csv).unwrap(), table);

        let field = Field::new(ndarray::array![[1.0, 2.0], [3.0, 4.5]], 1e-6, 1e-6).unwrap();
        let npy = dir.join("h.npy");
        let mut bytes = Vec::new();
        field.write_npy(&mut bytes).unwrap();
        std::fs::write(&npy, bytes).unwrap();
        let back = LabReader.read_field(&npy, 1e-6, 1e-6).unwrap();
        assert_eq!(back.values, field.values);

        let e = LabReader
            .read_table_with_lines(&npy)
            .unwrap_err()
            .to_string();
        assert!(
            e.ends_with("h.npy: cannot read tables from `.npy` files here (CSV only)"),
            "{e}"
        );
        std::fs::remove_dir_all(dir).unwrap();
    }
}
