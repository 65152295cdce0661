//! FRT MicroProf `.frt` files: the magic `FRTM_GLIDERV`, a 4-character
//! version (`1.00`: block sizes `u32`; `1.01`: `u64`), a `u16` block count,
//! then blocks of (`u16` id, size, contents), little-endian. Block 0x66
//! holds the grid (`u32` x points, y points, bits per value), 0x67 the
//! physical sizes along x and y (`f64`, m), 0x6c the metres per count
//! (`f64` after a `u32`), 0x0b the counts (`u16` for 16 bits, `i32` for 32)
//! in rows of constant y, and 0x72 the measurement's start (Unix time).
//! The count 1 marks a point not measured. Layout as read by Gwyddion's
//! `microprof.c` and SurfaceTopography's `IO/FRT.py`.
//!
//! The first row stored is the map's last (y flipped): so the reference map
//! of `frt-1.frt` has it (its all-zero last stored row is its row y = 0),
//! while SurfaceTopography 1.21's `FRT.py` keeps the stored order.

use ndarray::Array2;

use crate::bytes::{ByteOrder, Bytes, grid_points, utc_text};
use crate::{Format, FormatError, Topography};

const FORMAT: Format = Format::Frt;

const MAGIC: &[u8] = b"FRTM_GLIDERV";
const BLOCKS_AT: usize = MAGIC.len() + 4 + 2;

const GRID: u16 = 0x66;
const SIZE: u16 = 0x67;
const SCALE: u16 = 0x6c;
const HEIGHTS: u16 = 0x0b;
const TIMES: u16 = 0x72;
const SERIAL: u16 = 0x8e;
/// The count of a point not measured.
const UNDEFINED: i64 = 1;

/// Whether the file starts with the MicroProf magic.
pub(crate) fn matches(bytes: &[u8]) -> bool {
    bytes.starts_with(MAGIC)
}

/// The blocks: (id, offset of the contents, size).
fn blocks(bytes: &Bytes) -> Result<Vec<(u16, usize, usize)>, FormatError> {
    let version = bytes.text(MAGIC.len(), 4, "the version")?;
    let wide = match version.as_str() {
        "1.00" => false,
        "1.01" => true,
        _ => {
            return Err(FORMAT.unsupported(format!(
                "byte 12: version \"{version}\" (1.00 and 1.01 are read)"
            )));
        }
    };
    let count = bytes.read::<u16>(MAGIC.len() + 4, "the block count")?;
    let mut c = bytes.cursor(BLOCKS_AT);
    let mut blocks = Vec::new();
    // the count is not trusted further than the file: the last block ends it
    for _ in 0..count {
        if c.offset() >= bytes.len() {
            break;
        }
        let at = c.offset();
        let id = c.read::<u16>("a block id")?;
        let size = if wide {
            c.read::<u64>("a block size")?
        } else {
            u64::from(c.read::<u32>("a block size")?)
        };
        let size = usize::try_from(size)
            .ok()
            .filter(|&s| s <= bytes.len() - c.offset())
            .ok_or_else(|| {
                FORMAT.invalid(format!(
                    "block {id:#06x} at byte {at}: {size} bytes do not fit the file"
                ))
            })?;
        blocks.push((id, c.offset(), size));
        c.skip(size);
    }
    Ok(blocks)
}

/// Reads the heights (block 0x0b) in metres, axis 0 = x.
pub(crate) fn read(data: &[u8], max_points: usize) -> Result<Topography, FormatError> {
    let bytes = Bytes::new(data, FORMAT.name(), ByteOrder::Little);
    let blocks = blocks(&bytes)?;
    let block = |id: u16, needed: usize| -> Result<usize, FormatError> {
        let found = blocks.iter().find(|(b, _, _)| *b == id);
        match found {
            Some(&(_, at, size)) if size >= needed => Ok(at),
            Some(&(_, at, size)) => Err(FORMAT.invalid(format!(
                "block {id:#06x} at byte {at}: {size} bytes, expected at least {needed}"
            ))),
            None => Err(FORMAT.invalid(format!("no block {id:#06x}"))),
        }
    };
    let grid = block(GRID, 12)?;
    let nx = bytes.read::<u32>(grid, "the x points")? as usize;
    let ny = bytes.read::<u32>(grid + 4, "the y points")? as usize;
    let bits = bytes.read::<u32>(grid + 8, "the bits per value")?;
    let points = grid_points(
        FORMAT.name(),
        nx,
        ny,
        &format!("block 0x0066 at byte {grid}"),
        max_points,
    )?;
    let size = block(SIZE, 16)?;
    let size_x_m = bytes.read::<f64>(size, "the x size")?;
    let size_y_m = bytes.read::<f64>(size + 8, "the y size")?;
    let scale = block(SCALE, 12)?;
    let metres_per_count = bytes.read::<f64>(scale + 4, "the height scale")?;
    let (dx_m, dy_m) = (size_x_m / nx as f64, size_y_m / ny as f64);
    FORMAT.check_spacings(
        dx_m,
        dy_m,
        format_args!("block 0x0067 at byte {size} (sizes {size_x_m} m × {size_y_m} m)"),
    )?;
    let heights = block(HEIGHTS, 0)?;
    let what = format!("block 0x000b at byte {heights}");
    let counts: Vec<i64> = match bits {
        16 => bytes
            .values::<u16>(heights, points, &what)?
            .into_iter()
            .map(i64::from)
            .collect(),
        32 => bytes
            .values::<i32>(heights, points, &what)?
            .into_iter()
            .map(i64::from)
            .collect(),
        _ => {
            return Err(FORMAT.unsupported(format!(
                "block 0x0066 at byte {grid}: {bits} bits per value (16 or 32 are read)"
            )));
        }
    };
    let heights_m = Array2::from_shape_fn((nx, ny), |(i, j)| {
        let count = counts[(ny - 1 - j) * nx + i];
        if count == UNDEFINED {
            f64::NAN
        } else {
            count as f64 * metres_per_count
        }
    });
    let mut metadata = vec![("vendor".to_string(), "FRT".to_string())];
    if let Ok(serial) = block(SERIAL, 4) {
        let len = bytes.read::<u32>(serial, "the serial's length")? as usize;
        if let Ok(text) = bytes.text(serial + 4, len, "the serial number") {
            metadata.push(("serial".into(), text));
        }
    }
    if let Ok(times) = block(TIMES, 4) {
        let start = bytes.read::<u32>(times, "the start time")?;
        if let Some(date) = utc_text(i64::from(start)) {
            metadata.push(("date".into(), date));
        }
    }
    Ok(Topography::new(FORMAT, heights_m, dx_m, dy_m, metadata))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn block(id: u16, contents: &[u8]) -> Vec<u8> {
        let mut b = id.to_le_bytes().to_vec();
        b.extend((contents.len() as u32).to_le_bytes());
        b.extend(contents);
        b
    }

    fn file() -> Vec<u8> {
        let mut f = b"FRTM_GLIDERV1.00".to_vec();
        f.extend(4u16.to_le_bytes());
        let grid: Vec<u8> = [3u32, 2, 16].iter().flat_map(|v| v.to_le_bytes()).collect();
        f.extend(block(GRID, &grid));
        let size: Vec<u8> = [6e-6f64, 2e-6]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        f.extend(block(SIZE, &size));
        let mut scale = 5u32.to_le_bytes().to_vec();
        scale.extend(1e-9f64.to_le_bytes());
        f.extend(block(SCALE, &scale));
        let counts: Vec<u8> = [0u16, 1, 2, 3, 4, 5]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        f.extend(block(HEIGHTS, &counts));
        f
    }

    #[test]
    fn counts_in_rows_of_constant_y_flipped_and_one_is_missing() {
        let map = read(&file(), crate::DEFAULT_MAX_POINTS).unwrap();
        assert_eq!(map.heights_m.dim(), (3, 2));
        assert_eq!(map.heights_m[[0, 1]], 0.0);
        assert!(map.heights_m[[1, 1]].is_nan());
        assert_eq!(map.heights_m[[2, 0]], 5.0 * 1e-9);
        assert_eq!((map.dx_m, map.dy_m), (2e-6, 1e-6));
    }

    #[test]
    fn broken_blocks_are_named() {
        let f = file();
        let err = read(&f[..f.len() - 1], crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(err.contains("block 0x000b"), "{err}");
        let mut f = file();
        f[12..16].copy_from_slice(b"2.00");
        assert!(
            read(&f, crate::DEFAULT_MAX_POINTS)
                .unwrap_err()
                .to_string()
                .contains("version \"2.00\"")
        );
    }
}
