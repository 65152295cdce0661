//! `hypercontact export`: a finished run's products in formats other tools
//! open. Fields become VTK ImageData for ParaView ([`vti`]), tables CSV for
//! spreadsheets ([`csv`]); the run's own files are read, never changed, and
//! each export is written to a temporary file beside its target and renamed.
//!
//! What a run holds comes from its `provenance.json` (every exported file,
//! per stage). A field is a `NAME.npy` with its `NAME.grid.json`; the maps
//! a contact model hands on are `.npy` files listed in a column
//! `QUANTITY_file` of their index table (`contact_maps.parquet`), with
//! their spacing in the row's `dx_m` and `dy_m`.

pub mod csv;
pub mod units;
pub mod vti;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context as _, Result, bail};
use hypercontact_core::{ColumnData, Field, Table};
use hypercontact_runner::folders;
use hypercontact_runner::provenance::Provenance;

/// What to export.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Vtk,
    Csv,
}

/// What an export wrote, and what it left out and why.
#[derive(Debug, Default)]
pub struct Exported {
    pub written: Vec<PathBuf>,
    pub notes: Vec<String>,
}

/// Exports every field (`Vtk`) or table (`Csv`) of the run in `run_dir`
/// into `out_dir/<stage>/`.
pub fn export_run(run_dir: &Path, out_dir: &Path, format: Format) -> Result<Exported> {
    let record = run_dir.join("provenance.json");
    let provenance = Provenance::load(&record)?;
    check_out_dir(run_dir, out_dir, &provenance)?;
    let mut exported = Exported::default();
    for (stage, files) in stage_files(&provenance) {
        let stage_dir = run_dir.join(&stage);
        let target = out_dir.join(&stage);
        for file in &files {
            let path = stage_dir.join(file);
            if !path.is_file() {
                exported.notes.push(format!(
                    "{}: listed in provenance.json but missing",
                    path.display()
                ));
                continue;
            }
            match (format, file.rsplit_once('.')) {
                (Format::Csv, Some((stem, "parquet"))) => {
                    let out = target.join(format!("{stem}.csv"));
                    write_csv(&path, &out)?;
                    exported.written.push(out);
                }
                (Format::Vtk, Some((stem, "npy"))) if files.contains(&grid_name(stem)) => {
                    let field = hypercontact_runner::store::read_field(
                        &path,
                        &stage_dir.join(grid_name(stem)),
                    )?;
                    let out = target.join(format!("{stem}.vti"));
                    write_vti(&field, units::field_quantity(stem), &out)?;
                    exported.written.push(out);
                }
                (Format::Vtk, Some((_, "parquet"))) => {
                    export_indexed_maps(&path, &stage_dir, &target, &mut exported)?;
                }
                _ => {}
            }
        }
    }
    Ok(exported)
}

/// Refuses an output folder where the export would mix with what it must
/// not touch: a cache (its root or anything inside it: files there break
/// the entries' manifests, and `cache gc` never removes them), the run
/// folder itself, or a folder the run wrote (a stage's, whose files the
/// next run replaces). A folder of its own inside the run folder, such as
/// the default `export-csv`, is fine. Checked as `run` checks `--out`
/// against the cache ([`folders`]).
fn check_out_dir(run_dir: &Path, out_dir: &Path, provenance: &Provenance) -> Result<()> {
    if let Some(cache) = folders::enclosing_cache(out_dir) {
        let at_root =
            folders::part_within(out_dir, &cache).is_some_and(|p| p.as_os_str().is_empty());
        bail!(
            "--out {} {} the cache {}: the export would write among its entries; \
             give a folder outside the cache",
            out_dir.display(),
            if at_root {
                "is the root of"
            } else {
                "lies inside"
            },
            cache.display()
        );
    }
    let Some(below) = folders::part_within(out_dir, run_dir) else {
        return Ok(());
    };
    let first = below
        .components()
        .next()
        .map(|c| c.as_os_str().to_string_lossy());
    match first {
        None => bail!(
            "--out {} is the run folder {} itself: the export would mix with the run's \
             products; give a folder of its own (without --out: export-vtk or export-csv in it)",
            out_dir.display(),
            run_dir.display()
        ),
        Some(name)
            if provenance.stages.contains_key(name.as_ref()) || name == "provenance.json" =>
        {
            bail!(
                "--out {} lies inside {}, which the run wrote: the export would mix with \
                 the run's products; give a folder of its own",
                out_dir.display(),
                run_dir.join(name.as_ref()).display()
            )
        }
        Some(_) => Ok(()),
    }
}

/// The run's files per stage (names inside the stage's folder), in order.
fn stage_files(provenance: &Provenance) -> BTreeMap<String, Vec<String>> {
    let mut out: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for (stage, record) in &provenance.stages {
        for exported in record.outputs.keys() {
            if let Some(file) = exported.strip_prefix(&format!("{stage}/")) {
                out.entry(stage.clone()).or_default().push(file.to_owned());
            }
        }
    }
    out
}

fn grid_name(stem: &str) -> String {
    format!("{stem}.grid.json")
}

/// Every `.npy` map an index table lists in a `QUANTITY_file` column, with
/// the spacing of its row (`dx_m`, `dy_m`); an index without spacing
/// columns lists no maps this can place (a PNG mask's, a tile list's).
fn export_indexed_maps(
    index_path: &Path,
    stage_dir: &Path,
    target: &Path,
    exported: &mut Exported,
) -> Result<()> {
    let table = hypercontact_io::read_parquet_file(index_path)
        .with_context(|| format!("reading {}", index_path.display()))?;
    let (Ok(dx), Ok(dy)) = (table.f64("dx_m"), table.f64("dy_m")) else {
        return Ok(());
    };
    for column in table.columns() {
        let (Some(quantity), ColumnData::Str(files)) =
            (column.name.strip_suffix("_file"), &column.data)
        else {
            continue;
        };
        for (row, file) in files.iter().enumerate() {
            let Some(stem) = file.strip_suffix(".npy") else {
                continue;
            };
            if stem.contains(['/', '\\']) || stem.starts_with('.') {
                exported.notes.push(format!(
                    "{}: row {row} names `{file}`, not a file of the stage's folder; skipped",
                    index_path.display()
                ));
                continue;
            }
            let npy = stage_dir.join(file);
            let reader = std::fs::File::open(&npy).with_context(|| {
                format!("{} (listed in {})", npy.display(), index_path.display())
            })?;
            let field = Field::read_npy(std::io::BufReader::new(reader), dx[row], dy[row])
                .with_context(|| format!("reading {}", npy.display()))?;
            let (_, unit) = units::field_quantity(quantity);
            let out = target.join(format!("{stem}.vti"));
            write_vti(&field, (quantity, unit), &out)?;
            exported.written.push(out);
        }
    }
    Ok(())
}

fn write_vti(field: &Field, (quantity, unit): (&str, &str), out: &Path) -> Result<()> {
    let bytes = vti::vti_bytes(field, &units::array_name(quantity, unit));
    hypercontact_runner::write_atomic(out, &bytes)
        .with_context(|| format!("writing {}", out.display()))
}

/// A Parquet table as CSV: units as the stage declared them in the file
/// (`hypercontact:columns`), else as the column's name says.
fn write_csv(parquet: &Path, out: &Path) -> Result<()> {
    let table: Table = hypercontact_io::read_parquet_file(parquet)
        .with_context(|| format!("reading {}", parquet.display()))?;
    let file = std::fs::File::open(parquet).with_context(|| parquet.display().to_string())?;
    let declared: BTreeMap<String, String> = hypercontact_io::parquet_columns_meta(file)
        .map(|meta| meta.into_iter().map(|m| (m.name, m.unit)).collect())
        .unwrap_or_default();
    let units: Vec<String> = table
        .column_names()
        .into_iter()
        .map(|name| match declared.get(name) {
            Some(unit) if !unit.is_empty() => unit.clone(),
            _ => units::unit_from_name(name).to_owned(),
        })
        .collect();
    let text = csv::csv_text(&table, &units);
    hypercontact_runner::write_atomic(out, text.as_bytes())
        .with_context(|| format!("writing {}", out.display()))
}
