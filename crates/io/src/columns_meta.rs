//! Units and descriptions that travel inside a Parquet file (issue #34,
//! "Units travel with the data").
//!
//! A table written from a declaration ([`ColumnSpec`]s, the same ones
//! `hypercontact stages KIND` prints) carries one file key-value entry,
//! [`COLUMNS_KEY`], whose value is compact JSON: an array, in the table's
//! column order, of `{"name", "unit", "doc"}` for every column the
//! declaration names. File-level metadata rather than Arrow field metadata
//! because polars' `ParquetWriter` writes only the former. Python reads it
//! with `pl.read_parquet_metadata(path)` (polars) or
//! `pq.read_metadata(path).metadata` (pyarrow). Not pyarrow's
//! `read_schema(path).metadata`: pyarrow takes a schema's metadata from the
//! Arrow schema polars stores beside it (`ARROW:schema`), which has none.

use hypercontact_core::{ColumnSpec, Table};
use serde::{Deserialize, Serialize};

/// The key of the file metadata entry that holds the columns' units and docs.
pub const COLUMNS_KEY: &str = "hypercontact:columns";

/// One column's unit (empty for a dimensionless number or a label) and
/// description, as stored in and read back from a Parquet file.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ColumnMeta {
    pub name: String,
    pub unit: String,
    pub doc: String,
}

impl From<&ColumnSpec> for ColumnMeta {
    fn from(spec: &ColumnSpec) -> Self {
        Self {
            name: spec.name.to_owned(),
            unit: spec.unit.to_owned(),
            doc: spec.doc.to_owned(),
        }
    }
}

/// The declared columns of `table`, in the table's order; a column the
/// declaration does not name (a constant a study adds) is left out.
pub fn described_columns(table: &Table, columns: &[ColumnSpec]) -> Vec<ColumnMeta> {
    table
        .column_names()
        .into_iter()
        .filter_map(|name| columns.iter().find(|spec| spec.name == name))
        .map(ColumnMeta::from)
        .collect()
}

/// The value stored under [`COLUMNS_KEY`]: compact JSON, fields in the
/// struct's order, so the same declaration gives the same bytes.
pub fn encode(columns: &[ColumnMeta]) -> String {
    serde_json::to_string(columns).expect("strings always serialise")
}

/// Parses a value stored under [`COLUMNS_KEY`].
pub fn decode(value: &str) -> Result<Vec<ColumnMeta>, serde_json::Error> {
    serde_json::from_str(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn undeclared_columns_are_left_out_and_table_order_is_kept() {
        let declared = [
            ColumnSpec::f64("load_n", "N", "total normal load"),
            ColumnSpec::str("sample", "which sample"),
            ColumnSpec::f64("unused_m", "m", "a column this table lacks"),
        ];
        let table = Table::new()
            .with("sample", vec!["T1"])
            .with("icm.model", vec!["greenwood"])
            .with("load_n", vec![1.5]);
        let meta = described_columns(&table, &declared);
        let names: Vec<&str> = meta.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["sample", "load_n"]);
        assert_eq!(meta[1].unit, "N");
        assert_eq!(meta[0].unit, "");
        assert_eq!(
            encode(&meta),
            r#"[{"name":"sample","unit":"","doc":"which sample"},{"name":"load_n","unit":"N","doc":"total normal load"}]"#
        );
        assert_eq!(decode(&encode(&meta)).unwrap(), meta);
    }

    #[test]
    fn a_value_that_is_not_the_array_is_an_error() {
        assert!(decode("{\"name\":\"x\"}").is_err());
        assert!(decode("[{\"name\":\"x\"}]").is_err());
        assert!(decode("not json").is_err());
    }
}
