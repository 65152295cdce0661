//! Writes a report from synthetic inputs into a folder, to look at:
//! `cargo run -p hypercontact-report --release --example demo -- OUT_DIR [MAP_N LEVELS]`.

#[path = "../tests/common/mod.rs"]
mod common;

use hypercontact_report::{ReportOptions, render_report};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let out = std::path::PathBuf::from(args.get(1).map_or("report-demo", String::as_str));
    let map_n = args.get(2).map_or(Ok(200), |s| s.parse())?;
    let levels = args.get(3).map_or(Ok(1000), |s| s.parse())?;
    let inputs = common::with_bands(common::inputs(common::ALL, map_n, levels), levels);
    let start = std::time::Instant::now();
    let files = render_report(&inputs, &ReportOptions::default(), None)?;
    eprintln!("rendered in {:.3} s", start.elapsed().as_secs_f64());
    std::fs::create_dir_all(&out)?;
    for (name, bytes) in &files.files {
        std::fs::write(out.join(name), bytes)?;
    }
    Ok(())
}
