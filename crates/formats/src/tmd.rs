//! TrueMap / GelSight `.tmd` files: the magic `Binary TrueMap Data File
//! v2.0`, a 24-byte comment, the grid size (`u32` × 2), the lengths and
//! offsets of the map along x and y (`f32`, mm), then the heights as `f32`
//! in rows of constant y, little-endian (SurfaceTopography's `IO/TMD.py`).
//!
//! Lengths and heights are read in millimetres, as the reference map of
//! `tmd-1.tmd` was (300 points over 18.96 mm, a 63.2 µm spacing, heights
//! up to 0.35 mm); SurfaceTopography 1.21's `TMD.py` labels the same
//! numbers µm, which would make the file's 300-point map 19 µm wide.

use crate::bytes::{ByteOrder, Bytes, grid_points, x_major};
use crate::{Format, FormatError, Topography};

const FORMAT: Format = Format::Tmd;

const MAGIC: &[u8] = b"Binary TrueMap Data File v2.0";
/// The magic occupies 32 bytes (padded with CR LF NUL), the comment 24.
const MAGIC_LEN: usize = 32;
const COMMENT_LEN: usize = 24;
const HEADER_LEN: usize = MAGIC_LEN + COMMENT_LEN + 4 * 6;
/// Metres per the file's unit, the millimetre.
const MM: f64 = 1e-3;

/// Whether the file starts with the TrueMap magic.
pub(crate) fn matches(bytes: &[u8]) -> bool {
    bytes.starts_with(MAGIC)
}

/// Reads the map, heights in metres with axis 0 = x.
pub(crate) fn read(data: &[u8], max_points: usize) -> Result<Topography, FormatError> {
    let bytes = Bytes::new(data, FORMAT.name(), ByteOrder::Little);
    let comment = bytes.text(MAGIC_LEN, COMMENT_LEN, "the comment")?;
    let mut c = bytes.cursor(MAGIC_LEN + COMMENT_LEN);
    let nx = c.read::<u32>("the points along x")? as usize;
    let ny = c.read::<u32>("the points along y")? as usize;
    let length_x = c.read::<f32>("the length along x (mm)")?;
    let length_y = c.read::<f32>("the length along y (mm)")?;
    let offset_x = c.read::<f32>("the x offset (mm)")?;
    let offset_y = c.read::<f32>("the y offset (mm)")?;
    let points = grid_points(FORMAT.name(), nx, ny, "bytes 56–63", max_points)?;
    for (length, at) in [(length_x, 64), (length_y, 68)] {
        if !(length.is_finite() && length > 0.0) {
            return Err(FORMAT.invalid(format!(
                "byte {at}: the map's length {length} mm is not a positive number"
            )));
        }
    }
    let heights = bytes.values::<f32>(HEADER_LEN, points, "the heights")?;
    // f32 mm widened to f64 before scaling, as SurfaceTopography does
    let heights_m = x_major(nx, ny, &heights, |h| f64::from(h) * MM);
    let mut metadata = vec![("vendor".to_string(), "TrueMap".to_string())];
    if !comment.is_empty() {
        metadata.push(("comment".into(), comment));
    }
    let dx_m = f64::from(length_x) * MM / nx as f64;
    let dy_m = f64::from(length_y) * MM / ny as f64;
    let position_m = (offset_x.is_finite() && offset_y.is_finite())
        .then(|| (f64::from(offset_x) * MM, f64::from(offset_y) * MM));
    Ok(Topography {
        heights_m,
        dx_m,
        dy_m,
        format: FORMAT,
        position_m,
        metadata,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(nx: u32, ny: u32, heights: &[f32]) -> Vec<u8> {
        let mut f = MAGIC.to_vec();
        f.extend(b"\r\n\0");
        f.resize(MAGIC_LEN, 0);
        f.extend(b"Created by test");
        f.resize(MAGIC_LEN + COMMENT_LEN, 0);
        for v in [nx, ny] {
            f.extend(v.to_le_bytes());
        }
        for v in [3.0f32, 1.0, 0.5, 0.0] {
            f.extend(v.to_le_bytes());
        }
        for h in heights {
            f.extend(h.to_le_bytes());
        }
        f
    }

    #[test]
    fn rows_of_constant_y_in_millimetres() {
        let map = read(
            &file(3, 2, &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]),
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap();
        assert_eq!(map.heights_m.dim(), (3, 2));
        assert_eq!(map.heights_m[[2, 0]], 3e-3);
        assert_eq!(map.heights_m[[0, 1]], 4e-3);
        assert_eq!((map.dx_m, map.dy_m), (1e-3, 0.5e-3));
        assert_eq!(map.position_m, Some((0.5e-3, 0.0)));
        assert!(
            map.metadata
                .contains(&("comment".into(), "Created by test".into()))
        );
    }

    #[test]
    fn broken_headers_are_named() {
        let err = read(&file(3, 2, &[1.0; 5]), crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(err.contains("the heights needs bytes 80..104"), "{err}");
        let err = read(&file(0, 2, &[]), crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(err.contains("empty 0 × 2 grid"), "{err}");
        let mut f = file(1, 1, &[1.0]);
        f[64..68].copy_from_slice(&(-1.0f32).to_le_bytes());
        assert!(
            read(&f, crate::DEFAULT_MAX_POINTS)
                .unwrap_err()
                .to_string()
                .contains("byte 64")
        );
    }
}
