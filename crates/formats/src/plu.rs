//! Sensofar `.plu` (and `.apx`) files of the PLu / S neox confocal and
//! interferometric profilers.
//!
//! A fixed 500-byte little-endian header (date, comment, axis calibration,
//! measurement configuration), then one block per layer: its grid size
//! (rows, columns), rows of `f32` heights in µm, the layer's min/max and
//! `num_images` 24-bit RGB images of the same size. The layout is the one
//! Gwyddion's `sensofar.c` and SurfaceTopography's `IO/PLU.py` read; the
//! value 1000001 marks a point not measured (both readers).
//!
//! The format has no magic number: [`plausible`] checks that the header is
//! consistent (the calibration's grid equals the first layer's, a positive
//! pixel size, a known measurement type, the layer inside the file) so that
//! `detect` can trust the `.plu` extension only when the bytes agree.

use crate::bytes::{ByteOrder, Bytes, MAX_POINTS, grid_points, utc_text, x_major};
use crate::{Format, FormatError, Topography};

const FORMAT: Format = Format::Plu;

// Byte offsets of the header (Gwyddion's sensofar.c, SurfaceTopography's PLU.py).
const DATE: usize = 0;
const DATE_LEN: usize = 128;
const TIME: usize = 128;
const COMMENT: usize = 132;
const COMMENT_LEN: usize = 256;
const CAL_ROWS: usize = 388;
const CAL_COLUMNS: usize = 392;
const CAL_UM_PER_PIXEL_X: usize = 404;
const CAL_UM_PER_PIXEL_Y: usize = 408;
const CAL_OFFSET_X_UM: usize = 412;
const CAL_OFFSET_Y_UM: usize = 416;
const CAL_OFFSET_Z_UM: usize = 424;
const MEASUREMENT_TYPE: usize = 428;
const ALGORITHM: usize = 432;
const OBJECTIVE: usize = 440;
const NUM_LAYERS: usize = 489;
const VERSION: usize = 490;
const HARDWARE: usize = 491;
const NUM_IMAGES: usize = 492;
/// the first layer: rows, columns, then the heights
const LAYER: usize = 500;
const LAYER_DATA: usize = LAYER + 8;

/// Measurement types 0…6 (image, profile, multi-profile, topography,
/// coordinates, thickness, custom; Gwyddion's sensofar.c).
const TYPE_TOPOGRAPHY: u32 = 3;
const TYPE_LAST: u32 = 6;
/// The value of a point not measured.
const NOT_MEASURED: f32 = 1_000_001.0;
/// Format version 2012 (byte 0xFB): from it on the hardware byte names the
/// instrument; version 2000 (0) and later ones count down from 0xFF
/// (SurfaceTopography's PLU.py).
const VERSION_2012: u8 = 0xFB;

/// Instrument names by hardware configuration byte (SurfaceTopography's PLU.py).
const HARDWARE_NAMES: [&str; 12] = [
    "PLu",
    "PLu 2300 XGA",
    "PLu 2300 XGA T5",
    "PLu 2300 SXGA",
    "PLu 3300",
    "DCM 3D",
    "PLu neox",
    "DCM 3D rev. 2",
    "PLu Apex (prototype)",
    "S neox",
    "DCM8",
    "PLu Apex",
];

/// The header facts the reader and [`plausible`] share.
struct Header {
    rows: usize,
    columns: usize,
    um_per_pixel_x: f32,
    um_per_pixel_y: f32,
    measurement_type: u32,
    num_layers: u8,
}

impl Header {
    fn read(bytes: &Bytes) -> Result<Header, FormatError> {
        Ok(Header {
            rows: bytes.read::<u32>(CAL_ROWS, "the calibration's row count")? as usize,
            columns: bytes.read::<u32>(CAL_COLUMNS, "the calibration's column count")? as usize,
            um_per_pixel_x: bytes.read::<f32>(CAL_UM_PER_PIXEL_X, "the x pixel size (µm)")?,
            um_per_pixel_y: bytes.read::<f32>(CAL_UM_PER_PIXEL_Y, "the y pixel size (µm)")?,
            measurement_type: bytes.read::<u32>(MEASUREMENT_TYPE, "the measurement type")?,
            num_layers: bytes.read::<u8>(NUM_LAYERS, "the layer count")?,
        })
    }

    /// Everything that must hold before the heights are read, with the
    /// first layer's own grid size; the first failure as an error.
    fn check(&self, bytes: &Bytes, max_points: usize) -> Result<usize, FormatError> {
        if self.measurement_type > TYPE_LAST {
            return Err(FORMAT.invalid(format!(
                "measurement type {} at byte {MEASUREMENT_TYPE} is not one of 0…{TYPE_LAST}",
                self.measurement_type
            )));
        }
        if self.measurement_type != TYPE_TOPOGRAPHY {
            return Err(FORMAT.unsupported(format!(
                "measurement type {} at byte {MEASUREMENT_TYPE} is not a topography ({TYPE_TOPOGRAPHY}): \
                 profiles and images are not height maps",
                self.measurement_type
            )));
        }
        if self.num_layers == 0 {
            return Err(FORMAT.invalid(format!(
                "the layer count at byte {NUM_LAYERS} is 0: the file holds no height map"
            )));
        }
        for (value, offset, axis) in [
            (self.um_per_pixel_x, CAL_UM_PER_PIXEL_X, "x"),
            (self.um_per_pixel_y, CAL_UM_PER_PIXEL_Y, "y"),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(FORMAT.invalid(format!(
                    "the {axis} pixel size at byte {offset} is {value} µm, expected a positive number"
                )));
            }
        }
        let rows = bytes.read::<u32>(LAYER, "the layer's row count")? as usize;
        let columns = bytes.read::<u32>(LAYER + 4, "the layer's column count")? as usize;
        if (rows, columns) != (self.rows, self.columns) {
            return Err(FORMAT.invalid(format!(
                "the layer at byte {LAYER} is {columns} × {rows} points but the calibration at byte \
                 {CAL_ROWS} says {} × {}",
                self.columns, self.rows
            )));
        }
        let points = grid_points(FORMAT.name(), columns, rows, "the layer's grid", max_points)?;
        let needed = LAYER_DATA + 4 * points + 8;
        if bytes.len() < needed {
            return Err(FORMAT.invalid(format!(
                "a {columns} × {rows} layer of f32 heights and its min/max need {needed} bytes, \
                 the file has {}",
                bytes.len()
            )));
        }
        Ok(points)
    }
}

/// No magic number: `.plu` is known from its extension, see [`plausible`].
pub(crate) fn matches(_bytes: &[u8]) -> bool {
    false
}

/// Whether the whole file's bytes are a consistent `.plu` header followed by
/// its first layer (used together with the `.plu` extension).
pub(crate) fn plausible(bytes: &[u8]) -> bool {
    let bytes = Bytes::new(bytes, FORMAT.name(), ByteOrder::Little);
    let date_is_text = bytes.slice(DATE, DATE_LEN, "date").is_ok_and(|date| {
        date.iter()
            .take_while(|&&b| b != 0)
            .all(|b| b.is_ascii_graphic() || *b == b' ')
    });
    date_is_text
        && Header::read(&bytes)
            .and_then(|h| h.check(&bytes, MAX_POINTS))
            .is_ok()
}

/// Reads the first layer of a topography: heights in metres (µm in the file),
/// axis 0 = x, NaN where the instrument measured nothing.
pub(crate) fn read(data: &[u8], max_points: usize) -> Result<Topography, FormatError> {
    let bytes = Bytes::new(data, FORMAT.name(), ByteOrder::Little);
    let header = Header::read(&bytes)?;
    let points = header.check(&bytes, max_points)?;
    let (nx, ny) = (header.columns, header.rows);
    let heights_um = bytes.values::<f32>(LAYER_DATA, points, "the layer's heights")?;
    let heights_m = x_major(nx, ny, &heights_um, |h_um| {
        if h_um == NOT_MEASURED || !h_um.is_finite() {
            f64::NAN
        } else {
            f64::from(h_um) * 1e-6
        }
    });
    Ok(Topography {
        heights_m,
        dx_m: f64::from(header.um_per_pixel_x) * 1e-6,
        dy_m: f64::from(header.um_per_pixel_y) * 1e-6,
        format: Format::Plu,
        // The calibration's offsets (metadata below) are not documented as a
        // stage position (Gwyddion leaves them aside), so none is claimed.
        position_m: None,
        metadata: metadata(&bytes, &header)?,
    })
}

fn metadata(bytes: &Bytes, header: &Header) -> Result<Vec<(String, String)>, FormatError> {
    let mut metadata = vec![("vendor".to_string(), "Sensofar".to_string())];
    let version = bytes.read::<u8>(VERSION, "the format version")?;
    let hardware = bytes.read::<u8>(HARDWARE, "the hardware configuration")?;
    // Before version 2012 the hardware byte is unreliable.
    if version != 0
        && version <= VERSION_2012
        && let Some(name) = HARDWARE_NAMES.get(usize::from(hardware))
    {
        metadata.push(("instrument".into(), (*name).into()));
    }
    let date = bytes.text(DATE, DATE_LEN, "the date")?;
    if !date.is_empty() {
        metadata.push(("date".into(), date));
    }
    let time = bytes.read::<u32>(TIME, "the time stamp")?;
    metadata.push(("time_unix_s".into(), time.to_string()));
    if let Some(utc) = utc_text(i64::from(time)) {
        metadata.push(("date_utc".into(), utc));
    }
    let comment = bytes.text(COMMENT, COMMENT_LEN, "the comment")?;
    if !comment.is_empty() {
        metadata.push(("comment".into(), comment));
    }
    let objective = bytes.read::<u32>(OBJECTIVE, "the objective")?;
    metadata.push(("objective_id".into(), objective.to_string()));
    let algorithm = bytes.read::<u32>(ALGORITHM, "the algorithm")?;
    metadata.push(("algorithm_id".into(), algorithm.to_string()));
    metadata.push(("format_version_byte".into(), version.to_string()));
    metadata.push(("layers".into(), header.num_layers.to_string()));
    let images = bytes.read::<u8>(NUM_IMAGES, "the image count")?;
    metadata.push(("images_per_layer".into(), images.to_string()));
    for (key, offset) in [
        ("offset_x_um", CAL_OFFSET_X_UM),
        ("offset_y_um", CAL_OFFSET_Y_UM),
        ("offset_z_um", CAL_OFFSET_Z_UM),
    ] {
        metadata.push((key.into(), bytes.read::<f32>(offset, key)?.to_string()));
    }
    Ok(metadata)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A minimal valid file: `nx` × `ny` topography with `heights_um` (rows
    /// of constant y) and no RGB images.
    fn plu_file(nx: u32, ny: u32, um_per_pixel: f32, heights_um: &[f32]) -> Vec<u8> {
        let mut file = vec![0u8; LAYER];
        file[..24].copy_from_slice(b"Fri Mar 10 16:35:59 2023");
        file[CAL_ROWS..CAL_ROWS + 4].copy_from_slice(&ny.to_le_bytes());
        file[CAL_COLUMNS..CAL_COLUMNS + 4].copy_from_slice(&nx.to_le_bytes());
        file[CAL_UM_PER_PIXEL_X..CAL_UM_PER_PIXEL_X + 4]
            .copy_from_slice(&um_per_pixel.to_le_bytes());
        file[CAL_UM_PER_PIXEL_Y..CAL_UM_PER_PIXEL_Y + 4]
            .copy_from_slice(&um_per_pixel.to_le_bytes());
        file[MEASUREMENT_TYPE..MEASUREMENT_TYPE + 4]
            .copy_from_slice(&TYPE_TOPOGRAPHY.to_le_bytes());
        file[NUM_LAYERS] = 1;
        file[VERSION] = VERSION_2012;
        file[HARDWARE] = 9;
        file.extend_from_slice(&ny.to_le_bytes());
        file.extend_from_slice(&nx.to_le_bytes());
        for h in heights_um {
            file.extend_from_slice(&h.to_le_bytes());
        }
        file.extend_from_slice(&[0u8; 8]);
        file
    }

    #[test]
    fn micrometres_become_metres_and_the_marker_nan() {
        // 3 × 2: row y = 0 then y = 1
        let file = plu_file(3, 2, 0.5, &[1.0, -2.5, NOT_MEASURED, 0.25, 4.0, 8.0]);
        assert!(plausible(&file));
        let t = read(&file, crate::DEFAULT_MAX_POINTS).unwrap();
        assert_eq!(t.heights_m.dim(), (3, 2));
        let close = |a: f64, b: f64| (a - b).abs() < 1e-20;
        assert!(close(t.heights_m[[0, 0]], 1e-6));
        assert!(close(t.heights_m[[1, 0]], -2.5e-6));
        assert!(t.heights_m[[2, 0]].is_nan());
        assert!(close(t.heights_m[[0, 1]], 0.25e-6));
        assert!(close(t.heights_m[[2, 1]], 8e-6));
        assert_eq!((t.dx_m, t.dy_m), (0.5e-6, 0.5e-6));
        assert!(t.metadata.contains(&("instrument".into(), "S neox".into())));
    }

    #[test]
    fn inconsistent_headers_are_not_plausible() {
        let good = plu_file(3, 2, 0.5, &[0.0; 6]);
        let mut columns = good.clone();
        columns[CAL_COLUMNS] = 4;
        let mut pixel = good.clone();
        pixel[CAL_UM_PER_PIXEL_X..CAL_UM_PER_PIXEL_X + 4].copy_from_slice(&(-1.0f32).to_le_bytes());
        let mut kind = good.clone();
        kind[MEASUREMENT_TYPE] = 9;
        let short = good[..good.len() - 9].to_vec();
        for bad in [&columns, &pixel, &kind, &short] {
            assert!(!plausible(bad));
            assert!(matches!(
                read(bad, crate::DEFAULT_MAX_POINTS),
                Err(FormatError::Invalid { .. })
            ));
        }
        let err = read(&columns, crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(err.contains("calibration at byte 388 says 4 × 2"), "{err}");
        let mut profile = good;
        profile[MEASUREMENT_TYPE] = 1;
        assert!(matches!(
            read(&profile, crate::DEFAULT_MAX_POINTS),
            Err(FormatError::Unsupported { .. })
        ));
    }

    proptest::proptest! {
        #![proptest_config(hypercontact_fuzz::config(256))]

        /// The reader itself, past `plausible`: arbitrary bytes and edits of
        /// a small valid file are an error or a map, never a panic.
        #[test]
        fn read_never_panics(
            data in proptest::collection::vec(proptest::prelude::any::<u8>(), 0..1200),
            edits in hypercontact_fuzz::byte_edits(),
        ) {
            let _ = read(&data, crate::DEFAULT_MAX_POINTS);
            let heights: Vec<f32> = (0..12).map(|k| k as f32 - 3.0).collect();
            let edited = hypercontact_fuzz::splice(plu_file(4, 3, 0.5, &heights), &edits);
            // what `detect` trusts the extension for, the reader reads
            if plausible(&edited) {
                proptest::prop_assert!(read(&edited, crate::DEFAULT_MAX_POINTS).is_ok());
            }
        }
    }

    #[test]
    fn absurd_sizes_are_refused_before_reading() {
        let mut file = plu_file(1, 1, 1.0, &[0.0]);
        for offset in [CAL_ROWS, CAL_COLUMNS, LAYER, LAYER + 4] {
            file[offset..offset + 4].copy_from_slice(&1_000_000u32.to_le_bytes());
        }
        let err = read(&file, crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("1000000 × 1000000 = 1 000 000 000 000 points, above the limit of"),
            "{err}"
        );
    }
}
