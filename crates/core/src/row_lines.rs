//! Where the rows of a table stand in the file they were read from, so a
//! stage checking values names the place of a bad one as an editor numbers
//! it (`line 7`), or, for a file without lines (Parquet, another stage's
//! output), by its 1-based row (`row 3`). Part of the [`crate::ProductReader`]
//! interface: the CSV reader (hypercontact-labfiles) fills it, stages read it.

use std::fmt;

/// File lines for a text file, 1-based row numbers for a table that has no
/// lines.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RowLines(Option<Vec<u64>>);

impl RowLines {
    /// The 1-based file line of every row.
    pub fn from_lines(lines: Vec<u64>) -> Self {
        RowLines(Some(lines))
    }

    /// Where row `row` (0-based) stands, as messages name it.
    pub fn place(&self, row: usize) -> RowPlace {
        match self.0.as_ref().and_then(|lines| lines.get(row)) {
            Some(&line) => RowPlace::Line(line),
            None => RowPlace::Row(row + 1),
        }
    }
}

/// One row's place: `line 7` of a file, or `row 3` of a table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RowPlace {
    /// 1-based file line.
    Line(u64),
    /// 1-based data row.
    Row(usize),
}

impl fmt::Display for RowPlace {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RowPlace::Line(line) => write!(f, "line {line}"),
            RowPlace::Row(row) => write!(f, "row {row}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_name_rows_and_missing_lines_fall_back_to_row_numbers() {
        let lines = RowLines::from_lines(vec![4, 9]);
        assert_eq!(lines.place(1).to_string(), "line 9");
        assert_eq!(lines.place(2).to_string(), "row 3");
        assert_eq!(RowLines::default().place(0).to_string(), "row 1");
    }
}
