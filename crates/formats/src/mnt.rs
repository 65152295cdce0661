//! Digital Surf MountainsMap documents (`.mnt`): a compound file whose
//! stream `ScopedContents` holds, after an 8-byte size, a tree of TLV
//! entries (`u16` tag, `u64` size, contents; little-endian). The format is
//! not published; what is read here is what SurfaceTopography's `IO/MNT.py`
//! (1.21) found and what `mnt-1.mnt` shows:
//!
//! - the heights lie in the main container (tag 0x0001) under tag 0x02BD,
//!   whose 0x0001 is the data type (12: a count of 0 is a point not
//!   measured; 39: every count is a height) and whose 0x0002 holds zlib
//!   blocks of `i32` counts, each after a 16-byte prefix (`u64` offset of
//!   its first count, `u32` counts, `u32` compressed bytes); the blocks of
//!   one layer tile the map in rows of constant y, in any order;
//! - each axis is described by a record named by a one-letter string
//!   (`X`, `Y`, `Z`: tag 2, a type byte 4 and UTF-16 text) followed by its
//!   step (tag 1, `f64`), the step's unit (tag 2), the offset's unit (tag
//!   3), a ratio (tag 4), the offset (tag 5), a flag (tag 6) and, for X and
//!   Y, the number of points (tag 1, `u32`).
//!
//! A count c is the height c · step_Z + offset_Z, x_i = offset_X + i · step_X.
//! SurfaceTopography 1.21 takes the lateral size from another record (the
//! map's width in mm, 0.1 % smaller here) and leaves out the Z offset; the
//! reference map of `mnt-1.mnt` has the axis records' spacing and offset,
//! as here. The first layer whose blocks tile the X × Y grid is read.

use std::io::Read;

use flate2::read::ZlibDecoder;
use ndarray::Array2;

use crate::bytes::{ByteOrder, Bytes, grid_points};
use crate::cfb::{self, Compound};
use crate::units::metres_per;
use crate::{Format, FormatError, Topography};

const FORMAT: Format = Format::Mnt;

const MAIN: u16 = 0x0001;
const HEIGHT_DATA: u16 = 0x02BD;
/// Data type whose count 0 marks a point not measured.
const ZERO_IS_MISSING: u8 = 12;
const BLOCK_PREFIX: usize = 16;

/// Whether the file is a compound file (an `.mnt` is told from other
/// compound documents only by its `ScopedContents` stream, when read).
pub(crate) fn matches(bytes: &[u8]) -> bool {
    bytes.starts_with(cfb::MAGIC)
}

/// At most `most` TLV entries of `data` from `at` on: (tag, contents
/// offset, size); the walk stops at the first entry that overruns `data`.
fn entries(data: &[u8], mut at: usize, most: usize) -> Vec<(u16, usize, usize)> {
    let bytes = Bytes::new(data, FORMAT.name(), ByteOrder::Little);
    let mut out = Vec::new();
    while out.len() < most
        && let (Ok(tag), Ok(size)) = (
            bytes.read::<u16>(at, "a tag"),
            bytes.read::<u64>(at + 2, "a size"),
        )
    {
        let start = at + 10;
        let Some(size) = usize::try_from(size)
            .ok()
            .filter(|&s| s <= data.len() - start)
        else {
            break;
        };
        out.push((tag, start, size));
        at = start + size;
    }
    out
}

/// The contents of the first entry tagged `tag` in `data[range]`.
fn child(data: &[u8], start: usize, end: usize, tag: u16) -> Option<(usize, usize)> {
    entries(&data[..end], start, usize::MAX)
        .into_iter()
        .find(|(t, _, _)| *t == tag)
        .map(|(_, at, size)| (at, size))
}

/// An axis record: step and its unit, offset and its unit, points.
#[derive(Debug)]
struct Axis {
    step: f64,
    step_unit: String,
    offset: f64,
    offset_unit: String,
    points: Option<u32>,
}

/// The first record of the axis named `letter`.
fn axis(data: &[u8], letter: char) -> Option<Axis> {
    let mut name = b"\x02\x00\x03\x00\x00\x00\x00\x00\x00\x00\x04".to_vec();
    name.extend((letter as u16).to_le_bytes());
    let bytes = Bytes::new(data, FORMAT.name(), ByteOrder::Little);
    let text = |at: usize, size: usize| -> Option<String> {
        let units = bytes
            .values::<u16>(at + 1, size.saturating_sub(1) / 2, "a unit")
            .ok()?;
        Some(String::from_utf16_lossy(&units))
    };
    data.windows(name.len())
        .enumerate()
        .filter(|(_, w)| *w == name.as_slice())
        .find_map(|(at, _)| {
            let fields = entries(data, at + name.len(), 7);
            let [
                (1, step, 8),
                (2, su, sn),
                (3, ou, on),
                (4, _, 8),
                (5, offset, 8),
                ..,
            ] = fields[..]
            else {
                return None;
            };
            let points = match fields.get(6) {
                Some(&(1, at, 4)) => bytes.read::<u32>(at, "points").ok(),
                _ => None,
            };
            Some(Axis {
                step: bytes.read::<f64>(step, "a step").ok()?,
                step_unit: text(su, sn)?,
                offset: bytes.read::<f64>(offset, "an offset").ok()?,
                offset_unit: text(ou, on)?,
                points,
            })
        })
}

/// The zlib blocks of counts in `blocks` that lie within a map of `n`
/// counts: (offset of the first count, counts). At most four maps' worth
/// of counts are inflated, whatever the blocks claim.
fn count_blocks(blocks: &[u8], n: usize) -> Vec<(usize, Vec<u8>)> {
    let bytes = Bytes::new(blocks, FORMAT.name(), ByteOrder::Little);
    let mut found = Vec::new();
    let mut inflated_bytes = 0usize;
    let mut at = 0;
    while at + BLOCK_PREFIX + 2 <= blocks.len() && inflated_bytes <= 16 * n {
        let zlib = &blocks[at + BLOCK_PREFIX..];
        let header = zlib[0] == 0x78 && [0x01, 0x5e, 0x9c, 0xda].contains(&zlib[1]);
        let first = bytes.read::<u64>(at, "a block offset").unwrap_or(u64::MAX);
        let counts = bytes.read::<u32>(at + 8, "a block's counts").unwrap_or(0) as usize;
        let zipped = bytes.read::<u32>(at + 12, "a block's size").unwrap_or(0) as usize;
        let inside = usize::try_from(first).is_ok_and(|f| f < n && counts <= n - f);
        if header && counts > 0 && inside && zipped <= zlib.len() {
            let mut out = Vec::new();
            let inflated = ZlibDecoder::new(&zlib[..zipped])
                .take(counts as u64 * 4 + 1)
                .read_to_end(&mut out);
            if inflated.is_ok() && out.len() == counts * 4 {
                inflated_bytes += out.len();
                found.push((first as usize, out));
                at += BLOCK_PREFIX + zipped;
                continue;
            }
        }
        at += 1;
    }
    found
}

/// The counts of the first layer whose blocks tile `n` counts exactly.
fn layer(blocks: Vec<(usize, Vec<u8>)>, n: usize) -> Option<Vec<i32>> {
    let mut layers: Vec<Vec<(usize, Vec<u8>)>> = vec![Vec::new()];
    for block in blocks {
        let current = layers.last_mut()?;
        if current.iter().any(|(first, _)| *first == block.0) {
            layers.push(vec![block]);
        } else {
            current.push(block);
        }
    }
    layers.into_iter().find_map(|mut layer| {
        layer.sort_by_key(|(first, _)| *first);
        // n was checked against the caller's limit before the blocks were inflated
        let mut counts = Vec::with_capacity(n);
        for (first, data) in &layer {
            if *first != counts.len() {
                return None;
            }
            counts.extend(
                data.chunks_exact(4)
                    .map(|c| i32::from_le_bytes([c[0], c[1], c[2], c[3]])),
            );
        }
        (counts.len() == n).then_some(counts)
    })
}

/// Reads the document's surface as heights in metres, axis 0 = x.
pub(crate) fn read(data: &[u8], max_points: usize) -> Result<Topography, FormatError> {
    let contents = Compound::open(data, FORMAT)?.stream("ScopedContents")?;
    let (main, main_len) = child(&contents, 8, contents.len(), MAIN)
        .ok_or_else(|| FORMAT.invalid("ScopedContents has no main container (tag 0x0001)"))?;
    let (height, height_len) = child(&contents, main, main + main_len, HEIGHT_DATA)
        .ok_or_else(|| FORMAT.invalid("the main container has no height data (tag 0x02BD)"))?;
    let end = height + height_len;
    let data_type = child(&contents, height, end, 0x0001)
        .and_then(|(at, size)| (size == 1).then(|| contents[at]))
        .ok_or_else(|| FORMAT.invalid("the height data have no data type (tag 0x0001)"))?;
    let (blocks, blocks_len) = child(&contents, height, end, 0x0002)
        .ok_or_else(|| FORMAT.invalid("the height data have no blocks (tag 0x0002)"))?;
    let [x, y, z] = ['X', 'Y', 'Z'].map(|letter| axis(&contents, letter));
    let (Some(x), Some(y), Some(z)) = (x, y, z) else {
        return Err(FORMAT.invalid("ScopedContents lacks the X, Y or Z axis record"));
    };
    let (nx, ny) = (
        x.points.unwrap_or(0) as usize,
        y.points.unwrap_or(0) as usize,
    );
    let n = grid_points(
        FORMAT.name(),
        nx,
        ny,
        "the X and Y axis records",
        max_points,
    )?;
    let counts =
        layer(count_blocks(&contents[blocks..blocks + blocks_len], n), n).ok_or_else(|| {
            FORMAT.invalid(format!(
                "no layer of zlib blocks holds the {nx} × {ny} counts"
            ))
        })?;
    let unit =
        |u: &str| metres_per(u).ok_or_else(|| FORMAT.unsupported(format!("an axis unit \"{u}\"")));
    let (dx_m, dy_m) = (x.step * unit(&x.step_unit)?, y.step * unit(&y.step_unit)?);
    let (z_step_m, z_offset_m) = (
        z.step * unit(&z.step_unit)?,
        z.offset * unit(&z.offset_unit)?,
    );
    FORMAT.check_spacings(dx_m, dy_m, "the axis records")?;
    let heights_m = Array2::from_shape_fn((nx, ny), |(i, j)| {
        let count = counts[j * nx + i];
        if data_type == ZERO_IS_MISSING && count == 0 {
            f64::NAN
        } else {
            f64::from(count) * z_step_m + z_offset_m
        }
    });
    let position_m = (
        x.offset * unit(&x.offset_unit)?,
        y.offset * unit(&y.offset_unit)?,
    );
    Ok(Topography {
        heights_m,
        dx_m,
        dy_m,
        format: FORMAT,
        position_m: Some(position_m),
        metadata: vec![
            ("vendor".to_string(), "Digital Surf".to_string()),
            ("data_type".into(), data_type.to_string()),
        ],
    })
}

#[cfg(test)]
mod tests {
    use std::io::Write;

    use flate2::Compression;
    use flate2::write::ZlibEncoder;

    use super::*;

    fn block(first: u64, counts: &[i32]) -> Vec<u8> {
        let raw: Vec<u8> = counts.iter().flat_map(|c| c.to_le_bytes()).collect();
        let mut e = ZlibEncoder::new(Vec::new(), Compression::default());
        e.write_all(&raw).unwrap();
        let zipped = e.finish().unwrap();
        let mut b = first.to_le_bytes().to_vec();
        b.extend((counts.len() as u32).to_le_bytes());
        b.extend((zipped.len() as u32).to_le_bytes());
        b.extend(zipped);
        b
    }

    #[test]
    fn blocks_in_any_order_tile_a_layer() {
        let mut blocks = vec![0xaa, 0x78];
        blocks.extend(block(2, &[3, 4]));
        blocks.extend(block(0, &[1, 2]));
        // a second layer that repeats offset 0
        blocks.extend(block(0, &[9, 9, 9, 9]));
        let counts = layer(count_blocks(&blocks, 4), 4).unwrap();
        assert_eq!(counts, [1, 2, 3, 4]);
        // blocks reaching past a map of 3 are not taken
        assert!(layer(count_blocks(&blocks, 3), 3).is_none());
    }

    #[test]
    fn axis_records_are_found_by_their_letter() {
        let tlv = |tag: u16, data: &[u8]| {
            let mut v = tag.to_le_bytes().to_vec();
            v.extend((data.len() as u64).to_le_bytes());
            v.extend(data);
            v
        };
        let mut data = vec![0u8; 5];
        data.extend(tlv(2, &[4, b'X', 0]));
        data.extend(tlv(1, &2.5f64.to_le_bytes()));
        data.extend(tlv(2, &[4, 0xb5, 0, b'm', 0]));
        data.extend(tlv(3, &[4, b'm', 0, b'm', 0]));
        data.extend(tlv(4, &1000f64.to_le_bytes()));
        data.extend(tlv(5, &7f64.to_le_bytes()));
        data.extend(tlv(6, &1u32.to_le_bytes()));
        data.extend(tlv(1, &960u32.to_le_bytes()));
        let x = axis(&data, 'X').unwrap();
        assert_eq!((x.step, x.step_unit.as_str(), x.offset), (2.5, "µm", 7.0));
        assert_eq!((x.offset_unit.as_str(), x.points), ("mm", Some(960)));
        assert!(axis(&data, 'Y').is_none());
    }
}
