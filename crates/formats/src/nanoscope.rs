//! Bruker / Veeco / Digital Instruments Nanoscope files (`.di`, `.spm`,
//! `.001`…, version 4.3 and later): a Latin-1 text header of sections
//! (`\*File list` … `\*File list end`) holding `\key: value` lines, then
//! the images as little-endian `i16` or `i32` counts, each at its `Data
//! offset`, stored as `Number of lines` rows of `Samps/line` values.
//!
//! Every `\*Ciao image list` section is a channel, named as in its `@2:Image
//! Data` (`S [Height] "Height"` → Height). Its heights are, after the
//! Nanoscope file-format notes (Manne's `fileformats.html`), Gwyddion's
//! `nanoscope.c` and SurfaceTopography's `IO/DI.py`:
//!
//! h = count × (hard scale / 65536) × (soft scale) [× 1/65536 for 4-byte counts],
//!
//! the hard scale being the last number of `@2:Z scale: V [Sens. Zsens]
//! (… V/LSB) 2.910461 V` and the soft scale the number of the scanner's
//! `@Sens. Zsens: V 20.82646 nm/V`, whose numerator unit is the height
//! unit. The y axis is flipped (the first row stored is the last of the
//! map), as SurfaceTopography and Gwyddion show it. A channel not in a
//! length unit (phase, amplitude) is listed but not read as heights.

use std::sync::OnceLock;

use ndarray::Array2;
use regex::Regex;

use crate::bytes::{ByteOrder, Bytes, grid_points};
use crate::channel::{self, Channel};
use crate::text::{decode, lines};
use crate::units::metres_per;
use crate::{Format, FormatError, Topography};

const FORMAT: Format = Format::Nanoscope;

const MAGIC: &[u8] = b"\\*File list";
const END: &str = "\\*file list end";

/// Whether the file starts with the header's first section.
pub(crate) fn matches(bytes: &[u8]) -> bool {
    bytes.starts_with(MAGIC)
}

/// A section of the header: its name (lower case) and `key: value` lines
/// (keys lower case).
struct Section {
    name: String,
    entries: Vec<(String, String)>,
}

impl Section {
    fn get(&self, key: &str) -> Option<&str> {
        crate::lookup(&self.entries, key).map(String::as_str)
    }
}

/// The header's sections, up to `\*File list end`.
fn sections(data: &[u8]) -> Result<Vec<Section>, FormatError> {
    let end = find_end(data)
        .ok_or_else(|| FORMAT.invalid("the header has no \"\\*File list end\" line"))?;
    let text = decode(&data[..end]);
    let mut sections: Vec<Section> = Vec::new();
    for (index, line) in lines(&text).enumerate() {
        let line = line.trim();
        if let Some(name) = line.strip_prefix("\\*") {
            sections.push(Section {
                name: name.to_ascii_lowercase(),
                entries: Vec::new(),
            });
        } else if let Some(entry) = line.strip_prefix('\\') {
            let Some(section) = sections.last_mut() else {
                return Err(FORMAT.invalid(format!("line {}: a key before any section", index + 1)));
            };
            let (key, value) = entry.split_once(": ").unwrap_or((entry, ""));
            section
                .entries
                .push((key.to_ascii_lowercase(), value.trim().to_string()));
        } else if !line.is_empty() {
            return Err(FORMAT.invalid(format!(
                "line {}: a header line that does not start with a backslash",
                index + 1
            )));
        }
    }
    Ok(sections)
}

/// The byte where the `\*File list end` line starts (the header is at most
/// the file, and Latin-1, so the search is on bytes).
fn find_end(data: &[u8]) -> Option<usize> {
    data.windows(END.len())
        .position(|w| w.eq_ignore_ascii_case(END.as_bytes()))
}

/// What one image section says.
struct Image {
    name: String,
    nx: usize,
    ny: usize,
    offset: usize,
    length: usize,
    bytes_per_count: usize,
    dx_m: f64,
    dy_m: f64,
    /// metres per count, or why the counts are not heights
    metres_per_count: Result<f64, String>,
    direction: String,
}

/// A number of a header value, or an error naming the key.
fn parse<T: std::str::FromStr>(value: Option<&str>, key: &str) -> Result<T, FormatError> {
    let value = value.ok_or_else(|| FORMAT.invalid(format!("an image has no \"{key}\"")))?;
    value
        .trim()
        .parse()
        .map_err(|_| FORMAT.invalid(format!("\"{key}: {value}\" is not a number")))
}

fn image(
    section: &Section,
    scanner: &[(String, String)],
    max_points: usize,
) -> Result<Image, FormatError> {
    let data_key = section.get("@2:image data").unwrap_or_default();
    static NAME: OnceLock<Option<Regex>> = OnceLock::new();
    let name = NAME
        .get_or_init(|| Regex::new(r"^S \[(.*?)\] ").ok())
        .as_ref()
        .and_then(|r| r.captures(data_key).map(|c| c[1].to_string()))
        .ok_or_else(|| FORMAT.invalid(format!("\"@2:Image Data: {data_key}\" names no image")))?;
    let nx: usize = parse(section.get("samps/line"), "Samps/line")?;
    let ny: usize = parse(section.get("number of lines"), "Number of lines")?;
    grid_points(FORMAT.name(), nx, ny, &format!("image {name}"), max_points)?;
    let size = section.get("scan size").unwrap_or_default();
    let mut words = size.splitn(3, ' ');
    let sx: f64 = parse(words.next(), "Scan Size")?;
    let sy: f64 = parse(words.next(), "Scan Size")?;
    let xy_unit = words.next().unwrap_or_default().replace('~', "µ");
    let xy_m = metres_per(&xy_unit).ok_or_else(|| {
        FORMAT.unsupported(format!("image {name}: the scan size unit \"{xy_unit}\""))
    })?;
    let bytes_per_count: usize = parse(section.get("bytes/pixel"), "Bytes/pixel")?;
    Ok(Image {
        nx,
        ny,
        offset: parse(section.get("data offset"), "Data offset")?,
        length: parse(section.get("data length"), "Data length")?,
        bytes_per_count,
        dx_m: sx * xy_m / nx as f64,
        dy_m: sy * xy_m / ny as f64,
        metres_per_count: z_scale(section, scanner, bytes_per_count),
        direction: section
            .get("line direction")
            .unwrap_or_default()
            .to_string(),
        name,
    })
}

/// Metres per count of an image (see the module's formula), or why its
/// counts are not heights (kept, so that the other channels still read).
fn z_scale(
    section: &Section,
    scanner: &[(String, String)],
    bytes_per_count: usize,
) -> Result<f64, String> {
    let z_scale = section.get("@2:z scale").unwrap_or_default();
    static SCALE: OnceLock<Option<Regex>> = OnceLock::new();
    let pattern = SCALE
        .get_or_init(|| Regex::new(r"^V (?:\[(.*?)\]|)\s*\(([0-9\.]+) (.*)/LSB\) (.*) (.*)").ok());
    let Some(found) = pattern.as_ref().and_then(|p| p.captures(z_scale)) else {
        return Err(format!("its \"@2:Z scale: {z_scale}\" is not read"));
    };
    let hard: f64 = found[4]
        .parse()
        .map_err(|_| format!("its Z scale \"{}\" is not a number", &found[4]))?;
    let hard_unit = &found[5];
    let binary = match bytes_per_count {
        2 => 1.0,
        // 32-bit counts span the 16-bit range times 65536
        4 => 1.0 / 65536.0,
        other => return Err(format!("it has {other} bytes per pixel (2 or 4 are read)")),
    };
    let Some(quantity) = found.get(1).map(|m| m.as_str().to_ascii_lowercase()) else {
        return Err(format!("it is in \"{hard_unit}\", not a length"));
    };
    let key = format!("@{quantity}");
    let soft = scanner
        .iter()
        .rev()
        .find(|(k, _)| *k == key)
        .map(|(_, v)| v.as_str())
        .ok_or_else(|| format!("the scanner list has no \"{key}\""))?;
    let words: Vec<&str> = soft.split_whitespace().collect();
    let soft_scale: f64 = match words[..] {
        ["V", value, ..] => value
            .parse()
            .map_err(|_| format!("\"{key}: {soft}\" is not a V value"))?,
        _ => return Err(format!("\"{key}: {soft}\" is not a V value")),
    };
    let Some((height_unit, soft_unit)) = words.get(2).and_then(|u| u.split_once('/')) else {
        return Err(format!(
            "its sensitivity \"{soft}\" has no unit: not a length"
        ));
    };
    let Some(hard_to_soft) = volts(hard_unit).zip(volts(soft_unit)).map(|(h, s)| h / s) else {
        return Err(format!(
            "the Z scale's unit \"{hard_unit}\" and the sensitivity's \"{soft_unit}\" differ"
        ));
    };
    let height_unit = height_unit.replace('~', "µ");
    match metres_per(&height_unit) {
        Some(m) => Ok(hard / 65536.0 * hard_to_soft * soft_scale * binary * m),
        None => Err(format!("it is in \"{height_unit}\", not a length")),
    }
}

/// Volts per unit of a voltage unit.
fn volts(unit: &str) -> Option<f64> {
    match unit {
        "V" => Some(1.0),
        "mV" => Some(1e-3),
        "uV" | "µV" => Some(1e-6),
        _ => None,
    }
}

/// Reads the channel `asked` for.
pub(crate) fn read(
    data: &[u8],
    asked: &Channel,
    max_points: usize,
) -> Result<Topography, FormatError> {
    let sections = sections(data)?;
    if sections.first().map(|s| s.name.as_str()) != Some("file list") {
        return Err(FORMAT.invalid("the header does not start with \\*File list"));
    }
    let scanner: Vec<(String, String)> = sections
        .iter()
        .filter(|s| s.name == "scanner list" || s.name == "ciao scan list")
        .flat_map(|s| s.entries.iter().cloned())
        .collect();
    let images = sections
        .iter()
        .filter(|s| s.name == "ciao image list")
        .map(|s| image(s, &scanner, max_points))
        .collect::<Result<Vec<Image>, FormatError>>()?;
    let names: Vec<String> = images.iter().map(|i| i.name.clone()).collect();
    let index = channel::pick(FORMAT, &names, 0, asked)?;
    let image = &images[index];
    let metres_per_count = image.metres_per_count.clone().map_err(|why| {
        FORMAT.unsupported(format!(
            "channel {index} ({}) is not a height map: {why}",
            image.name
        ))
    })?;
    let (nx, ny) = (image.nx, image.ny);
    let bytes = Bytes::new(data, FORMAT.name(), ByteOrder::Little);
    let what = format!("image {} at byte {}", image.name, image.offset);
    if nx * ny * image.bytes_per_count > image.length {
        return Err(FORMAT.invalid(format!(
            "{what}: {nx} × {ny} counts of {} bytes exceed its Data length {}",
            image.bytes_per_count, image.length
        )));
    }
    let counts: Vec<f64> = if image.bytes_per_count == 2 {
        let counts = bytes.values::<i16>(image.offset, nx * ny, &what)?;
        counts.into_iter().map(f64::from).collect()
    } else {
        let counts = bytes.values::<i32>(image.offset, nx * ny, &what)?;
        counts.into_iter().map(f64::from).collect()
    };
    // the first row stored is the map's last (y flipped)
    let heights_m = Array2::from_shape_fn((nx, ny), |(i, j)| {
        counts[(ny - 1 - j) * nx + i] * metres_per_count
    });
    let mut metadata = vec![("vendor".to_string(), "Bruker".to_string())];
    let file_list = &sections[0];
    for (key, name) in [("date", "date"), ("version", "version")] {
        if let Some(value) = file_list.get(key) {
            metadata.push((name.into(), value.into()));
        }
    }
    if let Some(microscope) = sections
        .iter()
        .filter(|s| s.name == "equipment list")
        .find_map(|s| s.get("microscope"))
    {
        metadata.push(("instrument".into(), microscope.into()));
    }
    if !image.direction.is_empty() {
        metadata.push(("line_direction".into(), image.direction.clone()));
    }
    // `Samps/line` counts a scan line's points: each stored row is a line
    metadata.push((crate::FAST_AXIS.into(), "x".into()));
    FORMAT.check_spacings(
        image.dx_m,
        image.dy_m,
        format_args!("image {}: the scan size", image.name),
    )?;
    let map = Topography::new(FORMAT, heights_m, image.dx_m, image.dy_m, metadata);
    Ok(channel::with_channels(map, &names, index))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A header with one 2 × 2 height image of i16 counts after it.
    fn file(counts: [i16; 4]) -> Vec<u8> {
        let header = "\\*File list\r\n\\Version: 0x07200000\r\n\\*Scanner list\r\n\
                      \\@Sens. Zsens: V 2 nm/V\r\n\\@Sens. Phase: V 1.000000 \r\n\\*Ciao image list\r\n\\Data offset: 1024\r\n\
                      \\Data length: 8\r\n\\Bytes/pixel: 2\r\n\\Samps/line: 2\r\n\
                      \\Number of lines: 2\r\n\\Scan Size: 4 2 ~m\r\n\
                      \\@2:Image Data: S [Height] \"Height\"\r\n\
                      \\@2:Z scale: V [Sens. Zsens] (0.1 V/LSB) 65536 V\r\n\
                      \\*Ciao image list\r\n\\Data offset: 1024\r\n\\Data length: 8\r\n\
                      \\Bytes/pixel: 2\r\n\\Samps/line: 2\r\n\\Number of lines: 2\r\n\
                      \\Scan Size: 4 2 ~m\r\n\\@2:Image Data: S [Phase] \"Phase\"\r\n\
                      \\@2:Z scale: V [Sens. Phase] (0.1 º/LSB) 360 º\r\n\\*File list end\r\n";
        let mut f = header.as_bytes().to_vec();
        f.resize(1024, 0);
        for c in counts {
            f.extend(c.to_le_bytes());
        }
        f
    }

    #[test]
    fn counts_times_hard_and_soft_scale_with_y_flipped() {
        let f = file([1, 2, 3, 4]);
        assert!(matches(&f));
        let map = read(&f, &Channel::Default, crate::DEFAULT_MAX_POINTS).unwrap();
        // 65536 V / 65536 per count × 2 nm/V = 2 nm per count
        assert_eq!(map.heights_m[[0, 0]], 3.0 * 2e-9);
        assert_eq!(map.heights_m[[1, 1]], 2.0 * 2e-9);
        assert_eq!((map.dx_m, map.dy_m), (2e-6, 1e-6));
        assert_eq!(
            map.metadata[1],
            ("channels".into(), "0: Height; 1: Phase".into())
        );
    }

    #[test]
    fn phase_is_listed_but_not_a_height_map() {
        let err = read(
            &file([0; 4]),
            &Channel::Name("phase".into()),
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap_err();
        assert!(
            err.to_string().contains("has no unit: not a length"),
            "{err}"
        );
        let f = file([0; 4]);
        let err = read(
            &f[..f.len() - 1],
            &Channel::Default,
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("image Height at byte 1024"), "{err}");
    }
}
