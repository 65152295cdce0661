//! Column-oriented tables, the unit of exchange between stages.
//!
//! Stages build and read tables of plain vectors; the runner's I/O edge turns
//! them into Parquet. Column names carry their unit (`z_m`, `load_n`,
//! `nominal_stress_pa`), so a table needs no separate unit metadata.

use std::fmt;

use serde::Serialize;

/// The element type of a column.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum DType {
    F64,
    I64,
    Str,
}

impl fmt::Display for DType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            DType::F64 => "f64",
            DType::I64 => "i64",
            DType::Str => "str",
        })
    }
}

/// The values of one column.
#[derive(Clone, Debug, PartialEq)]
pub enum ColumnData {
    F64(Vec<f64>),
    I64(Vec<i64>),
    Str(Vec<String>),
}

impl ColumnData {
    pub fn len(&self) -> usize {
        match self {
            ColumnData::F64(v) => v.len(),
            ColumnData::I64(v) => v.len(),
            ColumnData::Str(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn dtype(&self) -> DType {
        match self {
            ColumnData::F64(_) => DType::F64,
            ColumnData::I64(_) => DType::I64,
            ColumnData::Str(_) => DType::Str,
        }
    }

    /// The values as `f64`: floats as they are, integers converted, text
    /// parsed (an empty cell is NaN, as the CSV reader reads one). The first
    /// cell that is not a number is the error, so a message can name its
    /// row.
    pub fn to_f64(&self) -> Result<Vec<f64>, NotANumber> {
        match self {
            ColumnData::F64(v) => Ok(v.clone()),
            ColumnData::I64(v) => Ok(v.iter().map(|&x| x as f64).collect()),
            ColumnData::Str(v) => v
                .iter()
                .enumerate()
                .map(|(row, text)| match text.trim() {
                    "" => Ok(f64::NAN),
                    t => t.parse().map_err(|_| NotANumber {
                        row,
                        text: text.clone(),
                    }),
                })
                .collect(),
        }
    }

    fn extend(&mut self, other: &ColumnData) -> bool {
        match (self, other) {
            (ColumnData::F64(a), ColumnData::F64(b)) => a.extend_from_slice(b),
            (ColumnData::I64(a), ColumnData::I64(b)) => a.extend_from_slice(b),
            (ColumnData::Str(a), ColumnData::Str(b)) => a.extend_from_slice(b),
            _ => return false,
        }
        true
    }

    fn repeat(&self, row: usize, n: usize) -> ColumnData {
        match self {
            ColumnData::F64(v) => ColumnData::F64(vec![v[row]; n]),
            ColumnData::I64(v) => ColumnData::I64(vec![v[row]; n]),
            ColumnData::Str(v) => ColumnData::Str(vec![v[row].clone(); n]),
        }
    }
}

impl From<Vec<f64>> for ColumnData {
    fn from(v: Vec<f64>) -> Self {
        ColumnData::F64(v)
    }
}

impl From<Vec<i64>> for ColumnData {
    fn from(v: Vec<i64>) -> Self {
        ColumnData::I64(v)
    }
}

impl From<Vec<String>> for ColumnData {
    fn from(v: Vec<String>) -> Self {
        ColumnData::Str(v)
    }
}

impl From<Vec<&str>> for ColumnData {
    fn from(v: Vec<&str>) -> Self {
        ColumnData::Str(v.into_iter().map(str::to_owned).collect())
    }
}

/// A cell that should hold a number and holds text.
#[derive(Clone, Debug, PartialEq)]
pub struct NotANumber {
    /// 0-based row.
    pub row: usize,
    pub text: String,
}

/// A named column.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    pub name: String,
    pub data: ColumnData,
}

/// Why a table could not be read or built as asked.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TableError {
    #[error("no column `{name}` (the table has: {available})")]
    MissingColumn { name: String, available: String },
    #[error("column `{name}` holds {found} values, expected {expected}")]
    WrongType {
        name: String,
        expected: DType,
        found: DType,
    },
    #[error("column `{name}` has {len} rows, the table has {expected}")]
    RaggedColumn {
        name: String,
        len: usize,
        expected: usize,
    },
    #[error("column `{0}` appears twice")]
    DuplicateColumn(String),
}

/// An ordered set of equally long, uniquely named columns.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    columns: Vec<Column>,
}

impl Table {
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends a column (builder style). Lengths and names are checked by
    /// [`Table::validate`], which the runner calls on every stage output.
    pub fn with(mut self, name: &str, data: impl Into<ColumnData>) -> Self {
        self.push(name, data);
        self
    }

    pub fn push(&mut self, name: &str, data: impl Into<ColumnData>) {
        self.columns.push(Column {
            name: name.to_owned(),
            data: data.into(),
        });
    }

    /// Appends every column of `other` after this table's (a flattened
    /// schema's columns, built by its own `into_table`).
    pub fn extend(&mut self, other: Table) {
        self.columns.extend(other.columns);
    }

    /// Checks that column names are unique and all columns are equally long.
    pub fn validate(&self) -> Result<(), TableError> {
        let expected = self.columns.first().map_or(0, |c| c.data.len());
        for (i, c) in self.columns.iter().enumerate() {
            if self.columns[..i].iter().any(|o| o.name == c.name) {
                return Err(TableError::DuplicateColumn(c.name.clone()));
            }
            if c.data.len() != expected {
                return Err(TableError::RaggedColumn {
                    name: c.name.clone(),
                    len: c.data.len(),
                    expected,
                });
            }
        }
        Ok(())
    }

    pub fn n_rows(&self) -> usize {
        self.columns.first().map_or(0, |c| c.data.len())
    }

    pub fn columns(&self) -> &[Column] {
        &self.columns
    }

    pub fn column_names(&self) -> Vec<&str> {
        self.columns.iter().map(|c| c.name.as_str()).collect()
    }

    pub fn column(&self, name: &str) -> Result<&ColumnData, TableError> {
        self.columns
            .iter()
            .find(|c| c.name == name)
            .map(|c| &c.data)
            .ok_or_else(|| TableError::MissingColumn {
                name: name.to_owned(),
                available: self.column_names().join(", "),
            })
    }

    pub fn f64(&self, name: &str) -> Result<&[f64], TableError> {
        match self.column(name)? {
            ColumnData::F64(v) => Ok(v),
            other => Err(wrong_type(name, DType::F64, other)),
        }
    }

    pub fn i64(&self, name: &str) -> Result<&[i64], TableError> {
        match self.column(name)? {
            ColumnData::I64(v) => Ok(v),
            other => Err(wrong_type(name, DType::I64, other)),
        }
    }

    pub fn str(&self, name: &str) -> Result<&[String], TableError> {
        match self.column(name)? {
            ColumnData::Str(v) => Ok(v),
            other => Err(wrong_type(name, DType::Str, other)),
        }
    }

    /// A numeric column as `f64`, whether stored as floats or integers (CSV
    /// files often hold whole numbers in float columns).
    pub fn to_f64(&self, name: &str) -> Result<Vec<f64>, TableError> {
        match self.column(name)? {
            ColumnData::F64(v) => Ok(v.clone()),
            ColumnData::I64(v) => Ok(v.iter().map(|&x| x as f64).collect()),
            other => Err(wrong_type(name, DType::F64, other)),
        }
    }

    /// Checks that every column of `spec` is present with its type.
    pub fn conform(&self, spec: &[crate::ColumnSpec]) -> Result<(), TableError> {
        for c in spec {
            let data = self.column(c.name)?;
            if data.dtype() != c.dtype {
                return Err(wrong_type(c.name, c.dtype, data));
            }
        }
        Ok(())
    }

    /// Prepends constant columns (one value per column, repeated for every
    /// row): how a study tags each variant's rows with its parameters.
    pub fn with_constants(&self, constants: &Table) -> Table {
        let n = self.n_rows();
        let mut columns: Vec<Column> = constants
            .columns
            .iter()
            .map(|c| Column {
                name: c.name.clone(),
                data: c.data.repeat(0, n),
            })
            .collect();
        columns.extend(
            self.columns
                .iter()
                .filter(|c| !constants.columns.iter().any(|k| k.name == c.name))
                .cloned(),
        );
        Table { columns }
    }

    /// Appends the rows of `other`, which must have the same columns in the
    /// same order and types.
    pub fn append(&mut self, other: &Table) -> Result<(), TableError> {
        if self.columns.is_empty() {
            *self = other.clone();
            return Ok(());
        }
        for (mine, theirs) in self.columns.iter().zip(&other.columns) {
            if mine.name != theirs.name {
                return Err(TableError::MissingColumn {
                    name: mine.name.clone(),
                    available: other.column_names().join(", "),
                });
            }
        }
        if self.columns.len() != other.columns.len() {
            let extra = other.columns[self.columns.len().min(other.columns.len())..]
                .first()
                .or(self.columns.get(other.columns.len()))
                .map(|c| c.name.clone())
                .unwrap_or_default();
            return Err(TableError::MissingColumn {
                name: extra,
                available: other.column_names().join(", "),
            });
        }
        for (mine, theirs) in self.columns.iter_mut().zip(&other.columns) {
            let (expected, found) = (mine.data.dtype(), theirs.data.dtype());
            if !mine.data.extend(&theirs.data) {
                return Err(TableError::WrongType {
                    name: mine.name.clone(),
                    expected,
                    found,
                });
            }
        }
        Ok(())
    }
}

fn wrong_type(name: &str, expected: DType, found: &ColumnData) -> TableError {
    TableError::WrongType {
        name: name.to_owned(),
        expected,
        found: found.dtype(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typed_access_names_the_column() {
        let t = Table::new()
            .with("z_m", vec![1.0, 2.0])
            .with("patches", vec![1_i64, 2]);
        assert_eq!(t.f64("z_m").unwrap(), &[1.0, 2.0]);
        let err = t.f64("patches").unwrap_err().to_string();
        assert!(err.contains("`patches`") && err.contains("i64"), "{err}");
        let err = t.f64("load_n").unwrap_err().to_string();
        assert!(
            err.contains("`load_n`") && err.contains("z_m, patches"),
            "{err}"
        );
    }

    #[test]
    fn validate_catches_ragged_and_duplicate_columns() {
        let ragged = Table::new().with("a", vec![1.0]).with("b", vec![1.0, 2.0]);
        assert!(matches!(
            ragged.validate(),
            Err(TableError::RaggedColumn {
                len: 2,
                expected: 1,
                ..
            })
        ));
        let dup = Table::new().with("a", vec![1.0]).with("a", vec![2.0]);
        assert_eq!(dup.validate(), Err(TableError::DuplicateColumn("a".into())));
    }

    #[test]
    fn constants_and_append_build_a_study_table() {
        let part = Table::new().with("x", vec![1.0, 2.0]);
        let tag = Table::new().with("icm.model", vec!["linear"]);
        let mut all = part.with_constants(&tag);
        assert_eq!(all.column_names(), ["icm.model", "x"]);
        assert_eq!(all.str("icm.model").unwrap().len(), 2);
        let other = Table::new()
            .with("x", vec![3.0])
            .with_constants(&Table::new().with("icm.model", vec!["hyperelastic"]));
        all.append(&other).unwrap();
        assert_eq!(all.f64("x").unwrap(), &[1.0, 2.0, 3.0]);
        assert_eq!(all.str("icm.model").unwrap()[2], "hyperelastic");
        let wrong = Table::new()
            .with("icm.model", vec![1.0])
            .with("x", vec![1.0]);
        assert!(all.append(&wrong).is_err());
    }
}
