//! The I/O edge: the only crate that touches polars.
//!
//! Tables go to and from Parquet, a declared table with its columns' units
//! and descriptions ([`columns_meta`]); the [`RunnerReader`] gives loader
//! stages Parquet as well as the CSV and `.npy` that hypercontact-labfiles
//! reads.

pub mod columns_meta;

use std::io::{Read, Seek, Write};
use std::path::Path;

use hypercontact_core::context::extension;
use hypercontact_core::regular_file::check_regular_file;
use hypercontact_core::{
    ColumnData, ColumnSpec, Field, ProductReader, RowLines, StageError, Table,
};
use hypercontact_labfiles::LabReader;
use polars::prelude::*;

pub use columns_meta::{COLUMNS_KEY, ColumnMeta};

#[derive(Debug, thiserror::Error)]
pub enum IoError {
    // Messages hold their causes, so these are not also `source()` (a
    // printed chain would repeat them): hence the plain `From` impls.
    #[error("parquet: {0}")]
    Polars(PolarsError),
    #[error("column `{name}` has type {dtype}, which hypercontact does not read")]
    Unsupported { name: String, dtype: String },
    #[error("table: {0}")]
    Table(hypercontact_core::TableError),
    #[error("file metadata `{key}` is not the columns' JSON array: {cause}")]
    ColumnsMeta {
        key: &'static str,
        cause: serde_json::Error,
    },
}

impl From<PolarsError> for IoError {
    fn from(e: PolarsError) -> Self {
        IoError::Polars(e)
    }
}

impl From<hypercontact_core::TableError> for IoError {
    fn from(e: hypercontact_core::TableError) -> Self {
        IoError::Table(e)
    }
}

fn to_frame(table: &Table) -> Result<DataFrame, IoError> {
    table.validate()?;
    let columns = table
        .columns()
        .iter()
        .map(|c| {
            let name = PlSmallStr::from(c.name.as_str());
            match &c.data {
                ColumnData::F64(v) => Column::new(name, v.as_slice()),
                ColumnData::I64(v) => Column::new(name, v.as_slice()),
                ColumnData::Str(v) => Column::new(name, v.as_slice()),
            }
        })
        .collect();
    Ok(DataFrame::new(table.n_rows(), columns)?)
}

/// Writes a table as Parquet (zstd, with statistics).
pub fn write_parquet<W: Write>(table: &Table, writer: W) -> Result<(), IoError> {
    write_parquet_described(table, &[], writer)
}

/// Writes a table as Parquet with the unit and description of each of its
/// columns that `columns` declares, under the file key [`COLUMNS_KEY`].
/// A table none of whose columns is declared gets no key: the same bytes
/// as [`write_parquet`].
pub fn write_parquet_described<W: Write>(
    table: &Table,
    columns: &[ColumnSpec],
    writer: W,
) -> Result<(), IoError> {
    let mut frame = to_frame(table)?;
    let described = columns_meta::described_columns(table, columns);
    let key_value = (!described.is_empty()).then(|| {
        KeyValueMetadata::from_static(vec![(
            COLUMNS_KEY.to_owned(),
            columns_meta::encode(&described),
        )])
    });
    ParquetWriter::new(writer)
        .with_compression(ParquetCompression::Zstd(None))
        .with_key_value_metadata(key_value)
        .finish(&mut frame)?;
    Ok(())
}

/// The units and descriptions a Parquet file carries under [`COLUMNS_KEY`],
/// in column order; empty for a file written without a declaration.
pub fn parquet_columns_meta<R>(reader: R) -> Result<Vec<ColumnMeta>, IoError>
where
    R: Read + Seek + Send + Sync + 'static + polars::io::mmap::MmapBytesReader,
{
    let mut parquet = ParquetReader::new(reader);
    let metadata = parquet.get_metadata()?;
    let Some(value) = metadata
        .key_value_metadata
        .iter()
        .flatten()
        .find(|kv| kv.key == COLUMNS_KEY)
        .and_then(|kv| kv.value.as_deref())
    else {
        return Ok(Vec::new());
    };
    columns_meta::decode(value).map_err(|cause| IoError::ColumnsMeta {
        key: COLUMNS_KEY,
        cause,
    })
}

/// Reads a Parquet file into a table. Integer columns become `i64`, float
/// columns `f64` (nulls read as NaN), strings `str`.
pub fn read_parquet<R>(reader: R) -> Result<Table, IoError>
where
    R: Read + Seek + Send + Sync + 'static + polars::io::mmap::MmapBytesReader,
{
    let frame = ParquetReader::new(reader).finish()?;
    let mut table = Table::new();
    for column in frame.columns() {
        let name = column.name().as_str();
        let dtype = column.dtype();
        let data = if dtype.is_float() {
            let c = column.cast(&DataType::Float64)?;
            ColumnData::F64(c.f64()?.iter().map(|v| v.unwrap_or(f64::NAN)).collect())
        } else if dtype.is_integer() {
            if column.null_count() > 0 {
                let c = column.cast(&DataType::Float64)?;
                ColumnData::F64(c.f64()?.iter().map(|v| v.unwrap_or(f64::NAN)).collect())
            } else {
                let c = column.cast(&DataType::Int64)?;
                ColumnData::I64(c.i64()?.iter().map(|v| v.unwrap_or_default()).collect())
            }
        } else if dtype.is_string() {
            ColumnData::Str(
                column
                    .str()?
                    .iter()
                    .map(|v| v.unwrap_or_default().to_owned())
                    .collect(),
            )
        } else {
            return Err(IoError::Unsupported {
                name: name.to_owned(),
                dtype: dtype.to_string(),
            });
        };
        table.push(name, data);
    }
    Ok(table)
}

/// Reads a Parquet file from disk.
/// Anything but a regular file (a folder, a device, a pipe) is refused
/// before reading, as every reader does.
pub fn read_parquet_file(path: &Path) -> Result<Table, StageError> {
    check_regular_file(path)?;
    let file = std::fs::File::open(path).map_err(|e| StageError::file(path, e.to_string()))?;
    read_parquet(file).map_err(|e| StageError::file(path, e.to_string()))
}

/// The reader the runner lends to stages: Parquet here, CSV (with its
/// lines) and `.npy` by the lab's [`LabReader`].
#[derive(Clone, Copy, Debug, Default)]
pub struct RunnerReader;

impl ProductReader for RunnerReader {
    fn read_table(&self, path: &Path) -> Result<Table, StageError> {
        match extension(path).as_str() {
            "parquet" | "pq" => read_parquet_file(path),
            _ => LabReader.read_table(path),
        }
    }

    fn read_table_with_lines(&self, path: &Path) -> Result<(Table, RowLines), StageError> {
        match extension(path).as_str() {
            "parquet" | "pq" => Ok((read_parquet_file(path)?, RowLines::default())),
            _ => LabReader.read_table_with_lines(path),
        }
    }

    fn read_field(&self, path: &Path, dx_m: f64, dy_m: f64) -> Result<Field, StageError> {
        LabReader.read_field(path, dx_m, dy_m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Cursor;

    #[test]
    fn parquet_round_trip_keeps_types_and_nan() {
        let t = Table::new()
            .with("mode", vec!["UT", "BT"])
            .with("stretch", vec![1.0, f64::NAN])
            .with("frame", vec![3_i64, 4]);
        let mut bytes = Vec::new();
        write_parquet(&t, &mut bytes).unwrap();
        let back = read_parquet(Cursor::new(bytes)).unwrap();
        assert_eq!(back.column_names(), ["mode", "stretch", "frame"]);
        assert_eq!(back.str("mode").unwrap(), ["UT", "BT"]);
        assert!(back.f64("stretch").unwrap()[1].is_nan());
        assert_eq!(back.i64("frame").unwrap(), &[3, 4]);
    }

    /// A declared table comes back with its values and, from the file
    /// metadata, its declaration; one without a declaration (or with one
    /// naming none of its columns) has no key and the bytes `write_parquet`
    /// always wrote. pyarrow reads the key too (checked once by hand, see
    /// `assert_exported_tables_carry_their_units` in tests/cli.rs).
    #[test]
    fn declared_units_and_docs_come_back_from_the_file() {
        let declared = [
            ColumnSpec::f64("load_n", "N", "total normal load"),
            ColumnSpec::f64("area_fraction", "", "true over nominal area"),
            ColumnSpec::str("mode", "loading mode"),
        ];
        let t = Table::new()
            .with("mode", vec!["UT", "BT"])
            .with("load_n", vec![1.0, 2.5])
            .with("study.value", vec![3_i64, 4])
            .with("area_fraction", vec![0.25, 0.5]);
        let mut bytes = Vec::new();
        write_parquet_described(&t, &declared, &mut bytes).unwrap();
        let back = read_parquet(Cursor::new(bytes.clone())).unwrap();
        assert_eq!(back.column_names(), t.column_names());
        assert_eq!(back.str("mode").unwrap(), ["UT", "BT"]);
        assert_eq!(back.f64("load_n").unwrap(), &[1.0, 2.5]);
        assert_eq!(back.i64("study.value").unwrap(), &[3, 4]);
        assert_eq!(back.f64("area_fraction").unwrap(), &[0.25, 0.5]);
        let meta = parquet_columns_meta(Cursor::new(bytes.clone())).unwrap();
        let expected: Vec<ColumnMeta> = [&declared[2], &declared[0], &declared[1]]
            .into_iter()
            .map(ColumnMeta::from)
            .collect();
        assert_eq!(meta, expected);
        assert_eq!(meta[1].unit, "N");

        let mut again = Vec::new();
        write_parquet_described(&t, &declared, &mut again).unwrap();
        assert_eq!(again, bytes, "the same declaration gives the same bytes");

        let mut plain = Vec::new();
        write_parquet(&t, &mut plain).unwrap();
        assert_ne!(plain, bytes);
        assert_eq!(
            parquet_columns_meta(Cursor::new(plain.clone())).unwrap(),
            []
        );
        assert_eq!(read_parquet(Cursor::new(plain.clone())).unwrap(), back);
        let unrelated = [ColumnSpec::f64("gap_m", "m", "not a column of t")];
        for columns in [&[][..], &unrelated[..]] {
            let mut undeclared = Vec::new();
            write_parquet_described(&t, columns, &mut undeclared).unwrap();
            assert_eq!(undeclared, plain);
        }
        let text = String::from_utf8_lossy(&plain);
        assert!(!text.contains(COLUMNS_KEY));
    }

    #[test]
    fn devices_and_folders_are_refused_before_reading() {
        for path in ["/dev/zero", "/dev/null", "/tmp"] {
            let e = read_parquet_file(Path::new(path)).unwrap_err().to_string();
            assert!(e.contains(path) && e.contains("not a regular file"), "{e}");
        }
    }

    #[test]
    fn ragged_table_is_refused() {
        let t = Table::new().with("a", vec![1.0]).with("b", vec![1.0, 2.0]);
        assert!(write_parquet(&t, Vec::new()).is_err());
    }

    /// A CSV table read through the runner keeps its file lines (stages
    /// name a bad row by them); a Parquet table numbers its rows.
    #[test]
    fn csv_keeps_its_lines_and_parquet_numbers_its_rows() {
        use hypercontact_core::RowPlace;
        let dir = std::env::temp_dir().join(format!("hc-io-lines-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let csv = dir.join("t.csv");
        std::fs::write(&csv, "# made by hand\nx\n\n1.5\n").unwrap();
        let (table, lines) = RunnerReader.read_table_with_lines(&csv).unwrap();
        assert_eq!(table.f64("x").unwrap(), [1.5]);
        assert_eq!(lines.place(0), RowPlace::Line(4));
        let parquet = dir.join("t.parquet");
        write_parquet(&table, std::fs::File::create(&parquet).unwrap()).unwrap();
        let (back, lines) = RunnerReader.read_table_with_lines(&parquet).unwrap();
        assert_eq!(back, table);
        assert_eq!(lines.place(0), RowPlace::Row(1));
        let e = RunnerReader
            .read_table(&dir.join("t.txt"))
            .unwrap_err()
            .to_string();
        assert!(
            e.ends_with("t.txt: cannot read tables from `.txt` files here (CSV only)"),
            "{e}"
        );
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn garbage_is_an_error_not_a_panic() {
        assert!(read_parquet(Cursor::new(b"not parquet".to_vec())).is_err());
    }
}
