//! Alicona Imaging `.al3d` files (InfiniteFocus focus-variation
//! microscopes): the magic `AliconaImaging\0\r\n`, then tags of 52 bytes
//! (a 20-byte key, a 30-byte value, both NUL-terminated text, and CR LF):
//! `Version`, `TagCount`, then `TagCount` more. `Cols` × `Rows` heights
//! follow at `DepthImageOffset` as little-endian `f32` metres, in rows of
//! constant y padded to a multiple of 8 bytes; `PixelSizeXMeter` and
//! `PixelSizeYMeter` are the spacings. A point equal to `InvalidPixelValue`
//! (to 1.5e-7 relative) or NaN was not measured. Layout as read by
//! Gwyddion's `alicona.c` and SurfaceTopography's `IO/AL3D.py`.

use crate::bytes::{ByteOrder, Bytes, grid_points};
use crate::{Format, FormatError, Topography};

const FORMAT: Format = Format::Al3d;

const MAGIC: &[u8] = b"AliconaImaging\0\r\n";
const KEY_LEN: usize = 20;
const VALUE_LEN: usize = 30;
const TAG_LEN: usize = KEY_LEN + VALUE_LEN + 2;
/// Relative distance to `InvalidPixelValue` under which a point is invalid
/// (SurfaceTopography's `_INVALID_RELTOL`: the value is written as text).
const INVALID_RELATIVE: f64 = 1.5e-7;

/// Whether the file starts with the Alicona magic.
pub(crate) fn matches(bytes: &[u8]) -> bool {
    bytes.starts_with(MAGIC)
}

/// The header's tags, in file order, with the byte offset of each.
fn tags(bytes: &Bytes) -> Result<Vec<(String, String, usize)>, FormatError> {
    let mut tags = Vec::new();
    let mut at = MAGIC.len();
    let mut count = 2;
    while tags.len() < count {
        let key = bytes.text(at, KEY_LEN, "a tag's key")?;
        let value = bytes.text(at + KEY_LEN, VALUE_LEN, "a tag's value")?;
        if bytes.slice(at + KEY_LEN + VALUE_LEN, 2, "a tag's CR LF")? != b"\r\n" {
            return Err(FORMAT.invalid(format!(
                "byte {}: tag \"{key}\" does not end in CR LF",
                at + KEY_LEN + VALUE_LEN
            )));
        }
        let expected = ["Version", "TagCount"].get(tags.len());
        if let Some(expected) = expected.filter(|e| **e != key) {
            return Err(FORMAT.invalid(format!(
                "byte {at}: expected the tag {expected}, found \"{key}\""
            )));
        }
        if key == "TagCount" {
            let extra = value.parse::<usize>().map_err(|_| {
                FORMAT.invalid(format!("byte {at}: TagCount \"{value}\" is not a count"))
            })?;
            // every tag takes 52 bytes: a count the file cannot hold is refused here
            if extra > bytes.len() / TAG_LEN {
                return Err(FORMAT.invalid(format!(
                    "byte {at}: {extra} tags do not fit in a file of {} bytes",
                    bytes.len()
                )));
            }
            count = 2 + extra;
        }
        tags.push((key, value, at));
        at += TAG_LEN;
    }
    Ok(tags)
}

/// Reads the depth image as heights in metres, axis 0 = x.
pub(crate) fn read(data: &[u8], max_points: usize) -> Result<Topography, FormatError> {
    let bytes = Bytes::new(data, FORMAT.name(), ByteOrder::Little);
    let tags = tags(&bytes)?;
    let tag = |key: &str| -> Result<(&str, usize), FormatError> {
        tags.iter()
            .find(|(k, _, _)| k == key)
            .map(|(_, v, at)| (v.as_str(), *at))
            .ok_or_else(|| FORMAT.invalid(format!("the header has no tag {key}")))
    };
    let count = |key: &str| -> Result<usize, FormatError> {
        let (value, at) = tag(key)?;
        value
            .parse::<usize>()
            .map_err(|_| FORMAT.invalid(format!("byte {at}: {key} \"{value}\" is not a count")))
    };
    let real = |key: &str| -> Result<f64, FormatError> {
        let (value, at) = tag(key)?;
        value
            .parse::<f64>()
            .map_err(|_| FORMAT.invalid(format!("byte {at}: {key} \"{value}\" is not a number")))
    };
    let (nx, ny) = (count("Cols")?, count("Rows")?);
    grid_points(FORMAT.name(), nx, ny, "the tags Cols and Rows", max_points)?;
    let offset = count("DepthImageOffset")?;
    let invalid = real("InvalidPixelValue")?;
    let (dx_m, dy_m) = (real("PixelSizeXMeter")?, real("PixelSizeYMeter")?);
    FORMAT.check_spacings(dx_m, dy_m, "PixelSizeXMeter and PixelSizeYMeter")?;
    // rows padded to a multiple of 8 bytes
    let stride = (nx * 4).div_ceil(8) * 8;
    let what = format!("the depth image at byte {offset}");
    let last_row = offset.checked_add((ny - 1) * stride);
    let Some(last_row) = last_row else {
        return Err(FORMAT.invalid(format!("{what}: {ny} rows overflow")));
    };
    bytes.slice(last_row, nx * 4, &what)?;
    let mut heights_m = ndarray::Array2::from_elem((nx, ny), f64::NAN);
    for j in 0..ny {
        let row = bytes.values::<f32>(offset + j * stride, nx, &what)?;
        for (i, h) in row.into_iter().enumerate() {
            let h = f64::from(h);
            let is_invalid = !invalid.is_nan() && (h - invalid).abs() < INVALID_RELATIVE * invalid;
            if !h.is_nan() && !is_invalid {
                heights_m[[i, j]] = h;
            }
        }
    }
    let mut metadata = vec![("vendor".to_string(), "Alicona Imaging".to_string())];
    for (key, value, _) in &tags {
        if ["CreatingApplication", "Version"].contains(&key.as_str()) && !value.is_empty() {
            metadata.push((key.to_ascii_lowercase(), value.clone()));
        }
    }
    Ok(Topography::new(FORMAT, heights_m, dx_m, dy_m, metadata))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tag(key: &str, value: &str) -> Vec<u8> {
        let mut t = vec![0u8; TAG_LEN];
        t[..key.len()].copy_from_slice(key.as_bytes());
        t[KEY_LEN..KEY_LEN + value.len()].copy_from_slice(value.as_bytes());
        t[KEY_LEN + VALUE_LEN..].copy_from_slice(b"\r\n");
        t
    }

    /// A 3 × 2 map (rows of 12 bytes padded to 16) with one invalid point.
    fn file() -> Vec<u8> {
        let mut f = MAGIC.to_vec();
        let offset = MAGIC.len() + 9 * TAG_LEN;
        for (k, v) in [
            ("Version", "1".to_string()),
            ("TagCount", "7".to_string()),
            ("Cols", "3".to_string()),
            ("Rows", "2".to_string()),
            ("DepthImageOffset", offset.to_string()),
            ("InvalidPixelValue", "3.0000000280e+15".to_string()),
            ("PixelSizeXMeter", "2e-6".to_string()),
            ("PixelSizeYMeter", "3e-6".to_string()),
            ("CreatingApplication", "test".to_string()),
        ] {
            f.extend(tag(k, &v));
        }
        for row in [[1.0f32, 2.0, 3.0e15], [4.0, f32::NAN, 6.0]] {
            for h in row {
                f.extend(h.to_le_bytes());
            }
            f.extend([0xaa; 4]);
        }
        f
    }

    #[test]
    fn padded_rows_and_invalid_points() {
        let map = read(&file(), crate::DEFAULT_MAX_POINTS).unwrap();
        assert_eq!(map.heights_m.dim(), (3, 2));
        assert_eq!(map.heights_m[[1, 0]], 2.0);
        assert_eq!(map.heights_m[[0, 1]], 4.0);
        assert!(map.heights_m[[2, 0]].is_nan());
        assert!(map.heights_m[[1, 1]].is_nan());
        assert_eq!((map.dx_m, map.dy_m), (2e-6, 3e-6));
        assert!(
            map.metadata
                .contains(&("creatingapplication".into(), "test".into()))
        );
    }

    #[test]
    fn broken_tags_are_named() {
        let mut f = file();
        f[MAGIC.len() + TAG_LEN + KEY_LEN] = b'x';
        let err = read(&f, crate::DEFAULT_MAX_POINTS).unwrap_err().to_string();
        assert!(err.contains("TagCount \"x\" is not a count"), "{err}");
        let mut f = file();
        f[MAGIC.len() + 2 * TAG_LEN - 1] = b'?';
        assert!(
            read(&f, crate::DEFAULT_MAX_POINTS)
                .unwrap_err()
                .to_string()
                .contains("CR LF")
        );
        let f = file();
        let err = read(&f[..f.len() - 5], crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(err.contains("the depth image"), "{err}");
    }
}
