//! Tensile test data: nominal stress against stretch in uniaxial (UT),
//! planar (PT) and equibiaxial (BT) tension, as the `tensile` table carries
//! it (columns `mode`, `stretch`, `nominal_stress_pa`), validated so that a
//! fit can trust it.

use hypercontact_core::{ColumnData, RowLines, RowPlace, Schema, Table};

use crate::{MaterialError, Mode};

/// Relative errors divide by max(|T|, this × the mode's largest |T|), so a
/// point at λ ≈ 1 with T ≈ 0 does not dominate a relative fit.
pub const RELATIVE_FLOOR: f64 = 0.01;

/// The `tensile` table (the DIC stage emits the same columns).
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct TensilePoints {
    /// UT (uniaxial), PT (planar / pure shear) or BT (equibiaxial)
    pub mode: Vec<String>,
    /// loading stretch λ ≥ 1, increasing within a mode
    #[column(unit = "1")]
    pub stretch: Vec<f64>,
    /// nominal (first Piola–Kirchhoff) stress: force over undeformed area
    #[column(unit = "Pa")]
    pub nominal_stress_pa: Vec<f64>,
}

/// One mode's curve, stretch strictly increasing from ≥ 1.
#[derive(Clone, Debug, PartialEq)]
pub struct TensileCurve {
    pub mode: Mode,
    pub stretch: Vec<f64>,
    pub stress_pa: Vec<f64>,
}

impl TensileCurve {
    pub fn len(&self) -> usize {
        self.stretch.len()
    }

    pub fn is_empty(&self) -> bool {
        self.stretch.is_empty()
    }

    /// The denominators of relative errors, Pa (see [`RELATIVE_FLOOR`]).
    pub fn relative_scales_pa(&self) -> Vec<f64> {
        let max = self.stress_pa.iter().fold(0.0_f64, |m, t| m.max(t.abs()));
        let floor = (RELATIVE_FLOOR * max).max(f64::MIN_POSITIVE);
        self.stress_pa.iter().map(|t| t.abs().max(floor)).collect()
    }
}

/// The curves of one material, in the order UT, PT, BT (absent modes left
/// out).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TensileData {
    pub curves: Vec<TensileCurve>,
}

impl TensileData {
    pub fn curve(&self, mode: Mode) -> Option<&TensileCurve> {
        self.curves.iter().find(|c| c.mode == mode)
    }

    pub fn n_points(&self) -> usize {
        self.curves.iter().map(TensileCurve::len).sum()
    }

    /// Adds another data set's points: curves of a mode already present are
    /// extended (repeat tests of one mode fit together).
    pub fn extend(&mut self, other: TensileData) {
        for curve in other.curves {
            match self.curves.iter_mut().find(|c| c.mode == curve.mode) {
                Some(mine) => {
                    mine.stretch.extend(curve.stretch);
                    mine.stress_pa.extend(curve.stress_pa);
                }
                None => self.curves.push(curve),
            }
        }
        self.curves
            .sort_by_key(|c| Mode::ALL.iter().position(|m| *m == c.mode));
    }

    /// "UT 24, PT 13, BT 16": the point counts for messages.
    pub fn counts(&self) -> String {
        Mode::ALL
            .iter()
            .map(|&m| format!("{m} {}", self.curve(m).map_or(0, TensileCurve::len)))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The `tensile` table, modes in the order UT, PT, BT.
    pub fn to_table(&self) -> Table {
        let mut points = TensilePoints {
            mode: Vec::new(),
            stretch: Vec::new(),
            nominal_stress_pa: Vec::new(),
        };
        for c in &self.curves {
            let label = c.mode.label().to_owned();
            points.mode.extend(std::iter::repeat_n(label, c.len()));
            points.stretch.extend_from_slice(&c.stretch);
            points.nominal_stress_pa.extend_from_slice(&c.stress_pa);
        }
        points.into_table()
    }

    /// Reads and validates a `tensile` table; `origin` (a file or an input
    /// name) heads every error, which also names the row and column.
    pub fn from_table(table: &Table, origin: &str) -> Result<Self, MaterialError> {
        let rows = validate(table, origin, &RowLines::default())?;
        let mut data = TensileData::default();
        for mode in Mode::ALL {
            let (stretch, stress_pa): (Vec<f64>, Vec<f64>) = rows
                .iter()
                .filter(|r| r.0 == mode)
                .map(|r| (r.1, r.2))
                .unzip();
            if !stretch.is_empty() {
                data.curves.push(TensileCurve {
                    mode,
                    stretch,
                    stress_pa,
                });
            }
        }
        Ok(data)
    }
}

fn error(origin: &str, place: Option<RowPlace>, column: &str, message: String) -> MaterialError {
    MaterialError::Tensile {
        origin: origin.to_owned(),
        place,
        column: column.to_owned(),
        message,
    }
}

/// A numeric column; a text cell is an error naming its place.
fn numeric(
    table: &Table,
    origin: &str,
    lines: &RowLines,
    name: &str,
) -> Result<Vec<f64>, MaterialError> {
    let column = table
        .column(name)
        .map_err(|e| error(origin, None, name, e.to_string()))?;
    column.to_f64().map_err(|bad| {
        error(
            origin,
            Some(lines.place(bad.row)),
            name,
            format!("`{}` is not a number", bad.text),
        )
    })
}

/// Checks every row and returns (mode, stretch, stress) in table order;
/// `lines` places the rows in their file for messages.
fn validate(
    table: &Table,
    origin: &str,
    lines: &RowLines,
) -> Result<Vec<(Mode, f64, f64)>, MaterialError> {
    table
        .validate()
        .map_err(|e| error(origin, None, "*", e.to_string()))?;
    let labels = table
        .str("mode")
        .map_err(|e| error(origin, None, "mode", e.to_string()))?;
    let stretch = numeric(table, origin, lines, "stretch")?;
    let stress = numeric(table, origin, lines, "nominal_stress_pa")?;
    if labels.is_empty() {
        return Err(error(origin, None, "mode", "the table has no rows".into()));
    }
    let mut last: [Option<(usize, f64)>; 3] = [None; 3];
    let mut rows = Vec::with_capacity(labels.len());
    for (i, label) in labels.iter().enumerate() {
        let row = Some(lines.place(i));
        let mode = Mode::from_label(label).ok_or_else(|| {
            error(
                origin,
                row,
                "mode",
                format!("unknown mode `{label}` (expected UT, PT or BT)"),
            )
        })?;
        let (l, t) = (stretch[i], stress[i]);
        if !l.is_finite() {
            return Err(error(
                origin,
                row,
                "stretch",
                format!("is {l}, not a number"),
            ));
        }
        if !t.is_finite() {
            return Err(error(
                origin,
                row,
                "nominal_stress_pa",
                if t.is_nan() {
                    format!(
                        "is {t}, not a number (a DIC run without force.csv measures strain \
                         only: give its folder the force log, columns time_s, force_n)"
                    )
                } else {
                    format!("is {t}, not a number")
                },
            ));
        }
        if l < 1.0 {
            return Err(error(
                origin,
                row,
                "stretch",
                format!("{l} is below 1: tension tests need stretch ≥ 1"),
            ));
        }
        let slot = &mut last[mode as usize];
        if let Some((previous_row, previous)) = *slot
            && l <= previous
        {
            return Err(error(
                origin,
                row,
                "stretch",
                format!(
                    "{l} does not increase past {previous} ({}, the previous {mode} row): \
                     stretch must increase strictly within each mode",
                    lines.place(previous_row)
                ),
            ));
        }
        *slot = Some((i, l));
        rows.push((mode, l, t));
    }
    refuse_compression(&rows, origin, lines)?;
    Ok(rows)
}

/// Every mode of the table stretches the specimen (λ ≥ 1), so its nominal
/// stress is tensile: a negative one at λ > 1 is a sign or unit mistake, not
/// a material. Load-cell noise around the unloaded state can dip below
/// zero, so negative values within [`RELATIVE_FLOOR`] of the mode's largest
/// |T| (what relative residuals already treat as zero) pass.
fn refuse_compression(
    rows: &[(Mode, f64, f64)],
    origin: &str,
    lines: &RowLines,
) -> Result<(), MaterialError> {
    let mut largest = [0.0_f64; 3];
    for &(mode, _, t) in rows {
        largest[mode as usize] = largest[mode as usize].max(t.abs());
    }
    let bad = rows.iter().enumerate().find(|(_, (mode, l, t))| {
        *l > 1.0 && *t < 0.0 && -t > RELATIVE_FLOOR * largest[*mode as usize]
    });
    match bad {
        Some((i, &(mode, l, t))) => Err(error(
            origin,
            Some(lines.place(i)),
            "nominal_stress_pa",
            format!(
                "{t} Pa is compressive at stretch {l} in a {mode} tension test: a sign or unit \
                 mistake (below zero only noise is accepted, within {}% of the mode's largest \
                 |stress|, {:e} Pa)",
                100.0 * RELATIVE_FLOOR,
                largest[mode as usize]
            ),
        )),
        None => Ok(()),
    }
}

/// The validated table with canonical mode labels (UT/PT/BT) and float
/// `stretch` / `nominal_stress_pa` columns; other columns pass through.
/// `lines` places the rows in their file for messages (the default numbers
/// them as rows).
pub fn normalise_table(
    table: &Table,
    origin: &str,
    lines: &RowLines,
) -> Result<Table, MaterialError> {
    let rows = validate(table, origin, lines)?;
    let mut out = Table::new();
    for column in table.columns() {
        let data = match column.name.as_str() {
            "mode" => ColumnData::from(rows.iter().map(|r| r.0.label()).collect::<Vec<_>>()),
            "stretch" => ColumnData::F64(rows.iter().map(|r| r.1).collect()),
            "nominal_stress_pa" => ColumnData::F64(rows.iter().map(|r| r.2).collect()),
            _ => column.data.clone(),
        };
        out.push(&column.name, data);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(modes: Vec<&str>, stretch: Vec<f64>, stress: Vec<f64>) -> Table {
        Table::new()
            .with("mode", modes)
            .with("stretch", stretch)
            .with("nominal_stress_pa", stress)
    }

    fn message(t: &Table) -> String {
        TensileData::from_table(t, "data/t.csv")
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn splits_modes_and_keeps_order() {
        let t = table(
            vec!["UT", "BT", "ut", "ET"],
            vec![1.1, 1.05, 1.3, 1.2],
            vec![1e5, 2e5, 2e5, 3e5],
        );
        let d = TensileData::from_table(&t, "x").unwrap();
        assert_eq!(d.curves.len(), 2);
        assert_eq!(d.curve(Mode::Uniaxial).unwrap().stretch, [1.1, 1.3]);
        assert_eq!(d.curve(Mode::Equibiaxial).unwrap().stress_pa, [2e5, 3e5]);
        assert_eq!(d.counts(), "UT 2, PT 0, BT 2");
        let n = normalise_table(&t, "x", &RowLines::default()).unwrap();
        assert_eq!(n.str("mode").unwrap(), ["UT", "BT", "UT", "BT"]);
    }

    #[test]
    fn integer_columns_and_extra_columns_pass() {
        let t = Table::new()
            .with("mode", vec!["PT", "PT"])
            .with("stretch", vec![1_i64, 2])
            .with("nominal_stress_pa", vec![0_i64, 100_000])
            .with("frame", vec![3_i64, 4]);
        let n = normalise_table(&t, "x", &RowLines::default()).unwrap();
        assert_eq!(n.f64("stretch").unwrap(), [1.0, 2.0]);
        assert_eq!(n.i64("frame").unwrap(), [3, 4]);
    }

    #[test]
    fn every_validation_error_names_file_row_and_column() {
        let e = message(&table(vec!["UT", "XT"], vec![1.1, 1.2], vec![1.0, 2.0]));
        assert!(
            e.contains("data/t.csv")
                && e.contains("row 2")
                && e.contains("`mode`")
                && e.contains("XT"),
            "{e}"
        );
        let e = message(&table(
            vec!["UT", "UT"],
            vec![1.1, f64::NAN],
            vec![1.0, 2.0],
        ));
        assert!(
            e.contains("row 2") && e.contains("`stretch`") && e.contains("NaN"),
            "{e}"
        );
        let e = message(&table(
            vec!["UT", "UT"],
            vec![1.1, 1.2],
            vec![f64::NAN, 2.0],
        ));
        assert!(
            e.contains("row 1") && e.contains("`nominal_stress_pa`") && e.contains("force.csv"),
            "{e}"
        );
        let e = message(&table(vec!["UT", "UT"], vec![0.9, 1.2], vec![1.0, 2.0]));
        assert!(e.contains("row 1") && e.contains("below 1"), "{e}");
        // Decreasing within a mode, even with another mode in between.
        let e = message(&table(
            vec!["UT", "BT", "UT"],
            vec![1.3, 1.1, 1.2],
            vec![1.0, 2.0, 3.0],
        ));
        assert!(
            e.contains("row 3") && e.contains("row 1") && e.contains("increase"),
            "{e}"
        );
        // Equal stretch twice is not strictly increasing.
        let e = message(&table(vec!["PT", "PT"], vec![1.2, 1.2], vec![1.0, 2.0]));
        assert!(e.contains("row 2"), "{e}");
        let e = message(
            &Table::new()
                .with("mode", vec!["UT"])
                .with("stretch", vec![1.1]),
        );
        assert!(
            e.contains("`nominal_stress_pa`") && e.contains("data/t.csv"),
            "{e}"
        );
        let e = message(&table(vec![], vec![], vec![]));
        assert!(e.contains("no rows"), "{e}");
        let e = message(
            &Table::new()
                .with("mode", vec![1.0])
                .with("stretch", vec![1.1])
                .with("nominal_stress_pa", vec![1.0]),
        );
        assert!(e.contains("`mode`") && e.contains("str"), "{e}");
    }

    #[test]
    fn relative_scales_are_floored() {
        let c = TensileCurve {
            mode: Mode::Uniaxial,
            stretch: vec![1.0, 2.0],
            stress_pa: vec![0.0, 1e6],
        };
        assert_eq!(c.relative_scales_pa(), [1e4, 1e6]);
    }
}
