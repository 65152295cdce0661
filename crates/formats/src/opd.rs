//! Wyko / Veeco / Bruker Vision `.opd` files (white-light interferometers).
//!
//! Two bytes, then a directory of 24-byte entries (16-byte name, `i16`
//! type, `i32` length, `u16` attribute; little-endian) whose first entry is
//! the directory itself, named `Directory`. The blocks' contents follow the
//! directory in its order, each exactly its declared length long. Arrays
//! (type 3) start with width, height and bytes per value (`u16` each) and
//! store the values with the x index first and y running downwards; scalar
//! blocks hold the calibration: `Wavelength` (nm), `Mult` (counts per
//! wavelength unit, default 1), `Aspect` (pixel height / width, default 1)
//! and `Pixel_size` (mm). Heights are value · λ / Mult; values ≥ 1e38
//! (f32) or ≥ 32766 (i16) mark bad points. Layout as read by Gwyddion's
//! `opdfile.c` and SurfaceTopography's `IO/OPD.py`.

use crate::bytes::{ByteOrder, Bytes, grid_points};
use crate::{Format, FormatError, Topography};

const FORMAT: Format = Format::Opd;

const PRELUDE: usize = 2;
const ENTRY_LEN: usize = 24;
const NAME_LEN: usize = 16;
const DIRECTORY: &[u8] = b"Directory";

const TYPE_ARRAY: i16 = 3;
const TYPE_TEXT: i16 = 5;
const TYPE_SHORT: i16 = 6;
const TYPE_FLOAT: i16 = 7;
const TYPE_DOUBLE: i16 = 8;
const TYPE_LONG: i16 = 12;

/// Names of the arrays that hold heights ("Image", "Intensity" and
/// "SecArr_0" hold intensities; SurfaceTopography's OPD.py).
const HEIGHT_ARRAYS: [&str; 5] = ["RAW DATA", "RAW_DATA", "OPD", "Raw", "SAMPLE_DATA"];

/// Bad-point thresholds of f32 and i16 arrays (Gwyddion's opdfile.c).
const BAD_F32: f32 = 1.0e38;
const BAD_I16: i16 = 32766;

/// Whether the directory's own entry, after the two-byte prelude, is named `Directory`.
pub(crate) fn matches(bytes: &[u8]) -> bool {
    bytes.get(PRELUDE..PRELUDE + NAME_LEN).is_some_and(|name| {
        name.starts_with(DIRECTORY) && name[DIRECTORY.len()..].iter().all(|&b| b == 0 || b == b' ')
    })
}

/// One directory entry and where its block's contents lie.
struct Block {
    name: String,
    kind: i16,
    at: usize,
    len: usize,
}

/// The directory's blocks with their content offsets, checked to lie in the file.
fn directory(bytes: &Bytes) -> Result<Vec<Block>, FormatError> {
    if !matches(bytes.slice(0, PRELUDE + NAME_LEN, "the directory's name")?) {
        return Err(FORMAT.invalid(format!(
            "the first directory entry at byte {PRELUDE} is not named \"Directory\""
        )));
    }
    let dir_len = bytes.read::<i32>(PRELUDE + NAME_LEN + 2, "the directory's length")?;
    let dir_len = usize::try_from(dir_len)
        .ok()
        .filter(|&n| n >= ENTRY_LEN && n % ENTRY_LEN == 0)
        .ok_or_else(|| {
            FORMAT.invalid(format!(
                "the directory's length {dir_len} at byte {} is not a positive multiple of {ENTRY_LEN}",
                PRELUDE + NAME_LEN + 2
            ))
        })?;
    bytes.slice(PRELUDE, dir_len, "the directory")?;
    let mut at = PRELUDE + dir_len;
    let mut blocks = Vec::new();
    for entry in (PRELUDE + ENTRY_LEN..PRELUDE + dir_len).step_by(ENTRY_LEN) {
        let name = bytes.text(entry, NAME_LEN, "a block name")?;
        let kind = bytes.read::<i16>(entry + NAME_LEN, "a block type")?;
        let len = bytes.read::<i32>(entry + NAME_LEN + 2, "a block length")?;
        // blocks of length ≤ 0 have no contents; a height array without
        // them is named here, not later as a missing array
        let len = match usize::try_from(len) {
            Ok(len) if len > 0 => len,
            _ if kind == TYPE_ARRAY && HEIGHT_ARRAYS.contains(&name.as_str()) => {
                return Err(FORMAT.invalid(format!(
                    "the height array block \"{name}\" (directory entry at byte {entry}) has the \
                     length {len}: it holds no heights"
                )));
            }
            _ => continue,
        };
        if at.checked_add(len).is_none_or(|end| end > bytes.len()) {
            return Err(FORMAT.invalid(format!(
                "block \"{name}\" (directory entry at byte {entry}) needs bytes {at}..{} but the \
                 file has {} bytes",
                at.saturating_add(len),
                bytes.len()
            )));
        }
        blocks.push(Block {
            name,
            kind,
            at,
            len,
        });
        at += len;
    }
    Ok(blocks)
}

/// A scalar block's value as f64 (the stored width decides the type, as
/// some files declare types that do not match; Gwyddion's opdfile.c).
fn number(bytes: &Bytes, block: &Block) -> Result<Option<f64>, FormatError> {
    let what = format!("block \"{}\"", block.name);
    let value = match (block.kind, block.len) {
        (TYPE_SHORT | TYPE_FLOAT, 2) => f64::from(bytes.read::<i16>(block.at, &what)?),
        (TYPE_SHORT, 4) | (TYPE_LONG, 4..) => f64::from(bytes.read::<i32>(block.at, &what)?),
        (TYPE_FLOAT, 4..) => f64::from(bytes.read::<f32>(block.at, &what)?),
        (TYPE_DOUBLE, 8..) => bytes.read::<f64>(block.at, &what)?,
        _ => return Ok(None),
    };
    Ok(Some(value))
}

/// The stored values of a height array, in metres per stored unit and the
/// bad-point rule applied: NaN for bad points.
enum Values {
    U8(Vec<u8>),
    I16(Vec<i16>),
    F32(Vec<f32>),
}

impl Values {
    fn get(&self, k: usize) -> f64 {
        match self {
            Values::U8(v) => f64::from(v[k]),
            Values::I16(v) if v[k] >= BAD_I16 => f64::NAN,
            Values::I16(v) => f64::from(v[k]),
            Values::F32(v) if !(v[k].is_finite() && v[k] < BAD_F32) => f64::NAN,
            Values::F32(v) => f64::from(v[k]),
        }
    }
}

/// The first height array: its block, grid size and stored values.
fn height_array<'b>(
    bytes: &Bytes,
    blocks: &'b [Block],
    max_points: usize,
) -> Result<(&'b Block, usize, usize, Values), FormatError> {
    let Some(array) = blocks
        .iter()
        .find(|b| b.kind == TYPE_ARRAY && HEIGHT_ARRAYS.contains(&b.name.as_str()))
    else {
        return Err(FORMAT.invalid(format!(
            "no height array: expected an array block named one of {HEIGHT_ARRAYS:?}"
        )));
    };
    let what = format!("array \"{}\" at byte {}", array.name, array.at);
    let nx = usize::from(bytes.read::<u16>(array.at, &what)?);
    let ny = usize::from(bytes.read::<u16>(array.at + 2, &what)?);
    let item = bytes.read::<u16>(array.at + 4, &what)?;
    let points = grid_points(FORMAT.name(), nx, ny, &what, max_points)?;
    let item_len = match item {
        1 | 2 | 4 => usize::from(item),
        _ => {
            return Err(FORMAT.unsupported(format!(
                "{what}: {item} bytes per value, expected 1, 2 or 4"
            )));
        }
    };
    if 6 + points * item_len > array.len {
        return Err(FORMAT.invalid(format!(
            "{what}: {nx} × {ny} values of {item_len} bytes do not fit its {} bytes",
            array.len
        )));
    }
    let at = array.at + 6;
    let values = match item {
        1 => Values::U8(bytes.slice(at, points, &what)?.to_vec()),
        2 => Values::I16(bytes.values::<i16>(at, points, &what)?),
        _ => Values::F32(bytes.values::<f32>(at, points, &what)?),
    };
    Ok((array, nx, ny, values))
}

/// What the file says beyond the heights: the array read, the wavelength
/// and Mult, the date and the magnification.
fn metadata(
    bytes: &Bytes,
    blocks: &[Block],
    array: &str,
    wavelength_nm: f64,
    mult: f64,
    scalar: &dyn Fn(&str) -> Result<Option<f64>, FormatError>,
) -> Result<Vec<(String, String)>, FormatError> {
    let mut metadata = vec![
        ("vendor".to_string(), "Wyko".to_string()),
        ("array".into(), array.to_string()),
        ("wavelength_nm".into(), wavelength_nm.to_string()),
    ];
    if mult != 1.0 {
        metadata.push(("mult".into(), mult.to_string()));
    }
    let text = |name: &str| -> Result<Option<String>, FormatError> {
        match blocks
            .iter()
            .find(|b| b.name == name && b.kind == TYPE_TEXT)
        {
            Some(block) => bytes
                .text(block.at, block.len, &format!("block \"{name}\""))
                .map(Some),
            None => Ok(None),
        }
    };
    // "Date" is month/day/year (SurfaceTopography's OPD.py)
    match (text("Date")?, text("Time")?) {
        (Some(date), Some(time)) => metadata.push(("date".into(), format!("{date} {time}"))),
        (Some(date), None) => metadata.push(("date".into(), date)),
        _ => {}
    }
    if let Some(magnification) = scalar("Magnification")? {
        metadata.push(("magnification".into(), magnification.to_string()));
    }
    Ok(metadata)
}

/// Reads the first height array as heights in metres, axis 0 = x, NaN at bad points.
pub(crate) fn read(data: &[u8], max_points: usize) -> Result<Topography, FormatError> {
    let bytes = Bytes::new(data, FORMAT.name(), ByteOrder::Little);
    let blocks = directory(&bytes)?;
    let scalar = |name: &str| -> Result<Option<f64>, FormatError> {
        match blocks.iter().find(|b| b.name == name) {
            Some(block) => number(&bytes, block),
            None => Ok(None),
        }
    };
    let wavelength_nm = scalar("Wavelength")?
        .ok_or_else(|| FORMAT.invalid("no \"Wavelength\" block: the height scale is unknown"))?;
    let mult = scalar("Mult")?.unwrap_or(1.0);
    let aspect = scalar("Aspect")?.unwrap_or(1.0);
    let pixel_mm = scalar("Pixel_size")?.ok_or_else(|| {
        FORMAT.unsupported("no \"Pixel_size\" block: the file has no lateral calibration")
    })?;
    // nm / Mult · 1e-6 is mm, · 1e-3 is m: SurfaceTopography's order, so
    // the metres agree with its reader to the last bit
    let mm_per_value = wavelength_nm / mult * 1e-6;
    if !(mm_per_value.is_finite() && mm_per_value != 0.0) {
        return Err(FORMAT.invalid(format!(
            "wavelength {wavelength_nm} nm / Mult {mult} gives no height scale"
        )));
    }
    let dx_m = pixel_mm * 1e-3;
    let dy_m = dx_m * aspect;
    if !(dx_m.is_finite() && dx_m > 0.0 && dy_m.is_finite() && dy_m > 0.0) {
        return Err(FORMAT.invalid(format!(
            "pixel size {pixel_mm} mm with aspect {aspect} is not a positive spacing"
        )));
    }

    let (array, nx, ny, values) = height_array(&bytes, &blocks, max_points)?;
    // stored x-major with y downwards: flip y (as Gwyddion and SurfaceTopography do)
    let heights_m = ndarray::Array2::from_shape_fn((nx, ny), |(i, j)| {
        values.get(i * ny + (ny - 1 - j)) * mm_per_value * 1e-3
    });

    let metadata = metadata(&bytes, &blocks, &array.name, wavelength_nm, mult, &scalar)?;
    Ok(Topography {
        heights_m,
        dx_m,
        dy_m,
        format: Format::Opd,
        // the file records the scanner's z position only, no stage x/y
        position_m: None,
        metadata,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry(name: &str, kind: i16, len: i32) -> Vec<u8> {
        let mut e = vec![0u8; NAME_LEN];
        e[..name.len()].copy_from_slice(name.as_bytes());
        e.extend_from_slice(&kind.to_le_bytes());
        e.extend_from_slice(&len.to_le_bytes());
        e.extend_from_slice(&8u16.to_le_bytes());
        e
    }

    /// A file with the calibration blocks and one 2-byte or 4-byte "Raw"
    /// array of `nx` × `ny` values stored x-major, y downwards.
    fn opd_file(nx: u16, ny: u16, stored: &[u8], item: u16, mult: Option<i16>) -> Vec<u8> {
        let array_len = 6 + stored.len() as i32;
        let mut blocks: Vec<(Vec<u8>, Vec<u8>)> = vec![
            (
                entry("Wavelength", TYPE_FLOAT, 4),
                600.0f32.to_le_bytes().to_vec(),
            ),
            (
                entry("Aspect", TYPE_FLOAT, 4),
                2.0f32.to_le_bytes().to_vec(),
            ),
            (
                entry("Pixel_size", TYPE_FLOAT, 4),
                0.001f32.to_le_bytes().to_vec(),
            ),
            (entry("Date", TYPE_TEXT, 8), b"7/7/2015".to_vec()),
            (entry("Empty", TYPE_TEXT, 0), Vec::new()),
        ];
        if let Some(m) = mult {
            blocks.push((entry("Mult", TYPE_SHORT, 2), m.to_le_bytes().to_vec()));
        }
        let mut raw = Vec::new();
        for v in [nx, ny, item] {
            raw.extend_from_slice(&v.to_le_bytes());
        }
        raw.extend_from_slice(stored);
        blocks.push((entry("Raw", TYPE_ARRAY, array_len), raw));
        let dir_len = (ENTRY_LEN * (blocks.len() + 2)) as i32;
        let mut file = vec![1, 0];
        file.extend(entry("Directory", 1, dir_len));
        for (e, _) in &blocks {
            file.extend_from_slice(e);
        }
        file.extend(vec![0u8; ENTRY_LEN]); // an unused entry
        for (_, contents) in &blocks {
            file.extend_from_slice(contents);
        }
        file
    }

    #[test]
    fn values_times_wavelength_over_mult_flipped_in_y() {
        // 2 × 3, stored x-major with y downwards: stored (i, s) = 10 i + s
        let stored: Vec<u8> = [0i16, 1, 2, 10, 11, BAD_I16]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let file = opd_file(2, 3, &stored, 2, Some(4));
        assert!(matches(&file));
        let t = read(&file, crate::DEFAULT_MAX_POINTS).unwrap();
        assert_eq!(t.heights_m.dim(), (2, 3));
        // 600 nm / 4 per count = 150 nm; y = 0 is the last stored value
        let nm = 1e-9;
        assert!((t.heights_m[[0, 0]] - 2.0 * 150.0 * nm).abs() < 1e-22);
        assert!((t.heights_m[[0, 2]] - 0.0).abs() < 1e-22);
        assert!(t.heights_m[[1, 0]].is_nan());
        assert!((t.heights_m[[1, 2]] - 10.0 * 150.0 * nm).abs() < 1e-21);
        // 0.001 mm stored as f32
        let pixel_m = f64::from(0.001f32) * 1e-3;
        assert!((t.dx_m - pixel_m).abs() < 1e-20);
        assert!((t.dy_m - 2.0 * pixel_m).abs() < 1e-20);
        assert!(t.metadata.contains(&("date".into(), "7/7/2015".into())));
    }

    #[test]
    fn float_arrays_mark_huge_values_bad_and_mult_defaults_to_one() {
        let stored: Vec<u8> = [1.0f32, 1.7e38, f32::NAN, -0.5]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let t = read(&opd_file(2, 2, &stored, 4, None), crate::DEFAULT_MAX_POINTS).unwrap();
        assert!((t.heights_m[[0, 1]] - 600e-9).abs() < 1e-20);
        assert!(t.heights_m[[0, 0]].is_nan());
        assert!(t.heights_m[[1, 1]].is_nan());
        assert!((t.heights_m[[1, 0]] + 300e-9).abs() < 1e-20);
    }

    #[test]
    fn broken_directories_say_which_block() {
        let stored = [0u8; 8];
        let good = opd_file(2, 2, &stored, 2, None);
        let short = &good[..good.len() - 1];
        let err = read(short, crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(err.contains("block \"Raw\""), "{err}");
        let mut item = good.clone();
        let raw_at = good.len() - 8 - 6;
        item[raw_at + 4] = 3;
        assert!(matches!(
            read(&item, crate::DEFAULT_MAX_POINTS),
            Err(FormatError::Unsupported { .. })
        ));
        let mut huge = good.clone();
        huge[raw_at] = 0xff; // 255 × 2 values in 8 bytes
        assert!(
            read(&huge, crate::DEFAULT_MAX_POINTS)
                .unwrap_err()
                .to_string()
                .contains("do not fit")
        );
        assert!(!matches(b"\x01\x00Directorx"));
    }
}
