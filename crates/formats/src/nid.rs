//! Nanosurf easyScan / DriveAFM `.nid` (and `.ezd`) files: an INI-style
//! Latin-1 header (`[Section]` lines and `key=value` lines) ended by `#!`,
//! then the images one after another in the order the `[DataSet]` section
//! lists them (`Gr{group}-Ch{channel}` for each group's `Gr{i}-Count`
//! slots, empty slots skipped). Each image's section gives `Points` ×
//! `Lines`, the lateral ranges `Dim0Range`, `Dim1Range` (in `Dim0Unit`,
//! `Dim1Unit`) and the value range `Dim2Min`, `Dim2Range` (in `Dim2Unit`)
//! that the `SaveBits`-bit counts span; `SaveSign` and `SaveOrder` (Intel =
//! little-endian) say how they are stored.
//!
//! As in SurfaceTopography's `IO/EZD.py` (after Gwyddion's `nanosurf.c`),
//! only the images in a length unit are channels, named `Frame (Dim2Name)`,
//! and the y axis is flipped. A count c is the value
//! c · Dim2Range / 2^bits + (Dim2Min + Dim2Range / 2) for signed counts
//! (+ Dim2Min for unsigned ones): SurfaceTopography leaves out the offset,
//! which is exactly zero when the range is centred on zero, as in the
//! reference file.

use ndarray::Array2;

use crate::bytes::{ByteOrder, Bytes, grid_points};
use crate::channel::{self, Channel};
use crate::text::{decode, lines};
use crate::units::metres_per;
use crate::{Format, FormatError, Topography};

const FORMAT: Format = Format::Nid;

const DATA_MARK: &[u8] = b"#!";

/// Whether the file starts with the `[DataSet]` section.
pub(crate) fn matches(bytes: &[u8]) -> bool {
    bytes.starts_with(b"[DataSet]\r\n") || bytes.starts_with(b"[DataSet]\n")
}

/// The header's sections: name and `key=value` entries, in file order.
type Sections = Vec<(String, Vec<(String, String)>)>;

/// The header (before the `#!` that starts a line) and where the data start.
fn header(data: &[u8]) -> Result<(Sections, usize), FormatError> {
    let mut at = 0;
    let end = loop {
        if data[at..].starts_with(DATA_MARK) {
            break at;
        }
        match data[at..].iter().position(|&b| b == b'\n') {
            Some(newline) => at += newline + 1,
            None => return Err(FORMAT.invalid("no line starting with #! ends the header")),
        }
    };
    let text = decode(&data[..end]);
    let mut sections: Sections = Vec::new();
    for line in lines(&text).map(str::trim).filter(|l| !l.is_empty()) {
        if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
            sections.push((name.to_string(), Vec::new()));
        } else if let (Some((_, entries)), Some((key, value))) =
            (sections.last_mut(), line.split_once('='))
        {
            entries.push((key.to_string(), value.to_string()));
        }
    }
    Ok((sections, end + DATA_MARK.len()))
}

/// One stored image.
struct Image {
    name: String,
    nx: usize,
    ny: usize,
    offset: usize,
    bits: u32,
    signed: bool,
    order: ByteOrder,
    dx_m: f64,
    dy_m: f64,
    /// metres per count and the offset in metres, for a length unit
    scale: Option<(f64, f64)>,
}

/// The images in storage order, offsets from the start of the data.
fn images(sections: &Sections, max_points: usize) -> Result<Vec<Image>, FormatError> {
    let section = |name: &str| crate::lookup(sections, name);
    let get = |entries: &Vec<(String, String)>, key: &str| {
        crate::lookup(entries, key).map(|v| v.trim().to_string())
    };
    let number = |entries: &Vec<(String, String)>, name: &str, key: &str| {
        get(entries, key)
            .and_then(|v| v.parse::<f64>().ok())
            .ok_or_else(|| FORMAT.invalid(format!("[{name}] has no number {key}")))
    };
    let global = section("DataSet").ok_or_else(|| FORMAT.invalid("no [DataSet] section"))?;
    let groups = number(global, "DataSet", "GroupCount")? as usize;
    let mut images = Vec::new();
    let mut offset = 0usize;
    for group in 0..groups.min(sections.len()) {
        let slots = number(global, "DataSet", &format!("Gr{group}-Count"))? as usize;
        for slot in 0..slots.min(1 << 16) {
            let Some(name) = get(global, &format!("Gr{group}-Ch{slot}")) else {
                continue;
            };
            let Some(entries) = section(&name) else {
                continue;
            };
            let image = image(
                entries,
                &name,
                offset,
                &|key| number(entries, &name, key),
                max_points,
            )?;
            let bytes = image.nx * image.ny * (image.bits / 8) as usize;
            offset = offset
                .checked_add(bytes)
                .ok_or_else(|| FORMAT.invalid(format!("[{name}]: the images' offsets overflow")))?;
            images.push(image);
        }
    }
    Ok(images)
}

/// One image's section.
fn image(
    entries: &[(String, String)],
    name: &str,
    offset: usize,
    number: &dyn Fn(&str) -> Result<f64, FormatError>,
    max_points: usize,
) -> Result<Image, FormatError> {
    let text = |key: &str| crate::lookup(entries, key).map_or("", |v| v.trim());
    if text("SaveMode") != "Binary" {
        return Err(FORMAT.unsupported(format!(
            "[{name}]: SaveMode \"{}\" (Binary is read)",
            text("SaveMode")
        )));
    }
    let (nx, ny) = (number("Points")? as usize, number("Lines")? as usize);
    grid_points(FORMAT.name(), nx, ny, &format!("[{name}]"), max_points)?;
    let bits = number("SaveBits")? as u32;
    if ![8, 16, 32].contains(&bits) {
        return Err(FORMAT.unsupported(format!("[{name}]: SaveBits {bits} (8, 16, 32 are read)")));
    }
    let lateral = |axis: &str, n: usize| -> Result<f64, FormatError> {
        let unit = text(&format!("Dim{axis}Unit"));
        let m = metres_per(unit).ok_or_else(|| {
            FORMAT.unsupported(format!(
                "[{name}]: Dim{axis}Unit \"{unit}\" is not a length"
            ))
        })?;
        Ok(number(&format!("Dim{axis}Range"))? * m / n as f64)
    };
    let signed = text("SaveSign") == "Signed";
    let scale = match metres_per(text("Dim2Unit")) {
        Some(m) => {
            let range = number("Dim2Range")?;
            let min = number("Dim2Min")?;
            let offset = if signed { min + range / 2.0 } else { min };
            Some((range / 2f64.powi(bits as i32) * m, offset * m))
        }
        None => None,
    };
    Ok(Image {
        name: format!("{} ({})", text("Frame"), text("Dim2Name")),
        nx,
        ny,
        offset,
        bits,
        signed,
        order: if text("SaveOrder") == "Intel" {
            ByteOrder::Little
        } else {
            ByteOrder::Big
        },
        dx_m: lateral("0", nx)?,
        dy_m: lateral("1", ny)?,
        scale,
    })
}

/// The counts of an image as f64.
fn counts(bytes: &Bytes, image: &Image, at: usize) -> Result<Vec<f64>, FormatError> {
    let n = image.nx * image.ny;
    let what = format!("channel {} at byte {at}", image.name);
    bytes.integers(at, n, (image.bits, image.signed), &what)
}

/// Reads the channel `asked` for.
pub(crate) fn read(
    data: &[u8],
    asked: &Channel,
    max_points: usize,
) -> Result<Topography, FormatError> {
    let (sections, data_start) = header(data)?;
    let images = images(&sections, max_points)?;
    let heights: Vec<&Image> = images.iter().filter(|i| i.scale.is_some()).collect();
    let names: Vec<String> = heights.iter().map(|i| i.name.clone()).collect();
    let index = channel::pick(FORMAT, &names, 0, asked)?;
    let image = heights[index];
    let Some((metres_per_count, offset_m)) = image.scale else {
        return Err(FORMAT.invalid("a height channel without a scale"));
    };
    let bytes = Bytes::new(data, FORMAT.name(), image.order);
    let at = data_start.saturating_add(image.offset);
    let counts = counts(&bytes, image, at)?;
    let (nx, ny) = (image.nx, image.ny);
    let heights_m = Array2::from_shape_fn((nx, ny), |(i, j)| {
        counts[(ny - 1 - j) * nx + i] * metres_per_count + offset_m
    });
    let mut metadata = vec![("vendor".to_string(), "Nanosurf".to_string())];
    let info = crate::lookup(&sections, "DataSet-Info");
    for (key, name) in [
        ("Date", "date"),
        ("Time", "time"),
        ("Head type", "instrument"),
        ("Controller S/N", "serial"),
    ] {
        if let Some(value) = info.and_then(|e| crate::lookup(e, key)) {
            metadata.push((name.into(), value.trim().to_string()));
        }
    }
    // `Points` per line × `Lines`: each stored row is a scan line
    metadata.push((crate::FAST_AXIS.into(), "x".into()));
    FORMAT.check_spacings(
        image.dx_m,
        image.dy_m,
        format_args!("channel {}: the ranges", image.name),
    )?;
    let map = Topography::new(FORMAT, heights_m, image.dx_m, image.dy_m, metadata);
    Ok(channel::with_channels(map, &names, index))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two 2 × 2 images of signed 16-bit counts: a deflection (N) and a height.
    fn file() -> Vec<u8> {
        let mut f = b"[DataSet]\r\nGroupCount=1\r\nGr0-Name=Scan forward\r\nGr0-Count=3\r\n\
                      Gr0-Ch0=DataSet-0:0\r\nGr0-Ch2=DataSet-0:2\r\n\r\n"
            .to_vec();
        for (name, unit, range, min) in [("0:0", "N", "2", "-1"), ("0:2", "m", "65536", "0")] {
            f.extend(
                format!(
                    "[DataSet-{name}]\r\nPoints=2\r\nLines=2\r\nFrame=Scan forward\r\n\
                     Dim0Unit=m\r\nDim0Range=4e-6\r\nDim1Unit=m\r\nDim1Range=2e-6\r\n\
                     Dim2Name=Z\r\nDim2Unit={unit}\r\nDim2Range={range}\r\nDim2Min={min}\r\n\
                     SaveMode=Binary\r\nSaveBits=16\r\nSaveSign=Signed\r\nSaveOrder=Intel\r\n\r\n"
                )
                .as_bytes(),
            );
        }
        f.extend(b"#!");
        for c in [9i16, 9, 9, 9, 1, 2, 3, -4] {
            f.extend(c.to_le_bytes());
        }
        f
    }

    #[test]
    fn only_length_channels_are_listed_and_y_is_flipped() {
        let f = file();
        assert!(matches(&f));
        let map = read(&f, &Channel::Default, crate::DEFAULT_MAX_POINTS).unwrap();
        assert_eq!(
            map.metadata[1],
            ("channels".into(), "0: Scan forward (Z)".into())
        );
        // 65536 m over 2^16 counts, offset 0 + 65536 / 2
        assert_eq!(map.heights_m[[0, 0]], 3.0 + 32768.0);
        assert_eq!(map.heights_m[[1, 0]], -4.0 + 32768.0);
        assert_eq!(map.heights_m[[0, 1]], 1.0 + 32768.0);
        assert_eq!((map.dx_m, map.dy_m), (2e-6, 1e-6));
    }

    #[test]
    fn broken_files_say_where() {
        let f = file();
        let err = read(
            &f[..f.len() - 1],
            &Channel::Default,
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("channel Scan forward (Z) at byte"), "{err}");
        let err = read(
            b"[DataSet]\r\nGroupCount=1\r\n",
            &Channel::Default,
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap_err();
        assert!(err.to_string().contains("#!"), "{err}");
    }
}
