//! A lab's image sequence with its force log, from a `Files` product (a
//! synthetic lab's) or a folder of real data, in one layout: `frames.csv`
//! (`frame, time_s, file`), the images it names (PNG or TIFF, 8 or 16 bit,
//! grey or colour) and `force.csv` (`time_s, force_n`, increasing times).
//! Without `frames.csv` the frames are the folder's PNG/TIFF files whose
//! names carry their time (`img_0007_t1.25s.tif`, see [`time_in_name`]).
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
    /// Where frames.csv lists it (`line 3`); `None` for a frame found by
    /// its file name.
    pub listed: Option<RowPlace>,
}

/// The opened sequence.
pub struct Sequence<'a> {
    source: FileSource<'a>,
    pub frames: Vec<FrameEntry>,
    /// (time_s, force_n), increasing in time.
    pub force: Vec<(f64, f64)>,
    /// The camera's exposure signal logged beside the force (force.csv's
    /// optional column `camera_trigger`), high at each force sample taken
    /// while the shutter was open: 0/1, or volts (high above the middle of
    /// the logged range).
    pub trigger: Option<Vec<bool>>,
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
    /// Opens the sequence: the frames from `frames.csv`, or, without one,
    /// from the image files' names ([`frames_from_names`]).
    pub fn open(source: FileSource<'a>) -> Result<Self, StageError> {
        let frames = if source.exists("frames.csv") {
            parse_frames(&Log::read(
                &source,
                "frames.csv",
                &["frame", "time_s", "file"],
            )?)?
        } else {
            frames_from_names(&source)?
        };
        let log = Log::read(&source, "force.csv", &["time_s", "force_n"])?;
        let force = parse_force(&log)?;
        let trigger = parse_trigger(&log)?;
        Ok(Sequence {
            source,
            frames,
            force,
            trigger,
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
            let why = match entry.listed {
                Some(line) => format!("missing (frames.csv lists it on {line})"),
                None => "missing".to_owned(),
            };
            return Err(StageError::file(self.source.display(name), why));
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
            listed: Some(log.line(row)),
        });
    }
    if frames.len() < 2 {
        return Err(log.error("lists fewer than 2 frames".into()));
    }
    Ok(frames)
}

/// force.csv's optional `camera_trigger` column as high/low samples.
fn parse_trigger(log: &Log) -> Result<Option<Vec<bool>>, StageError> {
    if log.table.column("camera_trigger").is_err() {
        return Ok(None);
    }
    let values = (0..log.rows())
        .map(|row| log.number("camera_trigger", row))
        .collect::<Result<Vec<f64>, StageError>>()?;
    let (low, high) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    if high <= low {
        return Err(log.error(format!(
            "column `camera_trigger` is {low} throughout: it never shows an exposure \
             (log the camera's trigger output, or drop the column)"
        )));
    }
    let middle = 0.5 * (low + high);
    Ok(Some(values.iter().map(|&v| v > middle).collect()))
}

/// How a folder without `frames.csv` must look, for the errors.
const NAMED_FRAMES_HELP: &str = "a sequence needs frames.csv (columns frame, time_s, file; \
     e.g. the lines `frame,time_s,file` and `0,0.0,img_000.tif`), or image files (PNG/TIFF) \
     whose names carry their camera time as a field of digits and a unit s, ms or us, \
     optionally after `t` or `t=`, between `_`, `-` or spaces: `img_000_t0.000s.tif`, \
     `frame-0012-1250ms.png`";

/// Whether `name` is one of a sequence's image files: a PNG or TIFF, not
/// hidden (a leading `.`: macOS writes `._img.tif` resource forks beside
/// the images on foreign disks).
fn is_frame_file(name: &str) -> bool {
    if name.starts_with('.') || name.contains('/') {
        return false;
    }
    let lower = name.to_ascii_lowercase();
    [".png", ".tif", ".tiff"]
        .iter()
        .any(|ext| lower.ends_with(ext))
}

/// What a file name says of its frame.
#[derive(Clone, Debug, PartialEq)]
pub enum NameTime {
    /// Exactly one time field, in seconds; `frame` the name's last field of
    /// plain digits, if any.
    Time { time_s: f64, frame: Option<i64> },
    /// No time field.
    None,
    /// More than one time field (the fields, as written).
    Ambiguous(Vec<String>),
}

/// The camera time written in an image file's name. The stem (the name
/// without its extension) is split at `_`, `-` and spaces; a time field is
/// a decimal number with a unit `s`, `ms`, `us` or `µs`, optionally after
/// `t` or `t=` (`0.250s`, `t1.25s`, `t=1250ms`, `1250000us`). A field of
/// plain digits is the frame number (the last such field). Negative times
/// cannot be written this way (`-` separates fields).
pub fn time_in_name(name: &str) -> NameTime {
    let stem = name.rsplit_once('.').map_or(name, |(stem, _)| stem);
    let mut times: Vec<(f64, &str)> = Vec::new();
    let mut frame = None;
    for field in stem.split(['_', '-', ' ']).filter(|f| !f.is_empty()) {
        if field.bytes().all(|b| b.is_ascii_digit()) {
            frame = field.parse::<i64>().ok().or(frame);
        } else if let Some(t) = time_field(field) {
            times.push((t, field));
        }
    }
    match times.as_slice() {
        [] => NameTime::None,
        [(time_s, _)] => NameTime::Time {
            time_s: *time_s,
            frame,
        },
        _ => NameTime::Ambiguous(times.iter().map(|(_, f)| (*f).to_owned()).collect()),
    }
}

/// A time field's seconds: `[t|t=]<digits>[.<digits>]<unit>`.
fn time_field(field: &str) -> Option<f64> {
    let body = field
        .strip_prefix("t=")
        .or_else(|| field.strip_prefix('t'))
        .unwrap_or(field);
    // Longest unit first: `ms` before `s`.
    let (number, scale) = [("ms", 1e-3), ("us", 1e-6), ("µs", 1e-6), ("s", 1.0)]
        .iter()
        .find_map(|(unit, scale)| body.strip_suffix(unit).map(|n| (n, *scale)))?;
    let (whole, fraction) = number.split_once('.').unwrap_or((number, ""));
    let digits = |s: &str| s.bytes().all(|b| b.is_ascii_digit());
    if whole.is_empty() || !digits(whole) || !digits(fraction) || number.ends_with('.') {
        return None;
    }
    let value: f64 = number.parse().ok()?;
    Some(value * scale).filter(|t| t.is_finite())
}

/// The frames of a source without `frames.csv`: its PNG/TIFF files, each
/// name carrying its time ([`time_in_name`]), in order of time. The frame
/// number is the name's digit field, or else the position (from 0). An
/// error names the file whose name has no time, or two files of one time.
pub fn frames_from_names(source: &FileSource) -> Result<Vec<FrameEntry>, StageError> {
    let mut images: Vec<String> = source
        .names()?
        .into_iter()
        .filter(|n| is_frame_file(n))
        .collect();
    // Natural order (`img_2` before `img_10`), for the order of the errors
    // and as the tie-breaker of the frame numbers below.
    alphanumeric_sort::sort_str_slice(&mut images);
    if images.is_empty() {
        return Err(StageError::file(
            source.display("frames.csv"),
            format!("missing, and there are no PNG/TIFF frames either: {NAMED_FRAMES_HELP}"),
        ));
    }
    let mut frames = Vec::with_capacity(images.len());
    for name in images {
        match time_in_name(&name) {
            NameTime::Time { time_s, frame } => frames.push((time_s, frame, name)),
            NameTime::None => {
                return Err(StageError::file(
                    source.display(&name),
                    format!(
                        "has no time in its name and there is no frames.csv: {NAMED_FRAMES_HELP}"
                    ),
                ));
            }
            NameTime::Ambiguous(fields) => {
                return Err(StageError::file(
                    source.display(&name),
                    format!(
                        "names more than one time ({}); rename it to carry one, or list the \
                         frames in frames.csv",
                        fields.join(", ")
                    ),
                ));
            }
        }
    }
    // Stable: equal times keep the natural order, and are refused next.
    frames.sort_by(|a, b| a.0.total_cmp(&b.0));
    for pair in frames.windows(2) {
        if pair[0].0 == pair[1].0 {
            return Err(StageError::file(
                source.display(&pair[1].2),
                format!(
                    "has the time {} s in its name, as {} does: two frames of one time",
                    pair[1].0, pair[0].2
                ),
            ));
        }
    }
    if frames.len() < 2 {
        return Err(StageError::file(
            source.display(&frames[0].2),
            format!("is the only frame (a sequence needs at least 2): {NAMED_FRAMES_HELP}"),
        ));
    }
    let numbered = frames.iter().all(|f| f.1.is_some());
    Ok(frames
        .into_iter()
        .enumerate()
        .map(|(k, (time_s, frame, file))| FrameEntry {
            frame: if numbered {
                frame.unwrap_or(k as i64)
            } else {
                k as i64
            },
            time_s,
            file,
            listed: None,
        })
        .collect())
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
    fn a_trigger_column_is_read_as_high_and_low() {
        let f = files(
            "frame,time_s,file\n0,0.0,a.png\n1,0.5,b.png\n",
            "time_s,force_n,camera_trigger\n0,0,0.02\n0.02,1,4.98\n0.04,1,5.01\n0.06,2,0\n",
        );
        let s = Sequence::open(source(&f)).unwrap();
        assert_eq!(s.trigger, Some(vec![false, true, true, false]));
        let f = files(
            "frame,time_s,file\n0,0.0,a.png\n1,0.5,b.png\n",
            "time_s,force_n\n0,0\n",
        );
        assert_eq!(Sequence::open(source(&f)).unwrap().trigger, None);
        let f = files(
            "frame,time_s,file\n0,0.0,a.png\n1,0.5,b.png\n",
            "time_s,force_n,camera_trigger\n0,0,1\n0.02,1,1\n",
        );
        let e = Sequence::open(source(&f)).err().unwrap().to_string();
        assert!(
            e.contains("force.csv: column `camera_trigger` is 1 throughout"),
            "{e}"
        );
        let f = files(
            "frame,time_s,file\n0,0.0,a.png\n1,0.5,b.png\n",
            "time_s,force_n,camera_trigger\n0,0,1\n0.02,1,high\n",
        );
        let e = Sequence::open(source(&f)).err().unwrap().to_string();
        assert!(e.contains("line 3, column `camera_trigger`: `high`"), "{e}");
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

    #[test]
    fn time_fields_in_names() {
        let time = |name: &str| match time_in_name(name) {
            NameTime::Time { time_s, frame } => (time_s, frame),
            other => panic!("{name}: {other:?}"),
        };
        assert_eq!(time("img_0007_t1.25s.tif"), (1.25, Some(7)));
        assert_eq!(time("frame-0012-1250ms.png"), (1.25, Some(12)));
        assert_eq!(time("t=0.5s.PNG"), (0.5, None));
        assert_eq!(time("run 3 250000us.tiff"), (0.25, Some(3)));
        assert_eq!(time("a_2µs.tif").0, 2e-6);
        assert_eq!(time("x_10s_5.png"), (10.0, Some(5)));
        for none in [
            "img_0007.tif",
            "sample1s.png",
            "img_1.s.tif",
            "img_.5s.tif",
            "img_t.png",
            "img_1e3s.png",
            "img_1.2.3s.png",
            "img_s.png",
        ] {
            assert_eq!(time_in_name(none), NameTime::None, "{none}");
        }
        assert_eq!(
            time_in_name("a_1s_2s.png"),
            NameTime::Ambiguous(vec!["1s".into(), "2s".into()])
        );
    }

    #[test]
    fn frames_from_names_without_frames_csv() {
        let force = b"time_s,force_n\n0,0\n5,1\n".to_vec();
        // Natural order and time order agree here; a `._` fork and other
        // files are not frames.
        let f = Files::new()
            .with("img_10_t2.5s.tif", vec![])
            .with("img_2_t0.5s.tif", vec![])
            .with("img_9_t=2000ms.tif", vec![])
            .with("._img_2_t0.5s.tif", vec![])
            .with("notes.txt", vec![])
            .with("force.csv", force.clone());
        let s = Sequence::open(source(&f)).unwrap();
        let got: Vec<(i64, f64, &str)> = s
            .frames
            .iter()
            .map(|e| (e.frame, e.time_s, e.file.as_str()))
            .collect();
        assert_eq!(
            got,
            [
                (2, 0.5, "img_2_t0.5s.tif"),
                (9, 2.0, "img_9_t=2000ms.tif"),
                (10, 2.5, "img_10_t2.5s.tif")
            ]
        );
        assert!(s.frames.iter().all(|e| e.listed.is_none()));
        // Times in the names decide the order, not the names' own order
        // (`t1.5s` sorts after `t1.25s` naturally).
        let f = Files::new()
            .with("t1.5s.png", vec![])
            .with("t1.25s.png", vec![])
            .with("force.csv", force.clone());
        let s = Sequence::open(source(&f)).unwrap();
        let got: Vec<(i64, &str)> = s
            .frames
            .iter()
            .map(|e| (e.frame, e.file.as_str()))
            .collect();
        assert_eq!(got, [(0, "t1.25s.png"), (1, "t1.5s.png")]);
        // A folder reads alike.
        let dir = std::env::temp_dir().join(format!("hc-seq-names-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for (name, bytes) in [
            ("b_0100ms.png", vec![]),
            ("a_0.2s.png", vec![]),
            ("force.csv", force.clone()),
        ] {
            std::fs::write(dir.join(name), bytes).unwrap();
        }
        let s = Sequence::open(FileSource::Dir(dir.clone())).unwrap();
        let got: Vec<&str> = s.frames.iter().map(|e| e.file.as_str()).collect();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(got, ["b_0100ms.png", "a_0.2s.png"]);
    }

    #[test]
    fn named_frames_errors_say_what_a_name_must_carry() {
        let force = b"time_s,force_n\n0,0\n".to_vec();
        let open = |names: &[&str]| {
            let mut f = Files::new().with("force.csv", force.clone());
            for name in names {
                f = f.with(name, vec![]);
            }
            Sequence::open(source(&f)).err().unwrap().to_string()
        };
        let e = open(&["img_001_t0s.tif", "img_002.tif"]);
        assert!(
            e.contains("img_002.tif: has no time in its name") && e.contains("frames.csv (columns"),
            "{e}"
        );
        let e = open(&["a_1s.png", "b_1000ms.png"]);
        assert!(
            e.contains("b_1000ms.png: has the time 1 s in its name, as a_1s.png"),
            "{e}"
        );
        let e = open(&["a_1s_2ms.png", "b_3s.png"]);
        assert!(
            e.contains("a_1s_2ms.png: names more than one time (1s, 2ms)"),
            "{e}"
        );
        let e = open(&["a_1s.png"]);
        assert!(e.contains("a_1s.png: is the only frame"), "{e}");
        let e = open(&["readme.txt"]);
        assert!(
            e.contains("frames.csv: missing, and there are no PNG/TIFF frames")
                && e.contains("img_000_t0.000s.tif"),
            "{e}"
        );
        // A frame named but gone by the time it is read: no listing line.
        let f = Files::new()
            .with("force.csv", force.clone())
            .with("a_0s.png", vec![])
            .with("b_1s.png", vec![]);
        let mut s = Sequence::open(source(&f)).unwrap();
        s.frames[1].file = "c_1s.png".into();
        let e = s.frame(1).unwrap_err().to_string();
        assert!(e.ends_with("c_1s.png: missing"), "{e}");
    }

    proptest::proptest! {
        /// Any name is read without a panic; a time written with a unit
        /// reads back.
        #[test]
        fn names_never_panic_and_written_times_read_back(
            name in "\\PC{0,40}",
            k in 0u32..100_000,
            ms in 0u64..10_000_000,
        ) {
            let _ = time_in_name(&name);
            let written = format!("img_{k:05}_t{}.{:03}s.tif", ms / 1000, ms % 1000);
            let read = time_in_name(&written);
            proptest::prop_assert_eq!(
                read,
                NameTime::Time { time_s: ms as f64 / 1000.0, frame: Some(i64::from(k)) }
            );
            let written = format!("cam-{ms}ms.png");
            let read = time_in_name(&written);
            proptest::prop_assert_eq!(read, NameTime::Time { time_s: ms as f64 * 1e-3, frame: None });
        }
    }
}
