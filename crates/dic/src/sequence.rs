//! The tensile test's raw files, from a `Files` product or a folder of real
//! data, in the layout `synth-tensile` writes:
//! `frames.csv` (`frame, time_s, file`), the images it names (PNG or TIFF,
//! 8 or 16 bit), `force.csv` (`time_s, force_n`) and, optionally,
//! `specimen.json` (`mode`, `gauge_width_m`, `thickness_m`, `pixel_m`,
//! `roi_px`).

use std::borrow::Cow;
use std::path::PathBuf;

use hypercontact_core::Files;
use serde::Deserialize;

use crate::DicError;
use crate::gray::GrayImage;

/// Where the files come from.
pub enum Source<'a> {
    Files(&'a Files),
    Dir(PathBuf),
}

/// One row of `frames.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameEntry {
    pub frame: i64,
    pub time_s: f64,
    pub file: String,
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
    source: Source<'a>,
    pub frames: Vec<FrameEntry>,
    /// (time_s, force_n), increasing in time.
    pub force: Vec<(f64, f64)>,
    pub specimen: Specimen,
}

impl<'a> Sequence<'a> {
    pub fn open(source: Source<'a>) -> Result<Self, DicError> {
        let mut sequence = Sequence {
            source,
            frames: Vec::new(),
            force: Vec::new(),
            specimen: Specimen::default(),
        };
        let frames_csv = sequence.read("frames.csv")?;
        sequence.frames = parse_frames(&csv_rows(
            "frames.csv",
            &frames_csv,
            &["frame", "time_s", "file"],
        )?)?;
        let force_csv = sequence.read("force.csv")?;
        sequence.force = parse_force(&csv_rows("force.csv", &force_csv, &["time_s", "force_n"])?)?;
        if sequence.exists("specimen.json") {
            let bytes = sequence.read("specimen.json")?;
            sequence.specimen = serde_json::from_slice(&bytes).map_err(|e| {
                DicError::file(
                    "specimen.json",
                    format!("not a valid specimen description: {e}"),
                )
            })?;
        }
        Ok(sequence)
    }

    fn exists(&self, name: &str) -> bool {
        match &self.source {
            Source::Files(files) => files.files.contains_key(name),
            Source::Dir(dir) => dir.join(name).is_file(),
        }
    }

    /// The bytes of file `name`.
    pub fn read(&self, name: &str) -> Result<Cow<'a, [u8]>, DicError> {
        match &self.source {
            Source::Files(files) => files
                .files
                .get(name)
                .map(|b| Cow::Borrowed(b.as_slice()))
                .ok_or_else(|| DicError::file(name, "missing from the `sequence` input")),
            Source::Dir(dir) => {
                let path = dir.join(name);
                std::fs::read(&path)
                    .map(Cow::Owned)
                    .map_err(|e| DicError::file(&path.display().to_string(), e.to_string()))
            }
        }
    }

    /// Decodes frame `k` (index into `frames`).
    pub fn image(&self, k: usize) -> Result<GrayImage, DicError> {
        let name = &self.frames[k].file;
        GrayImage::decode(name, &self.read(name)?)
    }

    /// The force at `t_s` by linear interpolation of the log; an error names
    /// the frame if the log does not cover it.
    pub fn force_at(&self, t_s: f64, frame: &FrameEntry) -> Result<f64, DicError> {
        let (first, last) = (self.force[0].0, self.force[self.force.len() - 1].0);
        let slack = 1e-9 * (1.0 + last.abs());
        if t_s < first - slack || t_s > last + slack {
            return Err(DicError::file(
                "force.csv",
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

/// The rows of a small CSV with a header, as the cells of the `wanted`
/// columns (by name, any order, extra columns ignored).
fn csv_rows(
    name: &str,
    bytes: &[u8],
    wanted: &[&str],
) -> Result<Vec<(usize, Vec<String>)>, DicError> {
    let text = std::str::from_utf8(bytes).map_err(|_| DicError::file(name, "is not UTF-8 text"))?;
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (_, header) = lines
        .next()
        .ok_or_else(|| DicError::file(name, "is empty"))?;
    let header: Vec<&str> = header.split(',').map(str::trim).collect();
    let columns: Vec<usize> = wanted
        .iter()
        .map(|w| {
            header.iter().position(|h| h == w).ok_or_else(|| {
                DicError::file(
                    name,
                    format!("has no column `{w}` (header: {})", header.join(", ")),
                )
            })
        })
        .collect::<Result<_, _>>()?;
    let mut rows = Vec::new();
    for (line, text) in lines {
        let cells: Vec<&str> = text.split(',').map(str::trim).collect();
        let row = columns
            .iter()
            .map(|&c| {
                cells.get(c).map(|s| s.to_string()).ok_or_else(|| {
                    DicError::file(
                        name,
                        format!(
                            "line {line}: {} cells, expected {}",
                            cells.len(),
                            header.len()
                        ),
                    )
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        rows.push((line, row));
    }
    if rows.is_empty() {
        return Err(DicError::file(name, "has a header but no rows"));
    }
    Ok(rows)
}

fn number(name: &str, line: usize, column: &str, cell: &str) -> Result<f64, DicError> {
    match cell.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(DicError::file(
            name,
            format!("line {line}, column `{column}`: `{cell}` is not a finite number"),
        )),
    }
}

fn parse_frames(rows: &[(usize, Vec<String>)]) -> Result<Vec<FrameEntry>, DicError> {
    let mut frames = Vec::with_capacity(rows.len());
    for (line, cells) in rows {
        let frame = cells[0].parse::<i64>().map_err(|_| {
            DicError::file(
                "frames.csv",
                format!(
                    "line {line}, column `frame`: `{}` is not an integer",
                    cells[0]
                ),
            )
        })?;
        let time_s = number("frames.csv", *line, "time_s", &cells[1])?;
        if let Some(prev) = frames.last().map(|f: &FrameEntry| f.time_s)
            && time_s <= prev
        {
            return Err(DicError::file(
                "frames.csv",
                format!("line {line}: time_s = {time_s} does not increase (previous {prev})"),
            ));
        }
        frames.push(FrameEntry {
            frame,
            time_s,
            file: cells[2].clone(),
        });
    }
    if frames.len() < 2 {
        return Err(DicError::file("frames.csv", "lists fewer than 2 frames"));
    }
    Ok(frames)
}

fn parse_force(rows: &[(usize, Vec<String>)]) -> Result<Vec<(f64, f64)>, DicError> {
    let mut force: Vec<(f64, f64)> = Vec::with_capacity(rows.len());
    for (line, cells) in rows {
        let t = number("force.csv", *line, "time_s", &cells[0])?;
        let f = number("force.csv", *line, "force_n", &cells[1])?;
        if let Some(&(prev, _)) = force.last()
            && t <= prev
        {
            return Err(DicError::file(
                "force.csv",
                format!("line {line}: time_s = {t} does not increase (previous {prev})"),
            ));
        }
        force.push((t, f));
    }
    Ok(force)
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let s = Sequence::open(Source::Files(&f)).unwrap();
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
        let s = Sequence::open(Source::Files(&f)).unwrap();
        let e = s.force_at(0.5, &s.frames[1]).unwrap_err().to_string();
        assert!(e.contains("force.csv") && e.contains("b.png"), "{e}");
        let f = files(
            "frame,time_s,file\n0,0.0,a.png\n1,x,b.png\n",
            "time_s,force_n\n0,0\n",
        );
        let e = Sequence::open(Source::Files(&f)).err().unwrap().to_string();
        assert!(e.contains("frames.csv") && e.contains("line 3"), "{e}");
        let f = files("frame,t,file\n0,0.0,a.png\n", "time_s,force_n\n0,0\n");
        let e = Sequence::open(Source::Files(&f)).err().unwrap().to_string();
        assert!(e.contains("no column `time_s`"), "{e}");
        let f = Files::new();
        let e = Sequence::open(Source::Files(&f)).err().unwrap().to_string();
        assert!(e.contains("frames.csv") && e.contains("missing"), "{e}");
    }
}
