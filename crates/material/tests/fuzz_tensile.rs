//! Property tests of the tensile-table reader and what follows it: valid
//! tables with comment and blank lines, then bad values, broken lines and
//! changed bytes, through `tensile-table` (the CSV reader and the
//! validation) and a quick `material-fit`. Never a panic; every error names
//! the file, and a single bad value names the line it is on.
//!
//! Bounded for CI: a fixed seed and a few hundred cases per property;
//! `PROPTEST_CASES` and `PROPTEST_RNG_SEED` widen or move the search.

use std::path::PathBuf;

use hypercontact_core::{Context, Inputs, Params, Product, Stage, StageError, Table};
use hypercontact_fuzz::{config, splice};
use hypercontact_material::fit_stage::{MaterialFit, MaterialFitParams};
use hypercontact_material::tensile_stage::{TensileTable, TensileTableParams};
use hypercontact_material::{Family, TensileData};
use proptest::prelude::*;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hc-fuzz-tensile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Runs `tensile-table` on `text` written to `path`.
fn load(path: &PathBuf, text: &[u8]) -> Result<Table, StageError> {
    std::fs::write(path, text).unwrap();
    let p = TensileTableParams {
        path: path.clone().into(),
    }
    .check()
    .unwrap();
    // The CSV reader the runner lends (core's own reads fields only).
    let ctx = Context::with("tensile", None, &hypercontact_labfiles::LabReader);
    let out = TensileTable.run(&p, &Inputs::new(), &ctx)?;
    match out.get("tensile") {
        Some(Product::Table(t)) => Ok(t.clone()),
        _ => panic!("tensile-table gave no table"),
    }
}

/// A line of a generated file.
#[derive(Clone, Debug)]
enum Line {
    Comment(String),
    Blank,
    /// mode, stretch, stress as written
    Row([String; 3]),
}

/// A valid tensile table: the header, then 1…3 modes (labels in any
/// accepted spelling) of 1…12 points each with stretch rising from 1 and
/// positive stress (a mode may start at the reference state `1,0`),
/// comment and blank lines anywhere.
fn valid_table() -> impl Strategy<Value = Vec<Line>> {
    let curve = (
        prop_oneof![
            Just("UT"),
            Just("ut"),
            Just("PT"),
            Just("PS"),
            Just("BT"),
            Just("ET"),
            Just("EB")
        ],
        any::<bool>(),
        prop::collection::vec((1e-3f64..0.3, 1e3f64..1e7), 1..12),
    )
        .prop_map(|(mode, reference, steps)| {
            let mut rows = Vec::new();
            if reference {
                rows.push([mode.to_owned(), "1".to_owned(), "0".to_owned()]);
            }
            let mut stretch = 1.0;
            for (step, stress) in steps {
                stretch += step;
                rows.push([mode.to_owned(), stretch.to_string(), stress.to_string()]);
            }
            rows
        });
    (
        prop::collection::vec(curve, 1..4),
        prop::collection::vec(
            prop_oneof![
                6 => Just(None),
                1 => "#[ -~]{0,16}".prop_map(|c| Some(Line::Comment(c))),
                1 => Just(Some(Line::Blank)),
            ],
            40,
        ),
    )
        .prop_map(|(curves, extras)| {
            // Curves of one mode label twice would not rise: keep one each.
            let mut seen = Vec::new();
            let mut lines = vec![Line::Comment("# exported by the rig".into())];
            lines.push(Line::Row([
                "mode".into(),
                "stretch".into(),
                "nominal_stress_pa".into(),
            ]));
            let mut extras = extras.into_iter().cycle();
            for rows in curves {
                let mode = rows[0][0].to_ascii_uppercase();
                let canonical = match mode.as_str() {
                    "PS" => "PT".to_owned(),
                    "ET" | "EB" => "BT".to_owned(),
                    m => m.to_owned(),
                };
                if seen.contains(&canonical) {
                    continue;
                }
                seen.push(canonical);
                for row in rows {
                    if let Some(Some(extra)) = extras.next() {
                        lines.push(extra);
                    }
                    lines.push(Line::Row(row));
                }
            }
            lines
        })
}

fn render(lines: &[Line]) -> String {
    let mut text = String::new();
    for line in lines {
        match line {
            Line::Comment(c) => text.push_str(c),
            Line::Blank => {}
            Line::Row(cells) => text.push_str(&cells.join(",")),
        }
        text.push('\n');
    }
    text
}

/// Values a spreadsheet or a careless export puts in a cell.
fn bad_token() -> impl Strategy<Value = String> {
    prop_oneof![
        Just(String::new()),
        Just("NaN".into()),
        Just("inf".into()),
        Just("-inf".into()),
        Just("1e400".into()),
        Just("-1e5".into()),
        Just("0".into()),
        Just("-0".into()),
        Just("0.5".into()),
        Just("1,5".into()),
        Just("\"1.2\"".into()),
        Just("\"".into()),
        Just("#".into()),
        Just("abc".into()),
        Just("XT".into()),
        Just("1.2 MPa".into()),
        Just("１".into()),
        "[ -~]{0,6}",
    ]
}

/// Line-level edits: a cell replaced, a line deleted, doubled or swapped
/// with the next; then byte splices.
#[derive(Clone, Debug)]
enum Edit {
    Cell(usize, usize, String),
    Delete(usize),
    Double(usize),
    Swap(usize),
}

fn edits() -> impl Strategy<Value = Vec<Edit>> {
    prop::collection::vec(
        prop_oneof![
            3 => (any::<usize>(), 0usize..3, bad_token()).prop_map(|(l, c, t)| Edit::Cell(l, c, t)),
            1 => any::<usize>().prop_map(Edit::Delete),
            1 => any::<usize>().prop_map(Edit::Double),
            1 => any::<usize>().prop_map(Edit::Swap),
        ],
        1..4,
    )
}

fn apply(mut lines: Vec<Line>, edits: &[Edit]) -> Vec<Line> {
    for edit in edits {
        let n = lines.len();
        match edit {
            Edit::Cell(l, c, token) => {
                if let Line::Row(cells) = &mut lines[l % n] {
                    cells[*c] = token.clone();
                }
            }
            Edit::Delete(l) => {
                lines.remove(l % n);
            }
            Edit::Double(l) => {
                let line = lines[l % n].clone();
                lines.insert(l % n, line);
            }
            Edit::Swap(l) => lines.swap(l % n, (l + 1) % n),
        }
        if lines.is_empty() {
            break;
        }
    }
    lines
}

fn splices() -> impl Strategy<Value = Vec<(usize, usize, Vec<u8>)>> {
    prop::collection::vec(
        (
            any::<usize>(),
            0usize..4,
            prop::collection::vec(any::<u8>(), 0..3),
        ),
        0..3,
    )
}

/// Fits a quick model to a loaded table; a failure must name the model.
fn quick_fit(table: Table, family: Family) {
    let inputs = Inputs::new().with("tensile", Product::Table(table));
    let p = MaterialFitParams {
        model: family,
        starts: 2,
        compare: false,
        ..Default::default()
    }
    .check()
    .unwrap();
    if let Err(e) = MaterialFit.run(&p, &inputs, &Context::new("fit")) {
        let message = e.to_string();
        assert!(
            message.contains(&family.name()) || message.contains("input `tensile`"),
            "{message}"
        );
    }
}

proptest! {
    #![proptest_config(config(192))]

    #[test]
    fn valid_tables_load_with_every_point(lines in valid_table()) {
        let table = load(&scratch("valid.csv"), render(&lines).as_bytes()).unwrap();
        let rows = lines.iter().filter(|l| matches!(l, Line::Row(_))).count() - 1;
        prop_assert_eq!(table.n_rows(), rows);
        prop_assert_eq!(TensileData::from_table(&table, "x").unwrap().n_points(), rows);
    }

    #[test]
    fn edited_tables_never_panic_and_errors_name_the_file(
        lines in valid_table(),
        edits in edits(),
        bytes in splices(),
        family in prop_oneof![
            Just(Family::NeoHookean),
            Just(Family::MooneyRivlin),
            Just(Family::Yeoh),
            Just(Family::Ogden(1)),
            Just(Family::Ogden(2)),
        ],
    ) {
        let path = scratch("edited.csv");
        let text = splice(render(&apply(lines, &edits)).into_bytes(), &bytes);
        match load(&path, &text) {
            Ok(table) => quick_fit(table, family),
            Err(e) => {
                let message = e.to_string();
                prop_assert!(
                    message.contains(&path.display().to_string()),
                    "the error does not name the file: {}",
                    message
                );
            }
        }
    }

    /// One bad value in an otherwise valid table: the error names the
    /// file, the line the value is on (comments and blank lines counted)
    /// and its column.
    #[test]
    fn a_single_bad_value_is_named_by_its_line_and_column(
        lines in valid_table(),
        pick in any::<usize>(),
        kind in 0usize..4,
    ) {
        let data: Vec<usize> = lines
            .iter()
            .enumerate()
            .filter(|(_, l)| matches!(l, Line::Row(_)))
            .map(|(i, _)| i)
            .skip(1)
            .collect();
        let at = data[pick % data.len()];
        let mut lines = lines;
        let Line::Row(cells) = &mut lines[at] else { unreachable!() };
        let stretch: f64 = cells[1].parse().unwrap();
        let (column, token) = match kind {
            0 => (1, "1.2.3".to_owned()),
            1 => (2, "12 kPa".to_owned()),
            2 => (0, "XT".to_owned()),
            // Compressive: refused where the stretch is above 1.
            _ if stretch > 1.0 => (2, "-1e9".to_owned()),
            _ => (1, "0.5".to_owned()),
        };
        cells[column] = token.clone();
        let path = scratch("one-bad.csv");
        let message = load(&path, render(&lines).as_bytes()).unwrap_err().to_string();
        let name = ["mode", "stretch", "nominal_stress_pa"][column];
        prop_assert!(
            message.contains(&format!("{}: line {}, column `{name}`", path.display(), at + 1)),
            "line {}, `{}` in `{}`: {}",
            at + 1,
            token,
            name,
            message
        );
    }
}
