//! A lab's image sequence with its force log, from a `Files` product (a
//! synthetic lab's) or a folder of real data, in one layout: `frames.csv`
//! (`frame, time_s, file`), the images it names (PNG or TIFF, 8 or 16 bit,
//! grey or colour) and `force.csv` (`time_s, force_n`, increasing times).
//! Other files (a specimen or rig description) are read by name. The
//! tensile test's DIC and the contact experiment's image analysis read their
//! sequences through this one reader, so both name files and lines alike.

use std::borrow::Cow;

use crate::csv_table::{RowLines, RowPlace, read_csv_bytes_with_lines};
use crate::{ColumnData, FileSource, StageError, Table};

/// One row of `frames.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameEntry {
    pub frame: i64,
    pub time_s: f64,
    pub file: String,
    /// Where frames.csv lists it (`line 3`).
    pub listed: RowPlace,
}

/// The opened sequence.
pub struct Sequence<'a> {
    source: FileSource<'a>,
    pub frames: Vec<FrameEntry>,
    /// (time_s, force_n), increasing in time.
    pub force: Vec<(f64, f64)>,
}

/// A decoded grey frame as the camera's integers: row-major
/// (`data[y * width + x]`), `bits` the container's depth (8 or 16; colour
/// files are converted to luma).
#[derive(Clone, Debug, PartialEq)]
pub struct GrayFrame {
    pub width: usize,
    pub height: usize,
    pub bits: u8,
    pub data: Vec<u16>,
}

impl GrayFrame {
    /// Decodes a PNG or TIFF file's bytes; `name` labels errors.
    pub fn decode(name: &str, bytes: &[u8]) -> Result<Self, StageError> {
        let decoded = image::load_from_memory(bytes)
            .map_err(|e| StageError::file(name, format!("not a readable PNG/TIFF image: {e}")))?;
        let (width, height) = (decoded.width() as usize, decoded.height() as usize);
        let sixteen_bit = matches!(
            decoded.color(),
            image::ColorType::L16
                | image::ColorType::La16
                | image::ColorType::Rgb16
                | image::ColorType::Rgba16
                | image::ColorType::Rgb32F
                | image::ColorType::Rgba32F
        );
        let (bits, data) = if sixteen_bit {
            (16, decoded.into_luma16().into_raw())
        } else {
            let raw = decoded.into_luma8().into_raw();
            (8, raw.into_iter().map(u16::from).collect())
        };
        if width == 0 || height == 0 || data.len() != width * height {
            return Err(StageError::file(
                name,
                format!(
                    "an image of {width} × {height} pixels holding {} values",
                    data.len()
                ),
            ));
        }
        Ok(GrayFrame {
            width,
            height,
            bits,
            data,
        })
    }

    /// The container's full scale, 2^bits − 1.
    pub fn full_scale(&self) -> f64 {
        f64::from((1u32 << self.bits) - 1)
    }
}

impl<'a> Sequence<'a> {
    pub fn open(source: FileSource<'a>) -> Result<Self, StageError> {
        let frames = parse_frames(&Log::read(
            &source,
            "frames.csv",
            &["frame", "time_s", "file"],
        )?)?;
        let force = parse_force(&Log::read(&source, "force.csv", &["time_s", "force_n"])?)?;
        Ok(Sequence {
            source,
            frames,
            force,
        })
    }

    /// How errors name file `name`.
    pub fn display(&self, name: &str) -> String {
        self.source.display(name)
    }

    /// Whether the sequence has file `name`.
    pub fn exists(&self, name: &str) -> bool {
        self.source.exists(name)
    }

    /// The bytes of file `name`; a missing one is an error saying so.
    pub fn read(&self, name: &str) -> Result<Cow<'a, [u8]>, StageError> {
        read(&self.source, name)
    }

    /// Decodes frame `k` (index into `frames`).
    pub fn frame(&self, k: usize) -> Result<GrayFrame, StageError> {
        let entry = &self.frames[k];
        let name = &entry.file;
        if !self.source.exists(name) {
            return Err(StageError::file(
                self.source.display(name),
                format!("missing (frames.csv lists it on {})", entry.listed),
            ));
        }
        GrayFrame::decode(&self.source.display(name), &self.read(name)?)
    }

    /// The force at `t_s` by linear interpolation of the log; an error names
    /// the frame if the log does not cover it.
    pub fn force_at(&self, t_s: f64, frame: &FrameEntry) -> Result<f64, StageError> {
        let (first, last) = (self.force[0].0, self.force[self.force.len() - 1].0);
        let slack = 1e-9 * (1.0 + last.abs());
        if t_s < first - slack || t_s > last + slack {
            return Err(StageError::file(
                self.source.display("force.csv"),
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
fn read<'a>(source: &FileSource<'a>, name: &str) -> Result<Cow<'a, [u8]>, StageError> {
    if !source.exists(name) {
        return Err(StageError::file(source.display(name), "missing"));
    }
    source.read(name)
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
    fn read(source: &FileSource, name: &str, columns: &[&str]) -> Result<Self, StageError> {
        let shown = source.display(name);
        let csv = read_csv_bytes_with_lines(&read(source, name)?, &shown)?;
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

    fn error(&self, message: String) -> StageError {
        StageError::file(&self.shown, message)
    }

    /// Where data row `row` (0-based) stands in the file: `line 7`.
    fn line(&self, row: usize) -> RowPlace {
        self.lines.place(row)
    }

    fn column(&self, name: &str) -> Result<&ColumnData, StageError> {
        self.table.column(name).map_err(|_| {
            self.error(format!(
                "has no column `{name}` (header: {})",
                self.table.column_names().join(", ")
            ))
        })
    }

    /// Cell `row` of column `name` as text (a number as Rust prints it).
    fn text(&self, name: &str, row: usize) -> Result<String, StageError> {
        Ok(match self.column(name)? {
            ColumnData::F64(v) => v[row].to_string(),
            ColumnData::I64(v) => v[row].to_string(),
            ColumnData::Str(v) => v[row].clone(),
        })
    }

    fn number(&self, name: &str, row: usize) -> Result<f64, StageError> {
        let cell = self.text(name, row)?;
        match cell.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.error(format!(
                "{}, column `{name}`: `{cell}` is not a finite number",
                self.line(row)
            ))),
        }
    }

    fn integer(&self, name: &str, row: usize) -> Result<i64, StageError> {
        let cell = self.text(name, row)?;
        cell.parse::<i64>().map_err(|_| {
            self.error(format!(
                "{}, column `{name}`: `{cell}` is not an integer",
                self.line(row)
            ))
        })
    }
}

fn parse_frames(log: &Log) -> Result<Vec<FrameEntry>, StageError> {
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

fn parse_force(log: &Log) -> Result<Vec<(f64, f64)>, StageError> {
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
    use crate::Files;

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
            .frame(1)
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
