//! `hypercontact export`: a finished run's fields as VTK ImageData or its
//! tables as CSV (the work is in the library's `export` module).

use anyhow::Result;
use hypercontact::export::{Format, export_run};

use super::args::{ExportArgs, ExportFormat};

pub fn export(args: &ExportArgs) -> Result<()> {
    let (format, folder) = match args.format {
        ExportFormat::Vtk => (Format::Vtk, "export-vtk"),
        ExportFormat::Csv => (Format::Csv, "export-csv"),
    };
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| args.run_dir.join(folder));
    let exported = export_run(&args.run_dir, &out, format)?;
    for note in &exported.notes {
        eprintln!("note: {note}");
    }
    say!(
        "{} files written in {}",
        exported.written.len(),
        out.display()
    );
    Ok(())
}
