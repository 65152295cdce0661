//! Zygo MetroPro `.dat` files (binary, written by MetroPro's "Save Data").
//!
//! A big-endian header (834 bytes for header formats 1 and 2, 4096 for
//! format 3, told apart by the magic number), then the intensity buckets
//! (`u16`) and the phase map (`i32`), each stored as rows of constant y.
//! Phase counts become heights as
//!
//! h = S · O · λ / R · count,
//!
//! with S the interferometric scale factor, O the obliquity factor, λ the
//! wavelength (m) and R the counts per fringe of the phase resolution
//! (4096, 32768 or 131072), negated when the header's `sign` is set; counts
//! ≥ 2147483640 mark invalid points. Layout and formula as in the MetroPro
//! Reference Guide (0347M), Gwyddion's `metropro.c` and SurfaceTopography's
//! `IO/MetroPro.py`.

use crate::bytes::{ByteOrder, Bytes, grid_points, utc_text, x_major};
use crate::{Format, FormatError, Topography};

const FORMAT: Format = Format::MetroPro;

/// Magic numbers of header formats 1, 2 and 3.
const MAGIC: [u32; 3] = [0x881B_036F, 0x881B_0370, 0x881B_0371];
/// Header size each header format declares (SurfaceTopography checks the same).
const HEADER_SIZE: [u32; 3] = [834, 834, 4096];

// Byte offsets in the header (MetroPro Reference Guide; big-endian).
const HEADER_FORMAT: usize = 4;
const HEADER_SIZE_AT: usize = 6;
const SOFTWARE_TYPE: usize = 10;
const SOFTWARE_DATE: usize = 12;
const VERSION: usize = 42;
const INTENSITY_WIDTH: usize = 52;
const INTENSITY_HEIGHT: usize = 54;
const BUCKETS: usize = 56;
const PHASE_WIDTH: usize = 68;
const PHASE_HEIGHT: usize = 70;
const TIME_STAMP: usize = 76;
const COMMENT: usize = 80;
const SCALE_FACTOR: usize = 164;
const WAVELENGTH_M: usize = 168;
const OBLIQUITY: usize = 176;
const MAGNIFICATION: usize = 180;
const LATERAL_RES_M: usize = 184;
const PHASE_RES: usize = 218;
const SIGN: usize = 232;
const SYSTEM_TYPE: usize = 238;
const SYSTEM_SERIAL: usize = 242;
const OBJECTIVE: usize = 246;
const PART: usize = 258;
const SCAN_DESCRIPTION: usize = 408;

/// Phase counts at or above this mark an invalid point.
const INVALID_PHASE: i32 = 2_147_483_640;

/// Software that wrote the file, by `software_type` (Gwyddion's metropro.c).
const SOFTWARE: [&str; 3] = ["MetroPro", "MetroBasic", "dbug"];

/// Whether the first bytes are one of the three MetroPro magic numbers.
pub(crate) fn matches(bytes: &[u8]) -> bool {
    Bytes::new(bytes, FORMAT.name(), ByteOrder::Big)
        .read::<u32>(0, "magic")
        .is_ok_and(|magic| MAGIC.contains(&magic))
}

/// Counts per fringe of a phase resolution code (0 normal, 1 high, 2 super high).
fn counts_per_fringe(phase_res: i16) -> Option<f64> {
    match phase_res {
        0 => Some(4096.0),
        1 => Some(32768.0),
        2 => Some(131_072.0),
        _ => None,
    }
}

/// Metres per phase count: S · O · λ / R, negated for an inverted sign.
fn metres_per_count(
    scale: f32,
    obliquity: f32,
    wavelength_m: f32,
    per_fringe: f64,
    inverted: bool,
) -> f64 {
    let sign = if inverted { -1.0 } else { 1.0 };
    sign * f64::from(scale) * f64::from(obliquity) * f64::from(wavelength_m) / per_fringe
}

/// Reads the phase map as heights in metres, axis 0 = x, NaN where invalid.
pub(crate) fn read(data: &[u8], max_points: usize) -> Result<Topography, FormatError> {
    let bytes = Bytes::new(data, FORMAT.name(), ByteOrder::Big);
    let magic = bytes.read::<u32>(0, "the magic number")?;
    let Some(kind) = MAGIC.iter().position(|&m| m == magic) else {
        return Err(FORMAT.invalid(format!(
            "magic number {magic:#010x} at byte 0 is none of 0x881b036f, 0x881b0370, 0x881b0371"
        )));
    };
    let header_size = bytes.read::<u32>(HEADER_SIZE_AT, "the header size")?;
    if header_size != HEADER_SIZE[kind] {
        return Err(FORMAT.unsupported(format!(
            "header size {header_size} at byte {HEADER_SIZE_AT}: header format {} has {} bytes",
            kind + 1,
            HEADER_SIZE[kind]
        )));
    }
    let intensity_width = usize::from(bytes.read::<u16>(INTENSITY_WIDTH, "the intensity width")?);
    let intensity_height =
        usize::from(bytes.read::<u16>(INTENSITY_HEIGHT, "the intensity height")?);
    let buckets = usize::from(bytes.read::<u16>(BUCKETS, "the bucket count")?);
    let nx = usize::from(bytes.read::<u16>(PHASE_WIDTH, "the phase width")?);
    let ny = usize::from(bytes.read::<u16>(PHASE_HEIGHT, "the phase height")?);
    if nx == 0 || ny == 0 {
        return Err(FORMAT.invalid(format!(
            "the phase map (bytes {PHASE_WIDTH}..{}) is {nx} × {ny}: the file holds no heights",
            PHASE_HEIGHT + 2
        )));
    }
    let points = grid_points(FORMAT.name(), nx, ny, "the phase map", max_points)?;
    // u16 sizes: these products cannot overflow
    let intensity_bytes = 2 * buckets * intensity_width * intensity_height;
    let phase_at = header_size as usize + intensity_bytes;

    let phase_res = bytes.read::<i16>(PHASE_RES, "the phase resolution")?;
    let per_fringe = counts_per_fringe(phase_res).ok_or_else(|| {
        FORMAT.invalid(format!(
            "phase resolution {phase_res} at byte {PHASE_RES} is not 0, 1 or 2"
        ))
    })?;
    let scale = bytes.read::<f32>(SCALE_FACTOR, "the interferometric scale factor")?;
    let obliquity = bytes.read::<f32>(OBLIQUITY, "the obliquity factor")?;
    let wavelength_m = bytes.read::<f32>(WAVELENGTH_M, "the wavelength")?;
    let inverted = bytes.read::<i16>(SIGN, "the sign")? != 0;
    let per_count = metres_per_count(scale, obliquity, wavelength_m, per_fringe, inverted);
    if !(per_count.is_finite() && per_count != 0.0) {
        return Err(FORMAT.invalid(format!(
            "scale factor {scale} (byte {SCALE_FACTOR}) × obliquity {obliquity} (byte {OBLIQUITY}) × \
             wavelength {wavelength_m} m (byte {WAVELENGTH_M}) gives no height scale"
        )));
    }
    let pixel_m = f64::from(bytes.read::<f32>(LATERAL_RES_M, "the lateral resolution")?);
    if !(pixel_m.is_finite() && pixel_m > 0.0) {
        return Err(FORMAT.unsupported(format!(
            "lateral resolution {pixel_m} m at byte {LATERAL_RES_M}: the file has no lateral \
             calibration (set it in MetroPro before saving)"
        )));
    }

    let counts = bytes.values::<i32>(phase_at, points, "the phase map")?;
    let heights_m = x_major(nx, ny, &counts, |count| {
        if count >= INVALID_PHASE {
            f64::NAN
        } else {
            per_count * f64::from(count)
        }
    });
    Ok(Topography {
        heights_m,
        dx_m: pixel_m,
        dy_m: pixel_m,
        format: Format::MetroPro,
        // The header's stage coordinate block (coords_*) has no established
        // units or byte order; no position is claimed.
        position_m: None,
        metadata: metadata(&bytes, kind)?,
    })
}

fn metadata(bytes: &Bytes, kind: usize) -> Result<Vec<(String, String)>, FormatError> {
    let mut metadata = vec![("vendor".to_string(), "Zygo".to_string())];
    let software = bytes.read::<i16>(SOFTWARE_TYPE, "the software type")?;
    let version: Vec<String> = (0..3)
        .map(|i| {
            bytes
                .read::<i16>(VERSION + 2 * i, "the software version")
                .map(|v| v.to_string())
        })
        .collect::<Result<_, _>>()?;
    let name = usize::try_from(software - 1)
        .ok()
        .and_then(|i| SOFTWARE.get(i))
        .map_or_else(|| format!("software type {software}"), |s| (*s).to_string());
    metadata.push(("software".into(), format!("{name} {}", version.join("."))));
    metadata.push((
        "software_date".into(),
        bytes.text(SOFTWARE_DATE, 30, "the software date")?,
    ));
    metadata.push(("header_format".into(), (kind + 1).to_string()));
    let header_format = bytes.read::<u16>(HEADER_FORMAT, "the header format")?;
    if usize::from(header_format) != kind + 1 {
        metadata.push(("header_format_field".into(), header_format.to_string()));
    }
    let stamp = bytes.read::<i32>(TIME_STAMP, "the time stamp")?;
    metadata.push(("time_unix_s".into(), stamp.to_string()));
    if let Some(utc) = utc_text(i64::from(stamp)) {
        metadata.push(("date_utc".into(), utc));
    }
    metadata.push((
        "system_type".into(),
        bytes
            .read::<i16>(SYSTEM_TYPE, "the system type")?
            .to_string(),
    ));
    metadata.push((
        "serial".into(),
        bytes
            .read::<u16>(SYSTEM_SERIAL, "the system serial")?
            .to_string(),
    ));
    for (key, offset, len) in [
        ("comment", COMMENT, 82),
        ("objective", OBJECTIVE, 12),
        ("part", PART, 40),
        ("scan", SCAN_DESCRIPTION, 20),
    ] {
        let text = bytes.text(offset, len, key)?;
        if !text.is_empty() {
            metadata.push((key.into(), text));
        }
    }
    let wavelength_m = bytes.read::<f32>(WAVELENGTH_M, "the wavelength")?;
    metadata.push(("wavelength_m".into(), wavelength_m.to_string()));
    let magnification = bytes.read::<f32>(MAGNIFICATION, "the magnification")?;
    if magnification != 0.0 {
        metadata.push(("magnification".into(), magnification.to_string()));
    }
    Ok(metadata)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A header-format-1 file with an `nx` × `ny` phase map (rows of
    /// constant y), one intensity bucket of the same size, and the given
    /// scale, obliquity, wavelength, phase resolution and sign.
    fn dat_file(nx: u16, ny: u16, counts: &[i32], phase_res: i16, sign: i16) -> Vec<u8> {
        let mut file = vec![0u8; 834];
        file[0..4].copy_from_slice(&MAGIC[0].to_be_bytes());
        file[HEADER_FORMAT..HEADER_FORMAT + 2].copy_from_slice(&1u16.to_be_bytes());
        file[HEADER_SIZE_AT..HEADER_SIZE_AT + 4].copy_from_slice(&834u32.to_be_bytes());
        file[SOFTWARE_TYPE..SOFTWARE_TYPE + 2].copy_from_slice(&1i16.to_be_bytes());
        for (at, value) in [(INTENSITY_WIDTH, nx), (INTENSITY_HEIGHT, ny), (BUCKETS, 1)] {
            file[at..at + 2].copy_from_slice(&value.to_be_bytes());
        }
        file[PHASE_WIDTH..PHASE_WIDTH + 2].copy_from_slice(&nx.to_be_bytes());
        file[PHASE_HEIGHT..PHASE_HEIGHT + 2].copy_from_slice(&ny.to_be_bytes());
        for (at, value) in [
            (SCALE_FACTOR, 0.5f32),
            (OBLIQUITY, 1.0),
            (WAVELENGTH_M, 600e-9),
            (LATERAL_RES_M, 2e-6),
        ] {
            file[at..at + 4].copy_from_slice(&value.to_be_bytes());
        }
        file[PHASE_RES..PHASE_RES + 2].copy_from_slice(&phase_res.to_be_bytes());
        file[SIGN..SIGN + 2].copy_from_slice(&sign.to_be_bytes());
        file.extend(std::iter::repeat_n(
            7u8,
            2 * usize::from(nx) * usize::from(ny),
        ));
        for c in counts {
            file.extend_from_slice(&c.to_be_bytes());
        }
        file
    }

    #[test]
    fn the_height_scale_is_s_o_lambda_over_r() {
        // 0.5 · 1 · 600 nm / 4096 per count, and the other resolutions
        assert_eq!(
            metres_per_count(0.5, 1.0, 600e-9, 4096.0, false),
            0.5 * f64::from(600e-9f32) / 4096.0
        );
        assert_eq!(counts_per_fringe(1), Some(32768.0));
        assert_eq!(counts_per_fringe(2), Some(131_072.0));
        assert_eq!(counts_per_fringe(3), None);
        assert_eq!(
            metres_per_count(0.5, 2.0, 1.0, 32768.0, true),
            -1.0 / 32768.0
        );
    }

    #[test]
    fn a_fringe_of_counts_is_half_a_wavelength_of_height() {
        // reflection: one fringe (4096 counts at resolution 0, S = 0.5) is λ/2
        let file = dat_file(2, 2, &[4096, -4096, INVALID_PHASE, 0], 0, 0);
        assert!(matches(&file));
        let t = read(&file, crate::DEFAULT_MAX_POINTS).unwrap();
        let half_wave_m = f64::from(600e-9f32) / 2.0;
        assert_eq!(t.heights_m[[0, 0]], half_wave_m);
        assert_eq!(t.heights_m[[1, 0]], -half_wave_m);
        assert!(t.heights_m[[0, 1]].is_nan());
        assert_eq!(t.heights_m[[1, 1]], 0.0);
        assert_eq!(t.dx_m, f64::from(2e-6f32));
        // the sign flag inverts, resolution 1 divides by 32768
        let t = read(
            &dat_file(2, 2, &[32768, 0, 0, 0], 1, 1),
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap();
        assert_eq!(t.heights_m[[0, 0]], -half_wave_m);
    }

    #[test]
    fn headers_are_checked_where_they_are_wrong() {
        let good = dat_file(2, 1, &[0, 0], 0, 0);
        let mut size = good.clone();
        size[HEADER_SIZE_AT + 3] = 0;
        assert!(
            read(&size, crate::DEFAULT_MAX_POINTS)
                .unwrap_err()
                .to_string()
                .contains("at byte 6")
        );
        let mut res = good.clone();
        res[PHASE_RES + 1] = 5;
        assert!(
            read(&res, crate::DEFAULT_MAX_POINTS)
                .unwrap_err()
                .to_string()
                .contains("at byte 218")
        );
        let mut lateral = good.clone();
        lateral[LATERAL_RES_M..LATERAL_RES_M + 4].copy_from_slice(&0f32.to_be_bytes());
        assert!(matches!(
            read(&lateral, crate::DEFAULT_MAX_POINTS),
            Err(FormatError::Unsupported { .. })
        ));
        let short = &good[..good.len() - 1];
        let err = read(short, crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(err.contains("the phase map needs bytes 838..846"), "{err}");
        assert!(!matches(b"\x88\x1b\x03\x72"));
    }
}
