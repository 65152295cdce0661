//! Molecular Imaging / Agilent PicoView `.mi` images: a text header of
//! lines with the key in the first 14 columns and the value after it
//! (`xPixels`, `yPixels`, `xLength`, `yLength` in metres, `scanUp`), one
//! block per channel from its `bufferLabel` line on (`bufferUnit`,
//! `bufferRange`), then the line `data          BINARY` (`i16` counts) or
//! `BINARY_32` (`i32`) and the channels' counts one channel after another,
//! little-endian, in rows of constant y.
//!
//! A count c is the value c / 2^15 (or 2^31) × bufferRange in bufferUnit,
//! and a scan recorded upwards (`scanUp TRUE`) is flipped in y, as in
//! SurfaceTopography's `IO/MI.py` (after Gwyddion's `mifile.c`). Channels
//! not in a length unit (deflection and friction in V) are listed but not
//! read as heights; ASCII data and spectroscopy files are not read.

use ndarray::Array2;

use crate::bytes::{ByteOrder, Bytes, grid_points};
use crate::channel::{self, Channel};
use crate::text::decode;
use crate::units::metres_per;
use crate::{Format, FormatError, Topography};

const FORMAT: Format = Format::Mi;

const IMAGE: &[u8] = b"fileType      Image";
const SPECTROSCOPY: &[u8] = b"fileType      Spectroscopy";
const KEY_WIDTH: usize = 14;

/// Whether the file starts as a PicoView image or spectroscopy file.
pub(crate) fn matches(bytes: &[u8]) -> bool {
    bytes.starts_with(IMAGE) || bytes.starts_with(SPECTROSCOPY)
}

/// A channel's header block.
struct Buffer {
    name: String,
    unit: String,
    range: Option<f64>,
}

/// The header: global entries, the channels, the count width and where the
/// counts start.
struct Header {
    entries: Vec<(String, String)>,
    buffers: Vec<Buffer>,
    count_bytes: usize,
    data_start: usize,
}

impl Header {
    fn get(&self, key: &str) -> Option<&str> {
        crate::lookup(&self.entries, key).map(String::as_str)
    }

    fn number(&self, key: &str) -> Result<f64, FormatError> {
        self.get(key)
            .and_then(|v| v.parse().ok())
            .ok_or_else(|| FORMAT.invalid(format!("the header has no number {key}")))
    }
}

fn parse(data: &[u8]) -> Result<Header, FormatError> {
    if data.starts_with(SPECTROSCOPY) {
        return Err(FORMAT.unsupported("a spectroscopy file, not an image"));
    }
    let mut header = Header {
        entries: Vec::new(),
        buffers: Vec::new(),
        count_bytes: 0,
        data_start: 0,
    };
    let mut at = 0;
    while at < data.len() {
        let end = data[at..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(data.len(), |p| at + p);
        let line = decode(&data[at..end]);
        let line = line.trim_end_matches('\r');
        at = end + 1;
        if let Some(kind) = line.strip_prefix("data ") {
            header.count_bytes = match kind.trim() {
                "BINARY" => 2,
                "BINARY_32" => 4,
                other => {
                    return Err(FORMAT.unsupported(format!(
                        "data stored as \"{other}\" (BINARY and BINARY_32 are read)"
                    )));
                }
            };
            header.data_start = at;
            return Ok(header);
        }
        if line.starts_with(' ') || line.is_empty() {
            continue;
        }
        let split = line
            .char_indices()
            .nth(KEY_WIDTH)
            .map_or(line.len(), |(i, _)| i);
        let (key, value) = (line[..split].trim(), line[split..].trim());
        if key == "bufferLabel" {
            header.buffers.push(Buffer {
                name: value.to_string(),
                unit: String::new(),
                range: None,
            });
        }
        match header.buffers.last_mut() {
            Some(buffer) if key == "bufferUnit" => buffer.unit = value.to_string(),
            Some(buffer) if key == "bufferRange" => buffer.range = value.parse().ok(),
            Some(_) => {}
            None => header.entries.push((key.to_string(), value.to_string())),
        }
    }
    Err(FORMAT.invalid("no \"data\" line ends the header"))
}

/// Reads the channel `asked` for.
pub(crate) fn read(
    data: &[u8],
    asked: &Channel,
    max_points: usize,
) -> Result<Topography, FormatError> {
    let header = parse(data)?;
    let names: Vec<String> = header.buffers.iter().map(|b| b.name.clone()).collect();
    let index = channel::pick(FORMAT, &names, 0, asked)?;
    let buffer = &header.buffers[index];
    let unit_m = metres_per(&buffer.unit).ok_or_else(|| {
        FORMAT.unsupported(format!(
            "channel {index} ({}) is in \"{}\", not a length: not a height map",
            buffer.name, buffer.unit
        ))
    })?;
    let range = buffer
        .range
        .ok_or_else(|| FORMAT.invalid(format!("channel {} has no bufferRange", buffer.name)))?;
    let count = |key: &str| -> Result<usize, FormatError> {
        let value = header.number(key)?;
        (value >= 1.0 && value.fract() == 0.0 && value < 1e9)
            .then_some(value as usize)
            .ok_or_else(|| FORMAT.invalid(format!("{key} {value} is not a grid size")))
    };
    let (nx, ny) = (count("xPixels")?, count("yPixels")?);
    let points = grid_points(FORMAT.name(), nx, ny, "xPixels and yPixels", max_points)?;
    let (dx_m, dy_m) = (
        header.number("xLength")? / nx as f64,
        header.number("yLength")? / ny as f64,
    );
    FORMAT.check_spacings(dx_m, dy_m, "xLength and yLength")?;
    let bytes = Bytes::new(data, FORMAT.name(), ByteOrder::Little);
    let at = header.data_start + index * points * header.count_bytes;
    let what = format!("channel {} at byte {at}", buffer.name);
    let (counts, full_scale): (Vec<f64>, f64) = if header.count_bytes == 2 {
        let counts = bytes.values::<i16>(at, points, &what)?;
        (counts.into_iter().map(f64::from).collect(), 32768.0)
    } else {
        let counts = bytes.values::<i32>(at, points, &what)?;
        (counts.into_iter().map(f64::from).collect(), 2_147_483_648.0)
    };
    let scan_up = header
        .get("scanUp")
        .is_some_and(|v| v.eq_ignore_ascii_case("TRUE"));
    // SurfaceTopography's order: count / full scale, × range, × metres per unit
    let heights_m = Array2::from_shape_fn((nx, ny), |(i, j)| {
        let row = if scan_up { ny - 1 - j } else { j };
        counts[row * nx + i] / full_scale * range * unit_m
    });
    let mut metadata = vec![("vendor".to_string(), "Molecular Imaging".to_string())];
    for (key, name) in [
        ("dateAcquired", "date"),
        ("mode", "mode"),
        ("version", "software"),
    ] {
        if let Some(value) = header.get(key).filter(|v| !v.is_empty()) {
            metadata.push((name.into(), value.into()));
        }
    }
    // the counts come in rows of constant y, one scan line each (`scanUp`
    // says which way the lines followed each other)
    metadata.push((crate::FAST_AXIS.into(), "x".into()));
    let map = Topography::new(FORMAT, heights_m, dx_m, dy_m, metadata);
    Ok(channel::with_channels(map, &names, index))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(scan_up: bool) -> Vec<u8> {
        let mut f = format!(
            "fileType      Image\nxPixels       2\nyPixels       2\nxLength       4e-6\n\
             yLength       2e-6\nscanUp        {}\nbufferLabel   Topography\n\
             bufferRange   2\nbufferUnit    um\nbufferLabel   Deflection\nbufferUnit    V\n\
             data          BINARY\n",
            if scan_up { "TRUE" } else { "FALSE" }
        )
        .into_bytes();
        for c in [16384i16, -16384, 0, 8192, 1, 1, 1, 1] {
            f.extend(c.to_le_bytes());
        }
        f
    }

    #[test]
    fn counts_scale_by_the_range_and_scan_up_flips_y() {
        let map = read(&file(false), &Channel::Default, crate::DEFAULT_MAX_POINTS).unwrap();
        assert_eq!(map.heights_m[[0, 0]], 1e-6);
        assert_eq!(map.heights_m[[1, 0]], -1e-6);
        assert_eq!(map.heights_m[[1, 1]], 0.5e-6);
        assert_eq!((map.dx_m, map.dy_m), (2e-6, 1e-6));
        let up = read(&file(true), &Channel::Default, crate::DEFAULT_MAX_POINTS).unwrap();
        assert_eq!(up.heights_m[[1, 0]], 0.5e-6);
    }

    #[test]
    fn volts_are_not_heights_and_truncations_are_named() {
        let err = read(
            &file(false),
            &Channel::Name("deflection".into()),
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap_err();
        assert!(err.to_string().contains("\"V\", not a length"), "{err}");
        let f = file(false);
        let err = read(
            &f[..f.len() - 9],
            &Channel::Default,
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("channel Topography"), "{err}");
        assert!(
            read(
                b"fileType      Image\n",
                &Channel::Default,
                crate::DEFAULT_MAX_POINTS
            )
            .is_err()
        );
    }
}
