//! Digital Surf `.sur`, the native surface file of MountainsMap (written
//! directly by several instruments): a 512-byte little-endian header, a
//! comment and a private zone, then the heights as int16 or int32 counts,
//! plain (magic `DIGITAL SURF`) or zlib-compressed (magic `DSCOMPRESSED`).
//!
//! Byte offsets and field meanings as read by Gwyddion (`modules/file/
//! surffile.c`), SurfaceTopography (`IO/SUR.py`) and RosettaSciIO
//! (`rsciio/digitalsurf`, the compressed layout): height = count × Z spacing
//! (+ Z offset, Gwyddion; SurfaceTopography 1.27 leaves the offset out, 0 in
//! the reference file), in the header's Z step unit; the count `zmin − 2`
//! marks a point not measured when the special-points flag is 1; the array
//! is stored row by row (x fastest), so the result is its transpose, flipped
//! as the inversion flag says.
//!
//! `position_m` holds the header's X and Y offsets: the origin MountainsMap
//! gives the axes (the stage position where the instrument records one).

use std::io::Read;

use flate2::read::ZlibDecoder;
use ndarray::{Array2, Axis};

use crate::bytes::{ByteOrder, Bytes, Cursor, grid_points, latin1, x_major};
use crate::{Format, FormatError, Topography};

const FORMAT: Format = Format::Sur;

/// Magic of the plain layout.
const MAGIC_PLAIN: &[u8; 12] = b"DIGITAL SURF";
/// Magic of the zlib-compressed layout.
const MAGIC_COMPRESSED: &[u8; 12] = b"DSCOMPRESSED";

/// The fixed header before the comment, private zone and points.
const HEADER_BYTES: usize = 512;

/// Most zlib streams a compressed file may split its points into.
const MAX_STREAMS: usize = 4096;

/// Whether the first bytes are this format's magic.
pub(crate) fn matches(bytes: &[u8]) -> bool {
    bytes.starts_with(MAGIC_PLAIN) || bytes.starts_with(MAGIC_COMPRESSED)
}

/// Reads the file's bytes.
pub(crate) fn read(data: &[u8], max_points: usize) -> Result<Topography, FormatError> {
    let bytes = Bytes::new(data, FORMAT.name(), ByteOrder::Little);
    let header = Header::parse(bytes, max_points)?;
    let (nx, ny) = (header.nx, header.ny);
    let n = nx * ny;
    let point_bytes = header.point_bits / 8;
    let start = header.points_start;
    let inflated;
    let (counts, counts_at) = if header.compressed {
        inflated = inflate(&mut bytes.cursor(start), n * point_bytes)?;
        (Bytes::new(&inflated, FORMAT.name(), ByteOrder::Little), 0)
    } else {
        if data.len().saturating_sub(start) < n * point_bytes {
            return Err(FORMAT.invalid(format!(
                "byte {start}: {nx} × {ny} points of {} bits take {} bytes, but the file ends at byte {}",
                header.point_bits,
                n * point_bytes,
                data.len()
            )));
        }
        (bytes, start)
    };
    let counts: Vec<i64> = if point_bytes == 2 {
        let counts = counts.values::<i16>(counts_at, n, "the height counts")?;
        counts.into_iter().map(i64::from).collect()
    } else {
        let counts = counts.values::<i32>(counts_at, n, "the height counts")?;
        counts.into_iter().map(i64::from).collect()
    };
    let scale = header.z_unit_m;
    // the count below the lowest one by 2 marks a point not measured
    let missing = (header.special_points == 1).then_some(i64::from(header.zmin) - 2);
    let to_height = |count: i64| {
        if Some(count) == missing {
            f64::NAN
        } else {
            (count as f64 * header.dz + header.z_offset) * scale
        }
    };
    // rows of nx points, one per y: axis 0 of the result is x
    let mut heights_m = x_major(nx, ny, &counts, to_height);
    header.inversion.apply(&mut heights_m);
    Ok(Topography {
        heights_m,
        dx_m: header.dx_m,
        dy_m: header.dy_m,
        format: Format::Sur,
        position_m: Some(header.position_m),
        metadata: header.metadata,
    })
}

/// The compressed points: a u32 stream count, then (raw, zipped) u32 byte
/// lengths per stream, then the zlib streams one after another (RosettaSciIO's
/// `_unpack_data`). Inflates no more than `expected_bytes` in all, whatever
/// the directory claims.
fn inflate(cursor: &mut Cursor, expected_bytes: usize) -> Result<Vec<u8>, FormatError> {
    let directory_at = cursor.offset();
    let streams = cursor.read::<u32>("the number of compressed streams")? as usize;
    if streams == 0 || streams > MAX_STREAMS {
        return Err(FORMAT.invalid(format!(
            "byte {directory_at}: expected 1 to {MAX_STREAMS} compressed streams, found {streams}"
        )));
    }
    let mut lengths = Vec::with_capacity(streams);
    let mut total_raw: usize = 0;
    for _ in 0..streams {
        let raw = cursor.read::<u32>("a stream's uncompressed length")? as usize;
        let zipped = cursor.read::<u32>("a stream's compressed length")? as usize;
        total_raw = total_raw.saturating_add(raw);
        lengths.push((raw, zipped));
    }
    if total_raw != expected_bytes {
        return Err(FORMAT.invalid(format!(
            "byte {directory_at}: the compressed streams hold {total_raw} bytes, \
             but the header's points take {expected_bytes}"
        )));
    }
    let mut counts = Vec::new();
    for (i, (raw, zipped)) in lengths.into_iter().enumerate() {
        let stream_at = cursor.offset();
        let stream = cursor.take(zipped, "a compressed stream")?;
        let before = counts.len();
        ZlibDecoder::new(stream)
            .take(raw as u64 + 1)
            .read_to_end(&mut counts)
            .map_err(|e| {
                FORMAT.invalid(format!(
                    "byte {stream_at}: compressed stream {i} cannot be inflated: {e}"
                ))
            })?;
        let produced = counts.len() - before;
        if produced != raw {
            return Err(FORMAT.invalid(format!(
                "byte {stream_at}: compressed stream {i} inflates to {} bytes, the directory says {raw}",
                if produced > raw {
                    format!("more than {raw}")
                } else {
                    produced.to_string()
                }
            )));
        }
    }
    Ok(counts)
}

/// What the 512-byte header says.
struct Header {
    compressed: bool,
    special_points: u16,
    point_bits: usize,
    zmin: i32,
    nx: usize,
    ny: usize,
    dx_m: f64,
    dy_m: f64,
    /// height per count, in the Z step unit
    dz: f64,
    /// added to every height, in the Z step unit
    z_offset: f64,
    /// metres per Z step unit
    z_unit_m: f64,
    inversion: Inversion,
    position_m: (f64, f64),
    /// where the points start: after the header, comment and private zone
    points_start: usize,
    metadata: Vec<(String, String)>,
}

/// The fixed header's fields as stored, before units and checks.
struct Fields {
    compressed: bool,
    objects: u16,
    object_name: String,
    operator_name: String,
    acquisition: u16,
    special_points: u16,
    point_bits: usize,
    zmin: i32,
    nx: usize,
    ny: usize,
    dx: f64,
    dy: f64,
    dz: f64,
    axis_names: [String; 3],
    step_units: [String; 3],
    inversion: Inversion,
    leveling: u16,
    /// s, min, h, day, month, year, weekday
    clock: [u16; 7],
    duration_s: f32,
    comment_size: usize,
    private_size: usize,
    x_offset: f64,
    y_offset: f64,
    z_offset: f64,
}

impl Fields {
    /// Reads the 512 bytes field by field (offsets in Gwyddion's surffile.c).
    fn read(bytes: Bytes, max_points: usize) -> Result<Self, FormatError> {
        let mut c = bytes.cursor(0);
        let magic = c.take(12, "the magic")?;
        let compressed = magic == MAGIC_COMPRESSED;
        if !compressed && magic != MAGIC_PLAIN {
            return Err(
                FORMAT.invalid("byte 0: expected DIGITAL SURF or DSCOMPRESSED (not a .sur file)")
            );
        }
        let _byte_order = c.read::<u16>("the format")?;
        let objects = c.read::<u16>("the number of objects")?;
        let _version = c.read::<u16>("the version")?;
        let object_type = c.read::<u16>("the object type")?;
        check_object_type(object_type)?;
        let object_name = latin1(c.take(30, "the object name")?);
        let operator_name = latin1(c.take(30, "the operator name")?);
        let _material_code = c.read::<u16>("the material code")?;
        let acquisition = c.read::<u16>("the acquisition type")?;
        let _range = c.read::<u16>("the range type")?;
        let special_points = c.read::<u16>("the special-points flag")?;
        let _absolute = c.read::<u16>("the absolute flag")?;
        c.skip(8); // gauge resolution, W size: spectra only
        let point_bits = usize::from(c.read::<u16>("the point size")?);
        if point_bits != 16 && point_bits != 32 {
            return Err(FORMAT.unsupported(format!(
                "byte 98: points of {point_bits} bits (16 or 32 are read)"
            )));
        }
        let zmin = c.read::<i32>("zmin")?;
        let _zmax = c.read::<i32>("zmax")?;
        let nx = grid_size(
            c.read::<i32>("the points per line")?,
            108,
            "points per line",
        )?;
        let ny = grid_size(c.read::<i32>("the number of lines")?, 112, "lines")?;
        let n = grid_points(FORMAT.name(), nx, ny, "bytes 108–115", max_points)?;
        let total = c.read::<u32>("the total number of points")? as usize;
        if total != n {
            return Err(FORMAT.invalid(format!(
                "byte 116: {total} points in all, but {nx} × {ny} = {n}"
            )));
        }
        let dx = f64::from(c.read::<f32>("the x spacing")?);
        let dy = f64::from(c.read::<f32>("the y spacing")?);
        let dz = f64::from(c.read::<f32>("the z spacing")?);
        let axis_names = [
            latin1(c.take(16, "the x axis name")?),
            latin1(c.take(16, "the y axis name")?),
            latin1(c.take(16, "the z axis name")?),
        ];
        let step_units = [
            latin1(c.take(16, "the x step unit")?),
            latin1(c.take(16, "the y step unit")?),
            latin1(c.take(16, "the z step unit")?),
        ];
        c.skip(3 * 16 + 3 * 4); // length units and unit ratios: display only
        let _imprint = c.read::<u16>("the imprint flag")?;
        let inversion = Inversion::parse(c.read::<u16>("the inversion flag")?)?;
        let leveling = c.read::<u16>("the levelling flag")?;
        c.skip(12);
        let mut clock = [0u16; 7];
        for field in &mut clock {
            *field = c.read::<u16>("the date")?;
        }
        let duration_s = c.read::<f32>("the measurement duration")?;
        c.skip(4 + 6); // compressed size (not needed: the directory has it), reserved
        let comment_size = usize::from(c.read::<u16>("the comment size")?);
        let private_size = usize::from(c.read::<u16>("the private zone size")?);
        c.skip(128); // client zone
        Ok(Fields {
            compressed,
            objects,
            object_name,
            operator_name,
            acquisition,
            special_points,
            point_bits,
            zmin,
            nx,
            ny,
            dx,
            dy,
            dz,
            axis_names,
            step_units,
            inversion,
            leveling,
            clock,
            duration_s,
            comment_size,
            private_size,
            x_offset: f64::from(c.read::<f32>("the x offset")?),
            y_offset: f64::from(c.read::<f32>("the y offset")?),
            z_offset: f64::from(c.read::<f32>("the z offset")?),
        })
    }

    /// What the header says beyond the grid and scales, as key–value text.
    fn metadata(&self, comment: String) -> Vec<(String, String)> {
        let mut metadata = Vec::new();
        let mut put = |key: &str, value: String| {
            if !value.is_empty() {
                metadata.push((key.to_string(), value));
            }
        };
        put("object_name", self.object_name.clone());
        put("operator_name", self.operator_name.clone());
        put(
            "acquisition",
            acquisition_name(self.acquisition).to_string(),
        );
        put("date", date(self.clock));
        if self.duration_s.is_finite() && self.duration_s > 0.0 {
            put("measurement_duration_s", self.duration_s.to_string());
        }
        put(
            "levelling",
            match self.leveling {
                1 => "least squares plane".into(),
                2 => "minimum zone".into(),
                _ => String::new(),
            },
        );
        put("comment", comment);
        put("axis_names", self.axis_names.join(", "));
        put("step_units", self.step_units.join(", "));
        put("point_bits", self.point_bits.to_string());
        put(
            "layout",
            if self.compressed {
                "zlib-compressed"
            } else {
                "plain"
            }
            .into(),
        );
        if self.objects > 1 {
            put(
                "objects_in_file",
                format!("{} (the first is read)", self.objects),
            );
        }
        metadata
    }
}

impl Header {
    fn parse(bytes: Bytes, max_points: usize) -> Result<Self, FormatError> {
        if bytes.len() < HEADER_BYTES {
            return Err(FORMAT.invalid(format!(
                "the file ends at byte {}, inside the {HEADER_BYTES}-byte header",
                bytes.len()
            )));
        }
        let f = Fields::read(bytes, max_points)?;
        let x_unit_m = unit_m(&f.step_units[0], 180, "x step unit")?;
        let y_unit_m = unit_m(&f.step_units[1], 196, "y step unit")?;
        let z_unit_m = unit_m(&f.step_units[2], 212, "z step unit")?;
        let (dx_m, dy_m) = (f.dx.abs() * x_unit_m, f.dy.abs() * y_unit_m);
        if !(dx_m.is_finite() && dx_m > 0.0 && dy_m.is_finite() && dy_m > 0.0) {
            return Err(FORMAT.invalid(format!(
                "bytes 120–127: expected positive grid spacings, found {} and {}",
                f.dx, f.dy
            )));
        }
        if !(f.dz.is_finite() && f.z_offset.is_finite()) {
            return Err(FORMAT.invalid(format!(
                "bytes 128 and 474: the z spacing {} and offset {} must be finite",
                f.dz, f.z_offset
            )));
        }

        let mut c = bytes.cursor(HEADER_BYTES);
        let comment = latin1(c.take(f.comment_size, "the comment")?);
        c.skip(f.private_size);
        let points_start = c.offset();

        Ok(Header {
            compressed: f.compressed,
            special_points: f.special_points,
            point_bits: f.point_bits,
            zmin: f.zmin,
            nx: f.nx,
            ny: f.ny,
            dx_m,
            dy_m,
            dz: f.dz,
            z_offset: f.z_offset,
            z_unit_m,
            inversion: f.inversion,
            position_m: (f.x_offset * x_unit_m, f.y_offset * y_unit_m),
            points_start,
            metadata: f.metadata(comment),
        })
    }
}

/// Surfaces (type 2) are read; the other MountainsMap objects are named.
fn check_object_type(object_type: u16) -> Result<(), FormatError> {
    let what = match object_type {
        2 => return Ok(()),
        1 => "a profile",
        3 => "a binary image",
        4 => "a series of profiles",
        5 => "a series of surfaces",
        6 => "a meridian disc",
        7 => "a multilayer profile",
        8 => "a multilayer surface",
        9 => "a parallel disc",
        10 => "an intensity image",
        11 => "an intensity surface",
        12 => "an RGB image",
        13 => "an RGB surface",
        14 => "a force curve",
        15 => "a series of force curves",
        16 => "an RGB intensity surface",
        20 => "a spectrum",
        21 => "a hyperspectral map",
        _ => "an object of unknown type",
    };
    Err(FORMAT.unsupported(format!(
        "byte 18: object type {object_type} is {what}, not a surface (type 2)"
    )))
}

/// A grid dimension: positive.
fn grid_size(value: i32, offset: usize, what: &str) -> Result<usize, FormatError> {
    usize::try_from(value)
        .ok()
        .filter(|&v| v > 0)
        .ok_or_else(|| {
            FORMAT.invalid(format!(
                "byte {offset}: {value} {what}, expected at least 1"
            ))
        })
}

/// Metres per unit of a header's unit text.
fn unit_m(unit: &str, offset: usize, what: &str) -> Result<f64, FormatError> {
    // old files write µ in an MS-DOS code page (0xE6, "æ" in Latin-1), as
    // SurfaceTopography's `_fix_unit` notes
    let factor = match unit {
        "m" => 1.0,
        "cm" => 1e-2,
        "mm" => 1e-3,
        "µm" | "um" | "æm" | "\u{3bc}m" => 1e-6,
        "nm" => 1e-9,
        "Å" => 1e-10,
        "pm" => 1e-12,
        _ => {
            return Err(FORMAT.unsupported(format!(
                "byte {offset}: {what} {unit:?} is not a length unit read here (m, cm, mm, µm, nm, Å, pm)"
            )));
        }
    };
    Ok(factor)
}

/// Names of the acquisition types (Gwyddion's list), empty for "unknown".
fn acquisition_name(code: u16) -> &'static str {
    match code {
        1 => "contact stylus",
        2 => "scanning optical gauge",
        3 => "thermocouple",
        5 => "contact stylus with skid",
        6 => "AFM",
        7 => "STM",
        8 => "video",
        9 => "interferometer",
        10 => "structured light projection",
        _ => "",
    }
}

/// ISO 8601 date from (s, min, h, day, month, year, weekday), empty when the
/// file leaves it at zero or gives an impossible one.
fn date(clock: [u16; 7]) -> String {
    let [second, minute, hour, day, month, year, _] = clock;
    let plausible = year > 0
        && (1..=12).contains(&month)
        && (1..=31).contains(&day)
        && hour < 24
        && minute < 60
        && second < 61;
    if plausible {
        format!("{year:04}-{month:02}-{day:02}T{hour:02}:{minute:02}:{second:02}")
    } else {
        String::new()
    }
}

/// The inversion flag (Gwyddion's `SurfInversionType`, SurfaceTopography's
/// `_to_grid`): heights negated, and for 2 and 3 the map mirrored in x or y.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Inversion {
    None,
    Z,
    ZFlipX,
    ZFlipY,
}

impl Inversion {
    fn parse(flag: u16) -> Result<Self, FormatError> {
        match flag {
            0 => Ok(Inversion::None),
            1 => Ok(Inversion::Z),
            2 => Ok(Inversion::ZFlipX),
            3 => Ok(Inversion::ZFlipY),
            other => {
                Err(FORMAT.invalid(format!("byte 290: inversion flag {other}, expected 0 to 3")))
            }
        }
    }

    /// Applies the flag to a map with axis 0 = x.
    fn apply(self, heights_m: &mut Array2<f64>) {
        if self == Inversion::None {
            return;
        }
        heights_m.mapv_inplace(|h| -h);
        let mirrored = match self {
            Inversion::ZFlipX => Some(Axis(0)),
            Inversion::ZFlipY => Some(Axis(1)),
            _ => None,
        };
        if let Some(axis) = mirrored {
            heights_m.invert_axis(axis);
            *heights_m = heights_m.as_standard_layout().into_owned();
        }
    }
}

#[cfg(test)]
#[path = "../tests/common/sur_streams.rs"]
mod sur_streams;

#[cfg(test)]
mod tests {
    use super::sur_streams::compressed_sur;
    use super::*;

    /// A plain header for an nx × ny map of 16-bit counts, spacing 2.5 µm,
    /// Z spacing 0.5 nm, zmin given.
    fn header(nx: i32, ny: i32, zmin: i32) -> Vec<u8> {
        let mut h = vec![0u8; HEADER_BYTES];
        h[0..12].copy_from_slice(MAGIC_PLAIN);
        h[14..16].copy_from_slice(&1u16.to_le_bytes());
        h[18..20].copy_from_slice(&2u16.to_le_bytes());
        h[98..100].copy_from_slice(&16u16.to_le_bytes());
        h[100..104].copy_from_slice(&zmin.to_le_bytes());
        h[108..112].copy_from_slice(&nx.to_le_bytes());
        h[112..116].copy_from_slice(&ny.to_le_bytes());
        h[116..120].copy_from_slice(&nx.wrapping_mul(ny).to_le_bytes());
        h[120..124].copy_from_slice(&2.5f32.to_le_bytes());
        h[124..128].copy_from_slice(&2.5f32.to_le_bytes());
        h[128..132].copy_from_slice(&0.5f32.to_le_bytes());
        h[180..182].copy_from_slice(b"um");
        // µ as the single Latin-1 byte 0xb5
        h[196] = 0xb5;
        h[197] = b'm';
        h[212..214].copy_from_slice(b"nm");
        h
    }

    fn counts16(values: &[i16]) -> Vec<u8> {
        values.iter().flat_map(|v| v.to_le_bytes()).collect()
    }

    #[test]
    fn units_convert_to_metres() {
        for (unit, factor) in [
            ("m", 1.0),
            ("cm", 1e-2),
            ("mm", 1e-3),
            ("µm", 1e-6),
            ("um", 1e-6),
            ("æm", 1e-6),
            ("nm", 1e-9),
            ("Å", 1e-10),
            ("pm", 1e-12),
        ] {
            assert_eq!(unit_m(unit, 0, "unit").unwrap(), factor, "{unit}");
        }
        let message = unit_m("inch", 212, "z step unit").unwrap_err().to_string();
        assert!(
            message.contains("byte 212") && message.contains("inch"),
            "{message}"
        );
    }

    #[test]
    fn counts_are_scaled_to_metres_and_transposed() {
        // 3 points per line, 2 lines: the file's rows are constant y
        let mut file = header(3, 2, -5);
        file.extend(counts16(&[1, 2, 3, -4, -5, 6]));
        let map = read(&file, crate::DEFAULT_MAX_POINTS).unwrap();
        assert_eq!(map.heights_m.dim(), (3, 2));
        let expected_nm = ndarray::array![[0.5, -2.0], [1.0, -2.5], [1.5, 3.0]];
        for (h, e) in map.heights_m.iter().zip(&expected_nm) {
            assert!((h - e * 1e-9).abs() <= 1e-24, "{h} vs {e} nm");
        }
        assert!((map.dx_m - 2.5e-6).abs() < 1e-21);
        assert!((map.dy_m - 2.5e-6).abs() < 1e-21);
    }

    #[test]
    fn the_count_two_below_zmin_is_missing_when_flagged() {
        let values = [-7, -5, 0, -7];
        let mut file = header(2, 2, -5);
        file.extend(counts16(&values));
        // without the special-points flag -7 is a height like any other
        let map = read(&file, crate::DEFAULT_MAX_POINTS).unwrap();
        assert_eq!(map.heights_m.iter().filter(|h| h.is_nan()).count(), 0);
        file[86] = 1;
        let map = read(&file, crate::DEFAULT_MAX_POINTS).unwrap();
        assert!(map.heights_m[[0, 0]].is_nan());
        assert!(map.heights_m[[1, 1]].is_nan());
        assert_eq!(map.heights_m[[1, 0]], -2.5e-9);
        assert_eq!(map.heights_m[[0, 1]], 0.0);
    }

    #[test]
    fn the_z_offset_is_added_in_the_z_unit() {
        let mut file = header(2, 1, 0);
        file[474..478].copy_from_slice(&100f32.to_le_bytes());
        file.extend(counts16(&[0, 4]));
        let map = read(&file, crate::DEFAULT_MAX_POINTS).unwrap();
        assert!((map.heights_m[[0, 0]] - 100e-9).abs() < 1e-22);
        assert!((map.heights_m[[1, 0]] - 102e-9).abs() < 1e-22);
    }

    #[test]
    fn inversion_negates_and_mirrors() {
        // 2 × 2: file rows (y = 0) 1 2, (y = 1) 3 4 → map[x][y]
        let read_with = |flag: u16| {
            let mut file = header(2, 2, 0);
            file[290..292].copy_from_slice(&flag.to_le_bytes());
            file.extend(counts16(&[2, 4, 6, 8]));
            read(&file, crate::DEFAULT_MAX_POINTS)
                .unwrap()
                .heights_m
                .mapv(|h| (h / 1e-9).round())
        };
        let plain = ndarray::array![[1.0, 3.0], [2.0, 4.0]];
        assert_eq!(read_with(0), plain);
        assert_eq!(read_with(1), -plain.clone());
        assert_eq!(read_with(2), ndarray::array![[-2.0, -4.0], [-1.0, -3.0]]);
        assert_eq!(read_with(3), ndarray::array![[-3.0, -1.0], [-4.0, -2.0]]);
        let mut file = header(2, 2, 0);
        file[290] = 9;
        file.extend(counts16(&[2, 4, 6, 8]));
        assert!(
            read(&file, crate::DEFAULT_MAX_POINTS)
                .unwrap_err()
                .to_string()
                .contains("byte 290")
        );
    }

    #[test]
    fn the_comment_and_private_zone_come_before_the_points() {
        let mut file = header(2, 1, 0);
        file[334..336].copy_from_slice(&5u16.to_le_bytes());
        file[336..338].copy_from_slice(&3u16.to_le_bytes());
        file.extend(b"hello");
        file.extend([0xaa; 3]);
        file.extend(counts16(&[2, 4]));
        let map = read(&file, crate::DEFAULT_MAX_POINTS).unwrap();
        assert_eq!(map.heights_m[[1, 0]], 2e-9);
        assert!(map.metadata.contains(&("comment".into(), "hello".into())));
    }

    #[test]
    fn compressed_points_equal_the_plain_ones() {
        let values: Vec<i16> = (0..12).map(|v| v * 3 - 7).collect();
        let mut plain = header(4, 3, 0);
        plain.extend(counts16(&values));
        let expected = read(&plain, crate::DEFAULT_MAX_POINTS).unwrap().heights_m;
        for chunk in [24, 10, 3] {
            let file = compressed_sur(&header(4, 3, 0), &counts16(&values), chunk);
            let map = read(&file, crate::DEFAULT_MAX_POINTS).unwrap();
            assert_eq!(map.heights_m, expected, "streams of {chunk} bytes");
            assert!(
                map.metadata
                    .contains(&("layout".into(), "zlib-compressed".into()))
            );
        }
    }

    /// The bomb: a DSCOMPRESSED header claiming 16384² points of
    /// 16 bits (512 MiB) beside 1 MiB of deflated zeros. Refused from the
    /// header by default; with the limit raised, the directory, which
    /// promises less than the header, is refused before any inflation.
    #[test]
    fn a_compressed_bomb_is_refused_before_inflating() {
        let file = compressed_sur(&header(16384, 16384, 0), &vec![0u8; 1 << 20], 1 << 20);
        assert!(file.len() < 1 << 16, "{} bytes", file.len());
        let message = read(&file, crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains(
                "bytes 108–115: the header claims 16384 × 16384 = 268 435 456 points, \
                 above the limit of 67 108 864 (max_points); raise `max_points`"
            ),
            "{message}"
        );
        let message = read(&file, 1 << 28).unwrap_err().to_string();
        assert!(
            message.contains("hold 1048576 bytes, but the header's points take 536870912"),
            "{message}"
        );
    }

    #[test]
    fn a_compressed_directory_that_disagrees_is_refused() {
        let values: Vec<i16> = (0..12).collect();
        let mut file = compressed_sur(&header(4, 3, 0), &counts16(&values), 24);
        // the directory's raw length (byte 516) claims one more byte
        file[516] += 1;
        let message = read(&file, crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("byte 512") && message.contains("take 24"),
            "{message}"
        );
        let mut file = compressed_sur(&header(4, 3, 0), &counts16(&values), 24);
        file[512..516].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(
            read(&file, crate::DEFAULT_MAX_POINTS)
                .unwrap_err()
                .to_string()
                .contains("compressed streams")
        );
    }

    #[test]
    fn absurd_sizes_are_refused_before_allocating() {
        let file = header(1_000_000_000, 1_000_000_000, 0);
        let message = read(&file, crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains(
                "bytes 108–115: the header claims 1000000000 × 1000000000 = 1 000 000 000 000 000 000 points"
            ),
            "{message}"
        );
        let file = header(-3, 2, 0);
        assert!(
            read(&file, crate::DEFAULT_MAX_POINTS)
                .unwrap_err()
                .to_string()
                .contains("byte 108")
        );
        // a plausible size the file is too short for
        let mut file = header(5_000, 5_000, 0);
        file.extend([0u8; 100]);
        let message = read(&file, crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("byte 512") && message.contains("50000000 bytes"),
            "{message}"
        );
    }

    #[test]
    fn other_objects_are_named_in_the_error() {
        let mut file = header(2, 1, 0);
        file[18] = 1;
        file.extend(counts16(&[0, 0]));
        let message = read(&file, crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(message.contains("a profile"), "{message}");
    }

    #[test]
    fn the_date_is_written_only_when_the_file_gives_one() {
        assert_eq!(date([5, 4, 3, 2, 1, 2020, 0]), "2020-01-02T03:04:05");
        assert_eq!(date([0; 7]), "");
        assert_eq!(date([0, 0, 0, 31, 13, 2020, 0]), "");
    }
}
