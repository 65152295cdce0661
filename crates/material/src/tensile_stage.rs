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
    version: 2,
    summary: "Load UT/PT/BT tensile data (CSV or Parquet) and validate it",
    doc: "Reads a table with columns `mode` (UT, PT or BT; PS is read as PT, ET/EB as BT), \
          `stretch` and `nominal_stress_pa` (force over undeformed area, Pa). Every row is \
          checked: a known mode, no NaN or infinite value, stretch ≥ 1 and strictly increasing \
          within each mode (rows of different modes may interleave), and no compressive stress \
          at stretch > 1 (every mode is a tension test, so a negative stress is a sign or unit \
          mistake; dips below zero within 1 % of the mode's largest stress pass as load-cell \
          noise). Errors name the file, the line (of a CSV file, as an editor numbers it: \
          header, `#` comment and blank lines counted; a Parquet file's 1-based row) and the \
          column. Extra \
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
        let (table, lines) = ctx.read_table_with_lines(&p.path)?;
        let origin = p.path.display().to_string();
        let table = normalise_table(&table, &origin, &lines).map_err(StageError::other)?;
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
        // The CSV reader the runner lends (core's own reads fields only).
        let ctx = Context::with("t", None, &hypercontact_labfiles::LabReader);
        TensileTable.run(&p, &Inputs::new(), &ctx)
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
    fn text_in_a_number_names_file_line_column_and_text() {
        let e = run("# c\nmode,stretch,nominal_stress_pa\nUT,1.1,1e5\n\n# c\nUT,abc,2e5\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("tensile.csv: line 6, column `stretch`: `abc` is not a number"),
            "{e}"
        );
        let e = run("mode,stretch,nominal_stress_pa\nUT,1.1,1e5\nUT,1.2,2e5 Pa\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 3, column `nominal_stress_pa`: `2e5 Pa`"),
            "{e}"
        );
    }

    #[test]
    fn empty_and_header_only_files_say_so() {
        let e = run("").unwrap_err().to_string();
        assert!(e.contains("tensile.csv: is empty"), "{e}");
        let e = run("# exported\nmode,stretch,nominal_stress_pa\n\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("tensile.csv: no data rows"), "{e}");
    }

    #[test]
    fn compressive_stress_under_tension_is_refused() {
        let e = run("mode,stretch,nominal_stress_pa\nUT,1.0,0\nUT,1.1,1e5\n# c\nUT,1.5,-2e5\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("tensile.csv: line 5, column `nominal_stress_pa`")
                && e.contains("-200000 Pa is compressive at stretch 1.5")
                && e.contains("UT"),
            "{e}"
        );
        // A whole curve with the wrong sign: its first row is named.
        let e = run("mode,stretch,nominal_stress_pa\nBT,1.1,-1e5\nBT,1.2,-2e5\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 2") && e.contains("BT"), "{e}");
        // Load-cell noise just below zero near λ = 1 is data, and so is the
        // reference state.
        run("mode,stretch,nominal_stress_pa\nPT,1.0,-50\nPT,1.001,-300\nPT,1.3,2e5\n").unwrap();
    }

    #[test]
    fn errors_name_the_file_row_and_column() {
        let e = run("mode,stretch,nominal_stress_pa\nUT,1.1,1e5\nUT,1.05,2e5\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("tensile.csv") && e.contains("line 3") && e.contains("`stretch`"),
            "{e}"
        );
        let e = run("mode,stretch,nominal_stress_pa\nUT,1.1,\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 2") && e.contains("`nominal_stress_pa`") && e.contains("NaN"),
            "{e}"
        );
        let e = run("mode,strain,nominal_stress_pa\nUT,0.1,1\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("`stretch`") && e.contains("strain"), "{e}");
        // Lines as the file numbers them, past comments and blank lines.
        let e =
            run("# rig 2\n\nmode,stretch,nominal_stress_pa\nUT,1.1,1e5\n# pause\n\nUT,1.05,2e5\n")
                .unwrap_err()
                .to_string();
        assert!(e.contains("tensile.csv: line 7, column `stretch`"), "{e}");
        let missing = TensileTable
            .params_from_json(serde_json::json!({}), std::path::Path::new("."))
            .unwrap_err();
        assert!(
            missing.message.contains("missing field `path`"),
            "{missing}"
        );
    }
}
