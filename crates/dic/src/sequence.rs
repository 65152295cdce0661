//! The tensile test's raw files, from a `Files` product or a folder of real
//! data, in the layout `synth-tensile` writes:
//! `frames.csv` (`frame, time_s, file`), the images it names (PNG or TIFF,
//! 8 or 16 bit), `force.csv` (`time_s, force_n`) and, optionally,
//! `specimen.json` (`mode`, `gauge_width_m`, `thickness_m`, `pixel_m`,
//! `roi_px`).

use std::borrow::Cow;

use hypercontact_core::csv_table::{RowLines, RowPlace, read_csv_bytes_with_lines};
use hypercontact_core::{ColumnData, FileSource, StageError, Table};
use serde::Deserialize;

use crate::DicError;
use crate::gray::GrayImage;

/// One row of `frames.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameEntry {
    pub frame: i64,
    pub time_s: f64,
    pub file: String,
    /// Where frames.csv lists it (`line 3`).
    pub listed: RowPlace,
}

/// `specimen.json`; every field may be overridden by a parameter.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(default)]
pub struct Specimen {
    pub mode: Option<String>,
    pub gauge_width_m: Option<f64>,
    pub gauge_length_m: Option<f64>,
    pub thickness_m: Option<f64>,
    pub pixel_m: Option<f64>,
    pub roi_px: Option<[usize; 4]>,
    pub bit_depth: Option<u32>,
}

/// The opened test.
pub struct Sequence<'a> {
    source: FileSource<'a>,
    pub frames: Vec<FrameEntry>,
    /// (time_s, force_n), increasing in time.
    pub force: Vec<(f64, f64)>,
    pub specimen: Specimen,
}

impl<'a> Sequence<'a> {
    pub fn open(source: FileSource<'a>) -> Result<Self, DicError> {
        let frames = parse_frames(&Log::read(
            &source,
            "frames.csv",
            &["frame", "time_s", "file"],
        )?)?;
        let force = parse_force(&Log::read(&source, "force.csv", &["time_s", "force_n"])?)?;
        let mut specimen = Specimen::default();
        if source.exists("specimen.json") {
            specimen = serde_json::from_slice(&read(&source, "specimen.json")?).map_err(|e| {
                DicError::file(
                    &source.display("specimen.json"),
                    format!("not a valid specimen description: {e}"),
                )
            })?;
        }
        Ok(Sequence {
            source,
            frames,
            force,
            specimen,
        })
    }

    /// The bytes of file `name`.
    pub fn read(&self, name: &str) -> Result<Cow<'a, [u8]>, DicError> {
        read(&self.source, name)
    }

    /// Decodes frame `k` (index into `frames`).
    pub fn image(&self, k: usize) -> Result<GrayImage, DicError> {
        let entry = &self.frames[k];
        let name = &entry.file;
        if !self.source.exists(name) {
            return Err(DicError::file(
                &self.source.display(name),
                format!("missing (frames.csv lists it on {})", entry.listed),
            ));
        }
        GrayImage::decode(&self.source.display(name), &self.read(name)?)
    }

    /// The force at `t_s` by linear interpolation of the log; an error names
    /// the frame if the log does not cover it.
    pub fn force_at(&self, t_s: f64, frame: &FrameEntry) -> Result<f64, DicError> {
        let (first, last) = (self.force[0].0, self.force[self.force.len() - 1].0);
        let slack = 1e-9 * (1.0 + last.abs());
        if t_s < first - slack || t_s > last + slack {
            return Err(DicError::file(
                &self.source.display("force.csv"),
                format!(
                    "covers {first} … {last} s but frame {} ({}) was taken at {t_s} s",
                    frame.frame, frame.file
                ),
            ));
        }
        let i = self.force.partition_point(|(t, _)| *t < t_s);
        if i == 0 {
            return Ok(self.force[0].1);
        }
        if i >= self.force.len() {
            return Ok(self.force[self.force.len() - 1].1);
        }
        let (t0, f0) = self.force[i - 1];
        let (t1, f1) = self.force[i];
        Ok(f0 + (f1 - f0) * (t_s - t0) / (t1 - t0))
    }
}

/// File `name` of the source; a missing one is an error saying so.
fn read<'a>(source: &FileSource<'a>, name: &str) -> Result<Cow<'a, [u8]>, DicError> {
    if !source.exists(name) {
        return Err(DicError::file(&source.display(name), "missing"));
    }
    source.read(name).map_err(from_source)
}

/// A file error of the source as the crate's error.
fn from_source(e: StageError) -> DicError {
    match e {
        StageError::File { path, message } => DicError::File {
            file: path.display().to_string(),
            message,
        },
        other => DicError::Invalid(other.to_string()),
    }
}

/// A small CSV log with a header, read by the one CSV reader: columns by
/// name (any order, extra columns ignored), a bad cell an error naming the
/// file and line.
struct Log {
    table: Table,
    /// The file line of every row.
    lines: RowLines,
    /// The file as errors show it.
    shown: String,
}

impl Log {
    /// CSV file `name` of the source, with the `columns` and some rows (an
    /// empty or header-only file is the reader's error).
    fn read(source: &FileSource, name: &str, columns: &[&str]) -> Result<Self, DicError> {
        let shown = source.display(name);
        let csv = read_csv_bytes_with_lines(&read(source, name)?, &shown).map_err(from_source)?;
        let log = Log {
            table: csv.table,
            lines: csv.lines,
            shown,
        };
        for column in columns {
            log.column(column)?;
        }
        Ok(log)
    }

    fn rows(&self) -> usize {
        self.table.n_rows()
    }

    fn error(&self, message: String) -> DicError {
        DicError::file(&self.shown, message)
    }

    /// Where data row `row` (0-based) stands in the file: `line 7`.
    fn line(&self, row: usize) -> RowPlace {
        self.lines.place(row)
    }

    fn column(&self, name: &str) -> Result<&ColumnData, DicError> {
        self.table.column(name).map_err(|_| {
            self.error(format!(
                "has no column `{name}` (header: {})",
                self.table.column_names().join(", ")
            ))
        })
    }

    /// Cell `row` of column `name` as text (a number as Rust prints it).
    fn text(&self, name: &str, row: usize) -> Result<String, DicError> {
        Ok(match self.column(name)? {
            ColumnData::F64(v) => v[row].to_string(),
            ColumnData::I64(v) => v[row].to_string(),
            ColumnData::Str(v) => v[row].clone(),
        })
    }

    fn number(&self, name: &str, row: usize) -> Result<f64, DicError> {
        let cell = self.text(name, row)?;
        match cell.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.error(format!(
                "{}, column `{name}`: `{cell}` is not a finite number",
                self.line(row)
            ))),
        }
    }

    fn integer(&self, name: &str, row: usize) -> Result<i64, DicError> {
        let cell = self.text(name, row)?;
        cell.parse::<i64>().map_err(|_| {
            self.error(format!(
                "{}, column `{name}`: `{cell}` is not an integer",
                self.line(row)
            ))
        })
    }
}

fn parse_frames(log: &Log) -> Result<Vec<FrameEntry>, DicError> {
    let mut frames: Vec<FrameEntry> = Vec::with_capacity(log.rows());
    for row in 0..log.rows() {
        let frame = log.integer("frame", row)?;
        let time_s = log.number("time_s", row)?;
        if let Some(prev) = frames.last().map(|f| f.time_s)
            && time_s <= prev
        {
            return Err(log.error(format!(
                "{}: time_s = {time_s} does not increase (previous {prev})",
                log.line(row)
            )));
        }
        let file = log.text("file", row)?;
        if file.is_empty() {
            return Err(log.error(format!(
                "{}, column `file`: no image file named",
                log.line(row)
            )));
        }
        frames.push(FrameEntry {
            frame,
            time_s,
            file,
            listed: log.line(row),
        });
    }
    if frames.len() < 2 {
        return Err(log.error("lists fewer than 2 frames".into()));
    }
    Ok(frames)
}

fn parse_force(log: &Log) -> Result<Vec<(f64, f64)>, DicError> {
    let mut force: Vec<(f64, f64)> = Vec::with_capacity(log.rows());
    for row in 0..log.rows() {
        let t = log.number("time_s", row)?;
        let f = log.number("force_n", row)?;
        if let Some(&(prev, _)) = force.last()
            && t <= prev
        {
            return Err(log.error(format!(
                "{}: time_s = {t} does not increase (previous {prev})",
                log.line(row)
            )));
        }
        force.push((t, f));
    }
    Ok(force)
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::Files;

    fn source(files: &Files) -> FileSource<'_> {
        FileSource::Files {
            files,
            input: "sequence".into(),
        }
    }

    fn files(frames: &str, force: &str) -> Files {
        Files::new()
            .with("frames.csv", frames.as_bytes().to_vec())
            .with("force.csv", force.as_bytes().to_vec())
    }

    #[test]
    fn reads_the_logs_and_interpolates_force() {
        let f = files(
            "frame,time_s,file\n0,0.0,a.png\n1,0.5,b.png\n",
            "time_s,force_n\n0,0\n0.02,1\n0.52,2\n",
        );
        let s = Sequence::open(source(&f)).unwrap();
        assert_eq!(s.frames[1].file, "b.png");
        let force = s.force_at(0.5, &s.frames[1]).unwrap();
        assert!((force - (1.0 + 0.48 / 0.5)).abs() < 1e-12);
    }

    #[test]
    fn bad_logs_name_the_file_and_line() {
        let f = files(
            "frame,time_s,file\n0,0.0,a.png\n1,0.5,b.png\n",
            "time_s,force_n\n0,0\n0.2,1\n",
        );
        let s = Sequence::open(source(&f)).unwrap();
        let e = s.force_at(0.5, &s.frames[1]).unwrap_err().to_string();
        assert!(e.contains("force.csv") && e.contains("b.png"), "{e}");
        let f = files(
            "frame,time_s,file\n0,0.0,a.png\n1,x,b.png\n",
            "time_s,force_n\n0,0\n",
        );
        let e = Sequence::open(source(&f)).err().unwrap().to_string();
        assert!(e.contains("frames.csv") && e.contains("line 3"), "{e}");
        let f = files("frame,t,file\n0,0.0,a.png\n", "time_s,force_n\n0,0\n");
        let e = Sequence::open(source(&f)).err().unwrap().to_string();
        assert!(e.contains("no column `time_s`"), "{e}");
        let f = Files::new();
        let e = Sequence::open(source(&f)).err().unwrap().to_string();
        assert!(e.contains("frames.csv") && e.contains("missing"), "{e}");
    }

    #[test]
    fn log_lines_count_comments_and_blank_lines() {
        let f = files(
            "# camera 1\nframe,time_s,file\n0,0.0,a.png\n\n# paused\n1,0.5,b.png\n2,0.4,c.png\n",
            "time_s,force_n\n0,0\n",
        );
        let e = Sequence::open(source(&f)).err().unwrap().to_string();
        assert!(e.contains("frames.csv: line 7: time_s = 0.4"), "{e}");
        let f = files(
            "frame,time_s,file\n0,0.0,a.png\n1,0.5,b.png\n",
            "# load cell\ntime_s,force_n\n\n0,0\n0.2,1 N\n",
        );
        let e = Sequence::open(source(&f)).err().unwrap().to_string();
        assert!(
            e.contains("force.csv: line 5, column `force_n`: `1 N`"),
            "{e}"
        );
        let f = files(
            "frame,time_s,file\n0,0.0,a.png\n1,0.5,\n",
            "time_s,force_n\n0,0\n",
        );
        let e = Sequence::open(source(&f)).err().unwrap().to_string();
        assert!(
            e.contains("frames.csv: line 3, column `file`: no image file"),
            "{e}"
        );
        // A listed image that is not there: the listing line too.
        let f = files(
            "# rig\nframe,time_s,file\n0,0.0,a.png\n1,0.5,b.png\n",
            "time_s,force_n\n0,0\n",
        );
        let e = Sequence::open(source(&f))
            .unwrap()
            .image(1)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("b.png: missing (frames.csv lists it on line 4)"),
            "{e}"
        );
        let f = files("frame,time_s,file\n", "time_s,force_n\n0,0\n");
        let e = Sequence::open(source(&f)).err().unwrap().to_string();
        assert!(
            e.contains("frames.csv") && e.contains("no data rows"),
            "{e}"
        );
    }
}
