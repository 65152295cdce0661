//! A table as CSV for spreadsheets: RFC 4180 quoting, a first line of
//! column names and a second of their units, then one line per row.
//!
//! Numbers are written in Rust's shortest form that reads back to the same
//! float (`0.1`, `1e-7`), so the CSV holds exactly the table's values; a
//! missing value (NaN) is `NaN` and infinities are `inf` and `-inf`, which
//! pandas, polars and LibreOffice read as such.

use hypercontact_core::{ColumnData, Table};

/// A cell quoted if it holds a separator, a quote or a line break.
fn cell(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) || text != text.trim() {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_owned()
    }
}

/// A float as it reads back: plain digits for everyday magnitudes, the
/// exponent form outside them (Rust's `{}` never uses an exponent and would
/// write 1e-300 with 300 zeros).
pub fn number(v: f64) -> String {
    if v.is_nan() {
        "NaN".to_owned()
    } else if v == f64::INFINITY {
        "inf".to_owned()
    } else if v == f64::NEG_INFINITY {
        "-inf".to_owned()
    } else if v == 0.0 || (1e-4..1e15).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// The CSV text of `table`, with `units[i]` the unit of column `i`.
pub fn csv_text(table: &Table, units: &[String]) -> String {
    let columns = table.columns();
    let mut out = String::new();
    let names: Vec<String> = table.column_names().into_iter().map(cell).collect();
    out.push_str(&names.join(","));
    out.push('\n');
    let units: Vec<String> = (0..columns.len())
        .map(|i| cell(units.get(i).map_or("", String::as_str)))
        .collect();
    out.push_str(&units.join(","));
    out.push('\n');
    for row in 0..table.n_rows() {
        let cells: Vec<String> = columns
            .iter()
            .map(|c| match &c.data {
                ColumnData::F64(v) => number(v[row]),
                ColumnData::I64(v) => v[row].to_string(),
                ColumnData::Str(v) => cell(&v[row]),
            })
            .collect();
        out.push_str(&cells.join(","));
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Read back with the `csv` crate (an independent RFC 4180 reader), the
    /// names, units and every value equal the table's, NaN where NaN.
    #[test]
    fn csv_reads_back_to_the_table() {
        let floats = vec![0.1, -1e-300, f64::NAN, 1.0 / 3.0, 6.02e23, f64::INFINITY];
        let table = Table::new()
            .with("load_n", floats.clone())
            .with("step", vec![0_i64, 1, -2, 3, i64::MAX, 5])
            .with(
                "label",
                vec!["a", "b,c", "say \"hi\"", "two\nlines", " pad", ""]
                    .into_iter()
                    .map(String::from)
                    .collect::<Vec<_>>(),
            );
        let units = vec!["N".to_owned(), String::new(), String::new()];
        let text = csv_text(&table, &units);
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(false)
            .from_reader(text.as_bytes());
        let rows: Vec<csv::StringRecord> = reader.records().map(|r| r.unwrap()).collect();
        assert_eq!(rows.len(), 8);
        assert_eq!(
            rows[0].iter().collect::<Vec<_>>(),
            ["load_n", "step", "label"]
        );
        assert_eq!(rows[1].iter().collect::<Vec<_>>(), ["N", "", ""]);
        let ColumnData::Str(labels) = &table.columns()[2].data else {
            panic!()
        };
        for (i, row) in rows[2..].iter().enumerate() {
            let back: f64 = row[0].parse().unwrap();
            assert!(
                back.to_bits() == floats[i].to_bits() || (back.is_nan() && floats[i].is_nan()),
                "row {i}: {} from {}",
                back,
                &row[0]
            );
            assert_eq!(
                row[1].parse::<i64>().unwrap(),
                table.i64("step").unwrap()[i]
            );
            assert_eq!(&row[2], labels[i].as_str());
        }
    }
}
