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

use crate::FileSource;
use crate::csv_table::{RowLines, RowPlace, read_csv_bytes_with_lines};
use hypercontact_core::{ColumnData, StageError, Table};

mod image_file;
pub use image_file::{DecodedImage, GrayFrame, LUMA_RULE, Samples, decode_image};

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

/// What a caller needs of a sequence's files. The default is the strict
/// layout the contact experiment needs: force.csv required, no frame rate.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Layout {
    /// force.csv may be missing (a strain-only DIC); then
    /// [`Sequence::force`] is empty and [`Sequence::has_force`] false.
    pub force_optional: bool,
    /// The caller's frame-rate parameter, if it has one: with a rate,
    /// a folder without frames.csv is read in the natural order of its
    /// file names at times k / rate.
    pub frame_rate: Option<FrameRate>,
    /// Image files of the folder that are not frames (a mask).
    pub not_frames: Vec<String>,
}

/// A caller's frame-rate parameter: its name (for messages) and value.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameRate {
    pub param: &'static str,
    pub hz: Option<f64>,
}

/// How force.csv must look, for the errors.
const FORCE_HELP: &str = "the force log force.csv needs the columns time_s and force_n with \
     increasing times, e.g. the lines `time_s,force_n` and `0.00,0.0`";

impl<'a> Sequence<'a> {
    /// Opens the sequence in the strict layout ([`Layout::default`]).
    pub fn open(source: FileSource<'a>) -> Result<Self, StageError> {
        Self::open_with(source, &Layout::default())
    }

    /// Opens the sequence: the frames from `frames.csv`, or, without one,
    /// from the image files' names ([`frames_from_names`]) or, given a
    /// frame rate, their natural order ([`frames_at_rate`]); force.csv as
    /// `layout` asks.
    pub fn open_with(source: FileSource<'a>, layout: &Layout) -> Result<Self, StageError> {
        let rate = layout
            .frame_rate
            .as_ref()
            .and_then(|r| r.hz.map(|hz| (r.param, hz)));
        let frames = if source.exists("frames.csv") {
            if let Some((param, hz)) = rate {
                return Err(StageError::file(
                    source.display("frames.csv"),
                    format!(
                        "lists the frames with their times, and `{param}` = {hz} Hz gives them \
                         too: drop the parameter (or the file)"
                    ),
                ));
            }
            parse_frames(&Log::read(
                &source,
                "frames.csv",
                &["frame", "time_s", "file"],
            )?)?
        } else if let Some((param, hz)) = rate {
            frames_at_rate(&source, param, hz, &layout.not_frames)?
        } else {
            frames_listed_by_names(&source, layout)?
        };
        let (force, trigger) = if layout.force_optional && !source.exists("force.csv") {
            (Vec::new(), None)
        } else {
            if !source.exists("force.csv") {
                return Err(StageError::file(
                    source.display("force.csv"),
                    format!("missing: {FORCE_HELP}"),
                ));
            }
            let log = Log::read(&source, "force.csv", &["time_s", "force_n"])?;
            (parse_force(&log)?, parse_trigger(&log)?)
        };
        Ok(Sequence {
            source,
            frames,
            force,
            trigger,
        })
    }

    /// Whether the sequence has a force log (always, unless opened with
    /// [`Layout::force_optional`]).
    pub fn has_force(&self) -> bool {
        !self.force.is_empty()
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
        let name = self.present(k)?;
        GrayFrame::decode(&self.source.display(name), &self.read(name)?)
    }

    /// Frame `k`'s file name, if the file is there.
    fn present(&self, k: usize) -> Result<&str, StageError> {
        let entry = &self.frames[k];
        let name = &entry.file;
        if !self.source.exists(name) {
            let why = match entry.listed {
                Some(line) => format!("missing (frames.csv lists it on {line})"),
                None => "missing".to_owned(),
            };
            return Err(StageError::file(self.source.display(name), why));
        }
        Ok(name)
    }

    /// Decodes frame `k` with its samples as stored ([`decode_image`]).
    pub fn decoded(&self, k: usize) -> Result<DecodedImage, StageError> {
        let name = self.present(k)?;
        decode_image(&self.source.display(name), &self.read(name)?)
    }

    /// The force at `t_s` by linear interpolation of the log; an error names
    /// the frame if the log does not cover it.
    pub fn force_at(&self, t_s: f64, frame: &FrameEntry) -> Result<f64, StageError> {
        let (Some(&(first, _)), Some(&(last, _))) = (self.force.first(), self.force.last()) else {
            return Err(StageError::file(
                self.source.display("force.csv"),
                format!("missing: {FORCE_HELP}"),
            ));
        };
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
    frames_listed_by_names(source, &Layout::default())
}

/// What a folder without `frames.csv` must hold, for the errors: with the
/// caller's frame-rate parameter if it has one.
fn named_frames_help(layout: &Layout) -> String {
    match &layout.frame_rate {
        Some(rate) => format!(
            "{NAMED_FRAMES_HELP}; or set `{}` (the frames are then the PNG/TIFF files in the \
             natural order of their names, `img_2.tif` before `img_10.tif`, at times k / rate)",
            rate.param
        ),
        None => NAMED_FRAMES_HELP.to_owned(),
    }
}

/// The folder's image files that may be frames, in natural order (`img_2`
/// before `img_10`); an error if there are none.
fn image_names(source: &FileSource, layout: &Layout) -> Result<Vec<String>, StageError> {
    let mut images: Vec<String> = source
        .names()?
        .into_iter()
        .filter(|n| is_frame_file(n) && !layout.not_frames.contains(n))
        .collect();
    alphanumeric_sort::sort_str_slice(&mut images);
    if images.is_empty() {
        return Err(StageError::file(
            source.display("frames.csv"),
            format!(
                "missing, and there are no PNG/TIFF frames either: {}",
                named_frames_help(layout)
            ),
        ));
    }
    Ok(images)
}

/// The frames of a source without `frames.csv` and a frame rate `hz`
/// (parameter `param`): its PNG/TIFF files in the natural order of their
/// names (alphanumeric-sort: `img_2` before `img_10`), frame k taken at
/// k / hz seconds; times written in the names are not read. The frame
/// number is the name's last field of digits if every name has one, else
/// the position (from 0).
pub fn frames_at_rate(
    source: &FileSource,
    param: &'static str,
    hz: f64,
    not_frames: &[String],
) -> Result<Vec<FrameEntry>, StageError> {
    if !(hz.is_finite() && hz > 0.0) {
        return Err(StageError::invalid(format!(
            "parameter `{param}`: must be a positive frame rate in Hz, got {hz}"
        )));
    }
    let layout = Layout {
        frame_rate: Some(FrameRate {
            param,
            hz: Some(hz),
        }),
        not_frames: not_frames.to_vec(),
        ..Layout::default()
    };
    let images = image_names(source, &layout)?;
    if images.len() < 2 {
        return Err(StageError::file(
            source.display(&images[0]),
            "is the only PNG/TIFF frame (a sequence needs at least 2)",
        ));
    }
    let numbers: Vec<Option<i64>> = images.iter().map(|n| number_in_name(n)).collect();
    let numbered = numbers.iter().all(Option::is_some);
    Ok(images
        .into_iter()
        .zip(numbers)
        .enumerate()
        .map(|(k, (file, number))| FrameEntry {
            frame: match number {
                Some(n) if numbered => n,
                _ => k as i64,
            },
            time_s: k as f64 / hz,
            file,
            listed: None,
        })
        .collect())
}

/// The last field of plain digits in a file name's stem (fields split at
/// `_`, `-` and spaces, as [`time_in_name`] splits them).
fn number_in_name(name: &str) -> Option<i64> {
    let stem = name.rsplit_once('.').map_or(name, |(stem, _)| stem);
    stem.split(['_', '-', ' '])
        .filter(|f| !f.is_empty() && f.bytes().all(|b| b.is_ascii_digit()))
        .filter_map(|f| f.parse::<i64>().ok())
        .next_back()
}

/// [`frames_from_names`] with the caller's layout (its help and the files
/// that are not frames).
fn frames_listed_by_names(
    source: &FileSource,
    layout: &Layout,
) -> Result<Vec<FrameEntry>, StageError> {
    // Natural order, for the order of the errors and as the tie-breaker of
    // the frame numbers below.
    let images = image_names(source, layout)?;
    let help = named_frames_help(layout);
    let mut frames = Vec::with_capacity(images.len());
    for name in images {
        match time_in_name(&name) {
            NameTime::Time { time_s, frame } => frames.push((time_s, frame, name)),
            NameTime::None => {
                return Err(StageError::file(
                    source.display(&name),
                    format!("has no time in its name and there is no frames.csv: {help}"),
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
            format!("is the only frame (a sequence needs at least 2): {help}"),
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
    use hypercontact_core::Files;

    /// (frame, time, file) of every frame, in order.
    fn listed<'s>(s: &'s Sequence) -> Vec<(i64, f64, &'s str)> {
        s.frames
            .iter()
            .map(|e| (e.frame, e.time_s, e.file.as_str()))
            .collect()
    }

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
        let got = listed(&s);
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

    fn layout(force_optional: bool, hz: Option<f64>) -> Layout {
        Layout {
            force_optional,
            frame_rate: Some(FrameRate {
                param: "frame_rate_hz",
                hz,
            }),
            not_frames: vec!["mask.png".into()],
        }
    }

    #[test]
    fn force_log_optional_when_the_caller_says_so() {
        let f = Files::new().with(
            "frames.csv",
            b"frame,time_s,file\n0,0.0,a.png\n1,0.5,b.png\n".to_vec(),
        );
        let e = Sequence::open(source(&f)).err().unwrap().to_string();
        assert!(
            e.contains(
                "force.csv: missing: the force log force.csv needs the columns time_s \
                        and force_n"
            ) && e.contains("`0.00,0.0`"),
            "{e}"
        );
        let s = Sequence::open_with(source(&f), &layout(true, None)).unwrap();
        assert!(!s.has_force() && s.trigger.is_none());
        let e = s.force_at(0.0, &s.frames[0]).unwrap_err().to_string();
        assert!(e.contains("force.csv: missing"), "{e}");
        // Present, it is read (and checked) as always.
        let f = f.with("force.csv", b"time_s,force_n\n0,x\n".to_vec());
        let e = Sequence::open_with(source(&f), &layout(true, None))
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("force.csv: line 2, column `force_n`"), "{e}");
    }

    #[test]
    fn a_frame_rate_orders_frames_by_natural_sort() {
        let f = Files::new()
            .with("img_10.tif", vec![])
            .with("img_2.tif", vec![])
            .with("img_1.tif", vec![])
            .with("mask.png", vec![])
            .with("._img_3.tif", vec![]);
        let s = Sequence::open_with(source(&f), &layout(true, Some(4.0))).unwrap();
        let got = listed(&s);
        assert_eq!(
            got,
            [
                (1, 0.0, "img_1.tif"),
                (2, 0.25, "img_2.tif"),
                (10, 0.5, "img_10.tif")
            ]
        );
        // Names without a digit field: numbered by position.
        let f = Files::new()
            .with("b.png", vec![])
            .with("a.png", vec![])
            .with("c3.png", vec![]);
        let s = Sequence::open_with(source(&f), &layout(true, Some(2.0))).unwrap();
        let got: Vec<(i64, &str)> = s
            .frames
            .iter()
            .map(|e| (e.frame, e.file.as_str()))
            .collect();
        assert_eq!(got, [(0, "a.png"), (1, "b.png"), (2, "c3.png")]);
        // Without a rate, the help names the caller's parameter.
        let e = Sequence::open_with(source(&f), &layout(true, None))
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("a.png: has no time in its name") && e.contains("or set `frame_rate_hz`"),
            "{e}"
        );
        // A rate and frames.csv both: refused.
        let f = f.with(
            "frames.csv",
            b"frame,time_s,file\n0,0.0,a.png\n1,0.5,b.png\n".to_vec(),
        );
        let e = Sequence::open_with(source(&f), &layout(true, Some(2.0)))
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("frames.csv: lists the frames with their times, and `frame_rate_hz`"),
            "{e}"
        );
        // One frame, or none.
        let f = Files::new().with("a.png", vec![]).with("mask.png", vec![]);
        let e = Sequence::open_with(source(&f), &layout(true, Some(2.0)))
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("a.png: is the only PNG/TIFF frame"), "{e}");
        let f = Files::new().with("mask.png", vec![]);
        let e = Sequence::open_with(source(&f), &layout(true, Some(2.0)))
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("frames.csv: missing, and there are no PNG/TIFF frames")
                && e.contains("`0,0.0,img_000.tif`"),
            "{e}"
        );
        for bad in [0.0, -1.0, f64::NAN] {
            let f = Files::new().with("a.png", vec![]).with("b.png", vec![]);
            let e = Sequence::open_with(source(&f), &layout(true, Some(bad)))
                .err()
                .unwrap()
                .to_string();
            assert!(e.contains("`frame_rate_hz`: must be a positive"), "{e}");
        }
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
