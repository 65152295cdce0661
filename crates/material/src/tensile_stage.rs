//! Stage `tensile-table`: loads UT/PT/BT stress–stretch data from a CSV or
//! Parquet file and validates it for fitting.

use hypercontact_core::{
    Checked, Context, InputPath, Inputs, OutputSpec, Outputs, Stage, StageError, StageInfo, params,
};

pub use crate::tensile::TensilePoints;
use crate::tensile::normalise_table;

/// Parameters of `tensile-table`.
#[params]
pub struct TensileTableParams {
    /// the CSV or Parquet file (columns mode, stretch, nominal_stress_pa)
    pub path: InputPath,
}

/// The `tensile-table` stage.
pub struct TensileTable;

static INFO: StageInfo = StageInfo {
    kind: "tensile-table",
    version: 1,
    summary: "Load UT/PT/BT tensile data (CSV or Parquet) and validate it",
    doc: "Reads a table with columns `mode` (UT, PT or BT; PS is read as PT, ET/EB as BT), \
          `stretch` and `nominal_stress_pa` (force over undeformed area, Pa). Every row is \
          checked: a known mode, no NaN or infinite value, stretch ≥ 1 and strictly increasing \
          within each mode (rows of different modes may interleave). Errors name the file, the \
          data row (1-based, header and `#` comment lines not counted) and the column. Extra \
          columns pass through unchanged. Whether there are enough points for a model is \
          checked by `material-fit`, which knows the model.",
    inputs: &[],
    outputs: &[OutputSpec::table::<TensilePoints>(
        "tensile",
        "the validated data, mode labels made canonical, file order kept",
    )],
};

impl Stage for TensileTable {
    type Params = TensileTableParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<TensileTableParams>,
        _: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let table = ctx.read_table(&p.path)?;
        let origin = p.path.display().to_string();
        let table = normalise_table(&table, &origin).map_err(StageError::other)?;
        ctx.note(&format!(
            "{} tensile points ({})",
            table.n_rows(),
            crate::TensileData::from_table(&table, &origin)
                .map_err(StageError::other)?
                .counts()
        ));
        Ok(Outputs::new().table("tensile", table))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::{DynStage, Params, Product, Schema};
    use std::path::PathBuf;

    fn dir() -> PathBuf {
        let dir = std::env::temp_dir().join(format!(
            "hc-tensile-{}-{:?}",
            std::process::id(),
            std::thread::current().id()
        ));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn run(csv: &str) -> Result<Outputs, StageError> {
        let path = dir().join("tensile.csv");
        std::fs::write(&path, csv).unwrap();
        let p = TensileTableParams { path: path.into() }.check().unwrap();
        TensileTable.run(&p, &Inputs::new(), &Context::new("t"))
    }

    #[test]
    fn loads_a_csv_and_passes_extra_columns() {
        let out =
            run("# comment\nmode,stretch,nominal_stress_pa,frame\nUT,1.1,1e5,1\nPS,1.1,2e5,2\n")
                .unwrap();
        let Some(Product::Table(t)) = out.get("tensile") else {
            panic!("no tensile table")
        };
        t.conform(TensilePoints::COLUMNS).unwrap();
        assert_eq!(t.str("mode").unwrap(), ["UT", "PT"]);
        assert_eq!(t.i64("frame").unwrap(), [1, 2]);
    }

    #[test]
    fn errors_name_the_file_row_and_column() {
        let e = run("mode,stretch,nominal_stress_pa\nUT,1.1,1e5\nUT,1.05,2e5\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("tensile.csv") && e.contains("row 2") && e.contains("`stretch`"),
            "{e}"
        );
        let e = run("mode,stretch,nominal_stress_pa\nUT,1.1,\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("row 1") && e.contains("`nominal_stress_pa`") && e.contains("NaN"),
            "{e}"
        );
        let e = run("mode,strain,nominal_stress_pa\nUT,0.1,1\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("`stretch`") && e.contains("strain"), "{e}");
        let missing = TensileTable
            .params_from_json(serde_json::json!({}), std::path::Path::new("."))
            .unwrap_err();
        assert!(
            missing.message.contains("missing field `path`"),
            "{missing}"
        );
    }
}
