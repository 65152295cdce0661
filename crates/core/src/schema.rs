//! Table schemas declared once: a struct of columns is both the list a stage
//! declares (for the plan's checks and `hypercontact stages`) and the
//! builder and reader of the table.

use crate::{ColumnData, ColumnSpec, DType, Table, TableError};

/// A table as a struct of columns; derive it with [`crate::Schema`].
///
/// ```
/// use hypercontact_core::{Schema, Table};
///
/// /// Two columns of a toy table.
/// #[derive(Schema)]
/// struct Curve {
///     /// plane height
///     #[column(unit = "m")]
///     z_m: Vec<f64>,
///     /// patch count
///     patches: Vec<i64>,
/// }
///
/// assert_eq!(Curve::COLUMNS[0].unit, "m");
/// let table = Curve { z_m: vec![1.0, 0.0], patches: vec![1, 3] }.into_table();
/// assert_eq!(table.column_names(), ["z_m", "patches"]);
/// assert_eq!(Curve::from_table(&table).unwrap().patches, [1, 3]);
///
/// /// A table that is a `Curve` plus a column of its own.
/// #[derive(Schema)]
/// struct LabelledCurve {
///     #[column(flatten)]
///     curve: Curve,
///     /// where the curve came from
///     source: Vec<String>,
/// }
///
/// let names: Vec<&str> = LabelledCurve::COLUMNS.iter().map(|c| c.name).collect();
/// assert_eq!(names, ["z_m", "patches", "source"]);
/// let t = LabelledCurve {
///     curve: Curve { z_m: vec![2.0], patches: vec![1] },
///     source: vec!["a".into()],
/// }
/// .into_table();
/// assert_eq!(t.column_names(), names);
/// assert_eq!(LabelledCurve::from_table(&t).unwrap().curve.z_m, [2.0]);
/// ```
pub trait Schema: Sized {
    /// The columns, in order, with types, units and docs.
    const COLUMNS: &'static [ColumnSpec];

    fn into_table(self) -> Table;

    /// Reads the declared columns (others are ignored); integer columns are
    /// accepted where numbers are declared, as CSV files give them.
    fn from_table(table: &Table) -> Result<Self, TableError>;
}

/// The Rust type of one column.
pub trait ColumnType: Sized {
    const DTYPE: DType;
    fn into_column(self) -> ColumnData;
    fn read(table: &Table, name: &str) -> Result<Self, TableError>;
}

impl ColumnType for Vec<f64> {
    const DTYPE: DType = DType::F64;

    fn into_column(self) -> ColumnData {
        ColumnData::F64(self)
    }

    fn read(table: &Table, name: &str) -> Result<Self, TableError> {
        table.to_f64(name)
    }
}

impl ColumnType for Vec<i64> {
    const DTYPE: DType = DType::I64;

    fn into_column(self) -> ColumnData {
        ColumnData::I64(self)
    }

    fn read(table: &Table, name: &str) -> Result<Self, TableError> {
        table.i64(name).map(<[i64]>::to_vec)
    }
}

impl ColumnType for Vec<String> {
    const DTYPE: DType = DType::Str;

    fn into_column(self) -> ColumnData {
        ColumnData::Str(self)
    }

    fn read(table: &Table, name: &str) -> Result<Self, TableError> {
        table.str(name).map(<[String]>::to_vec)
    }
}
