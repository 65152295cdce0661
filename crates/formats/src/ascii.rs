//! Height matrices as plain text: one row of the map a line (rows of
//! constant y, values along x separated by blanks), under an optional
//! header that states the grid, the spacing and the units. Gwyddion's ASCII
//! export (`# Channel:`, `# Width:`, `# Height:`, `# Value units:`) and the
//! `key=value` headers of SPIP-style exports (`h=`, `w=`, `pixel size=`,
//! `height conversion factor (-> m)=`) are read.
//!
//! The rules are those of SurfaceTopography's `IO/Text.py` (`AscReader`): a
//! line whose words all parse as numbers is a row (`nan`, `inf`, `bad`
//! mark a point not measured), any other line is a header line; a
//! `Channel:` line starts a new channel; the map's width and height are its
//! physical size, a pixel size times the grid; heights are the values times
//! the conversion factor, in the `Value units` (or `z-unit`). A file of one
//! value a line is a line scan (n × 1).

use std::sync::OnceLock;

use ndarray::Array2;
use regex::Regex;

use crate::bytes::grid_points;
use crate::channel::{self, Channel};
use crate::text::{decode, lines, looks_like_text, number};
use crate::units::metres_per;
use crate::{Format, FormatError, Topography};

const FORMAT: Format = Format::AsciiMatrix;

/// Bytes looked at to tell text from binary.
const SNIFF: usize = 4096;

/// Whether the file starts like one of the headers read here: Gwyddion's
/// export (`# Channel:`) or the `h=… w=…` of SPIP-style exports.
pub(crate) fn matches(bytes: &[u8]) -> bool {
    let head = &bytes[..bytes.len().min(SNIFF)];
    if !looks_like_text(head, SNIFF) {
        return false;
    }
    let text = decode(head);
    let first = lines(&text).next().unwrap_or_default().trim();
    first.starts_with("# Channel:") || (first.starts_with("h=") && first.contains(" w="))
}

/// Whether a file without a known header (found by its `.txt`, `.asc` or
/// `.dat` name) is text with a row of numbers among its first lines.
pub(crate) fn plausible(bytes: &[u8]) -> bool {
    let head = &bytes[..bytes.len().min(SNIFF)];
    looks_like_text(head, SNIFF)
        && lines(&decode(head))
            .take(64)
            .any(|line| row(line).is_some_and(|values| !values.is_empty()))
}

/// The values of a line when every word is a number (or a missing-point
/// keyword), else `None`.
fn row(line: &str) -> Option<Vec<f64>> {
    line.split_whitespace()
        .map(|word| match word.to_ascii_lowercase().as_str() {
            "bad" | "nan" | "inf" | "infinite" => Some(f64::NAN),
            _ => number(word).filter(|v| v.is_finite()),
        })
        .collect()
}

/// What the header lines say, in the file's units.
#[derive(Default)]
struct Header {
    columns: Option<usize>,
    rows: Option<usize>,
    width: Option<(f64, String)>,
    height: Option<(f64, String)>,
    pixel: Option<(f64, String)>,
    x_unit: Option<String>,
    y_unit: Option<String>,
    z_unit: Option<String>,
    z_factor: Option<f64>,
}

/// The patterns of the header lines (SurfaceTopography's `_metadata_regex`).
fn patterns() -> &'static [(Regex, &'static str)] {
    static PATTERNS: OnceLock<Vec<(Regex, &'static str)>> = OnceLock::new();
    const FLOAT: &str = r"([-+]?[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)";
    PATTERNS.get_or_init(|| {
        let rules = [
            (r"\b(?:x-pixels|h)\b\s*=\s*([0-9]+)".to_string(), "rows"),
            (r"\b(?:y-pixels|w)\b\s*=\s*([0-9]+)".to_string(), "columns"),
            (
                format!(r"\b(?:x-length|Width|Breite)\b\s*(?:=|:)\s*{FLOAT}(.*)"),
                "width",
            ),
            (
                format!(r"\b(?:y-length|Height|Höhe)\b\s*(?:=|:)\s*{FLOAT}(.*)"),
                "height",
            ),
            (r"\b(?:x-unit)\b\s*(?:=|:)\s*(\w+)".to_string(), "x_unit"),
            (r"\b(?:y-unit)\b\s*(?:=|:)\s*(\w+)".to_string(), "y_unit"),
            (
                r"\b(?:z-unit|Value units)\b\s*(?:=|:)\s*(\w+)".to_string(),
                "z_unit",
            ),
            (format!(r"(?:pixel\s+size)\s*=\s*{FLOAT}(.*)"), "pixel"),
            (
                format!(r"(?:height\s+conversion\s+factor\s+\(->\s+(.*)\))\s*=\s*{FLOAT}"),
                "z_factor",
            ),
            (
                r"\b(?:Channel|Kanal)\b\s*(?:=|:)\s*([\w|\s]+)".to_string(),
                "channel",
            ),
        ];
        rules
            .into_iter()
            .filter_map(|(pattern, key)| Regex::new(&pattern).ok().map(|r| (r, key)))
            .collect()
    })
}

/// One channel's rows as read.
struct Block {
    name: String,
    rows: Vec<Vec<f64>>,
    /// the line of the first row, for messages
    first_line: usize,
}

impl Header {
    /// Takes what a header line says; returns a channel name it starts.
    fn take(&mut self, line: &str) -> Option<String> {
        let mut channel = None;
        for (pattern, key) in patterns() {
            let Some(found) = pattern.captures(line) else {
                continue;
            };
            let group = |k: usize| found.get(k).map_or("", |m| m.as_str()).trim().to_string();
            let value = |k: usize| number(&group(k));
            match *key {
                "rows" => self.rows = group(1).parse().ok(),
                "columns" => self.columns = group(1).parse().ok(),
                "width" => self.width = value(1).map(|v| (v, group(2))),
                "height" => self.height = value(1).map(|v| (v, group(2))),
                "x_unit" => self.x_unit = Some(group(1)),
                "y_unit" => self.y_unit = Some(group(1)),
                "z_unit" => self.z_unit = Some(group(1)),
                "pixel" => self.pixel = value(1).map(|v| (v, group(2))),
                "z_factor" => {
                    self.z_unit = Some(group(1));
                    self.z_factor = value(2);
                }
                _ => channel = Some(group(1)),
            }
        }
        channel
    }
}

/// The header and the channels' rows of the whole text.
fn parse(text: &str) -> (Header, Vec<Block>) {
    let mut header = Header::default();
    let mut blocks: Vec<Block> = Vec::new();
    let mut current = "Default".to_string();
    for (index, line) in lines(text).enumerate() {
        match row(line) {
            Some(values) if !values.is_empty() => {
                match blocks.iter_mut().find(|b| b.name == current) {
                    Some(block) => block.rows.push(values),
                    None => blocks.push(Block {
                        name: current.clone(),
                        rows: vec![values],
                        first_line: index + 1,
                    }),
                }
            }
            Some(_) => {}
            None => {
                if let Some(name) = header.take(line) {
                    current = name;
                }
            }
        }
    }
    (header, blocks)
}

/// Metres per unit of a header's unit text, or an error naming the key.
fn unit_m(unit: &str, key: &str) -> Result<f64, FormatError> {
    metres_per(unit).ok_or_else(|| {
        FORMAT.unsupported(format!(
            "the header's {key} unit \"{unit}\" is not a length unit"
        ))
    })
}

/// Reads the channel `asked` for.
pub(crate) fn read(
    data: &[u8],
    asked: &Channel,
    max_points: usize,
) -> Result<Topography, FormatError> {
    if !looks_like_text(data, data.len()) {
        return Err(FORMAT.invalid("the file holds bytes that are not text"));
    }
    let text = decode(data);
    let (header, blocks) = parse(&text);
    let names: Vec<String> = blocks.iter().map(|b| b.name.clone()).collect();
    let index = channel::pick(FORMAT, &names, 0, asked)?;
    let block = &blocks[index];
    let columns = block.rows[0].len();
    if let Some(k) = block.rows.iter().position(|r| r.len() != columns) {
        return Err(FORMAT.invalid(format!(
            "channel \"{}\": row {} has {} values, the first row (line {}) {columns}",
            block.name,
            k + 1,
            block.rows[k].len(),
            block.first_line
        )));
    }
    let rows = block.rows.len();
    // one value a line is a line scan along x
    let (nx, ny, line_scan) = if columns == 1 {
        (rows, 1, true)
    } else {
        (columns, rows, false)
    };
    for (stated, found, key) in [(header.columns, columns, "w"), (header.rows, rows, "h")] {
        if stated.is_some_and(|s| s != found) && !line_scan {
            return Err(FORMAT.invalid(format!(
                "the header's {key}={} disagrees with the {found} found",
                stated.unwrap_or_default()
            )));
        }
    }
    // text takes at least two bytes a value, so the rows parsed are bounded
    // by the file; the limit still holds for the map built from them
    grid_points(FORMAT.name(), nx, ny, "the rows and columns", max_points)?;
    let (dx_m, dy_m, z_m) = calibration(&header, nx, ny, line_scan)?;
    let heights_m = if line_scan {
        Array2::from_shape_fn((nx, 1), |(i, _)| block.rows[i][0] * z_m)
    } else {
        Array2::from_shape_fn((nx, ny), |(i, j)| block.rows[j][i] * z_m)
    };
    let mut metadata = Vec::new();
    if line_scan {
        metadata.push(("line_scan".to_string(), "true".to_string()));
    }
    let map = Topography::new(FORMAT, heights_m, dx_m, dy_m, metadata);
    Ok(channel::with_channels(map, &names, index))
}

/// The spacings along x and y and the metres per stored value.
fn calibration(
    header: &Header,
    nx: usize,
    ny: usize,
    line_scan: bool,
) -> Result<(f64, f64, f64), FormatError> {
    let Some(z_unit) = header.z_unit.as_deref() else {
        return Err(FORMAT.unsupported(
            "the file states no height unit (\"Value units\", \"z-unit\" or a height \
             conversion factor): read it as a plain matrix with the spacing and units given",
        ));
    };
    let z_m = header.z_factor.unwrap_or(1.0) * unit_m(z_unit, "height")?;
    // a size stated without a unit is in the height unit (SurfaceTopography)
    let size_m = |size: &Option<(f64, String)>, axis_unit: &Option<String>, key| {
        size.as_ref()
            .map(|(value, unit)| {
                let unit = if unit.is_empty() {
                    axis_unit.as_deref().unwrap_or(z_unit)
                } else {
                    unit.as_str()
                };
                unit_m(unit, key).map(|m| value * m)
            })
            .transpose()
    };
    let pixel_m = size_m(&header.pixel, &header.x_unit, "pixel size")?;
    let width_m = size_m(&header.width, &header.x_unit, "width")?;
    let height_m = size_m(&header.height, &header.y_unit, "height")?;
    let dx_m = width_m.map(|w| w / nx as f64).or(pixel_m);
    let dy_m = height_m.map(|h| h / ny as f64).or(pixel_m);
    let (dx_m, dy_m) = match (dx_m, dy_m, line_scan) {
        (Some(dx), _, true) => (dx, dx),
        (Some(dx), Some(dy), false) => (dx, dy),
        _ => {
            return Err(FORMAT.unsupported(
                "the header states no width and height or pixel size: the grid spacing is unknown",
            ));
        }
    };
    if !(dx_m.is_finite() && dx_m > 0.0 && dy_m.is_finite() && dy_m > 0.0 && z_m.is_finite()) {
        return Err(FORMAT.invalid(format!(
            "the header gives the spacings {dx_m} m × {dy_m} m and {z_m} m per value"
        )));
    }
    Ok((dx_m, dy_m, z_m))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gwyddion_exports_are_rows_of_constant_y() {
        let file = "# Channel: Topo\n# Width: 3 µm\n# Height: 2 µm\n# Value units: nm\n\
                    1 2 3\n4 nan 6\n";
        assert!(matches(file.as_bytes()));
        let map = read(
            file.as_bytes(),
            &Channel::Default,
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap();
        assert_eq!(map.heights_m.dim(), (3, 2));
        assert_eq!(map.heights_m[[2, 0]], 3.0 * 1e-9);
        assert_eq!(map.heights_m[[0, 1]], 4.0 * 1e-9);
        assert!(map.heights_m[[1, 1]].is_nan());
        assert_eq!((map.dx_m, map.dy_m), (1e-6, 1e-6));
        assert_eq!(map.metadata[0], ("channel".into(), "Topo".into()));
    }

    #[test]
    fn channels_follow_their_header_line() {
        let file = "# Value units: m\n# Width: 2 m\n# Height: 2 m\n# Channel: A\n1 2\n3 4\n\
                    # Channel: B\n5 6\n7 8\n";
        let b = read(
            file.as_bytes(),
            &Channel::Name("b".into()),
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap();
        assert_eq!(b.heights_m[[0, 0]], 5.0);
        let err = read(
            file.as_bytes(),
            &Channel::Index(2),
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap_err();
        assert!(err.to_string().contains("0: A; 1: B"), "{err}");
    }

    #[test]
    fn one_value_a_line_is_a_line_scan_and_ragged_rows_are_named() {
        let file = "# Value units: um\n# Width: 4 um\n1\n2\n3\n4\n";
        let map = read(
            file.as_bytes(),
            &Channel::Default,
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap();
        assert_eq!(map.heights_m.dim(), (4, 1));
        assert_eq!((map.dx_m, map.dy_m), (1e-6, 1e-6));
        let ragged = "# Value units: m\n# Width: 2 m\n# Height: 2 m\n1 2\n3\n";
        let err = read(
            ragged.as_bytes(),
            &Channel::Default,
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("row 2 has 1 values"), "{err}");
    }

    #[test]
    fn a_matrix_without_units_is_refused_with_the_reason() {
        let err = read(b"1 2\n3 4\n", &Channel::Default, crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(err.contains("no height unit"), "{err}");
        assert!(plausible(b"1 2\n3 4\n"));
        assert!(!plausible(b"\x00\x01"));
        assert!(!matches(b"1 2\n3 4\n"));
    }
}
