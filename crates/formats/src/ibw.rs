//! Igor Pro binary waves (`.ibw`, version 5), as Asylum Research AFMs
//! write their images: a 64-byte `BinHeader5` (the sizes of the sections
//! after the data), a 320-byte `WaveHeader5` (type, dimensions `nDim`,
//! spacings `sfA`, units), the values, then the formula, the note, the
//! extended units and the dimension labels. Layout after WaveMetrics'
//! Technical Note 003 ("Igor Binary Format"); the byte order is the one
//! in which the version reads 5, and the 16-bit sum of both headers is
//! zero (their checksum), which is how a wave is told from its bytes.
//!
//! An AFM image is a 3-D wave: x × y × channels, stored with x fastest;
//! the channels' names are the labels of dimension 2 (its label 0 names
//! the dimension). As in SurfaceTopography's `IO/IBW.py` every layer is a
//! channel in the wave's data unit, the default is the first, and the y
//! axis is flipped.

use ndarray::Array2;

use crate::bytes::{ByteOrder, Bytes, grid_points, latin1};
use crate::channel::{self, Channel};
use crate::units::metres_per;
use crate::{Format, FormatError, Topography};

const FORMAT: Format = Format::Ibw;

const BIN_HEADER: usize = 64;
const WAVE_HEADER: usize = 320;
/// A dimension label: 31 characters and a NUL.
const LABEL_LEN: usize = 32;

// Offsets in the binary header.
const WFM_SIZE: usize = 4;
const FORMULA_SIZE: usize = 8;
const NOTE_SIZE: usize = 12;
const DATA_E_UNITS_SIZE: usize = 16;
const DIM_E_UNITS_SIZE: usize = 20;
const DIM_LABELS_SIZE: usize = 36;
// Offsets in the wave header, from the file's start.
const TYPE: usize = BIN_HEADER + 16;
const NAME: usize = BIN_HEADER + 28;
const N_DIM: usize = BIN_HEADER + 68;
const SF_A: usize = BIN_HEADER + 84;
const DATA_UNITS: usize = BIN_HEADER + 148;
const DIM_UNITS: usize = BIN_HEADER + 152;

/// The byte order in which the version is 5 and the headers sum to zero.
fn order(bytes: &[u8]) -> Option<ByteOrder> {
    let headers = bytes.get(..BIN_HEADER + WAVE_HEADER)?;
    [ByteOrder::Little, ByteOrder::Big]
        .into_iter()
        .find(|&order| {
            let b = Bytes::new(headers, FORMAT.name(), order);
            let sum = (0..headers.len() / 2)
                .filter_map(|k| b.read::<u16>(2 * k, "a checksum word").ok())
                .fold(0u16, u16::wrapping_add);
            b.read::<u16>(0, "the version").ok() == Some(5) && sum == 0
        })
}

/// Whether the file is a version-5 wave whose headers check out.
pub(crate) fn matches(bytes: &[u8]) -> bool {
    order(bytes).is_some()
}

/// The wave's shape and where its parts are.
struct Wave {
    nx: usize,
    ny: usize,
    kind: u16,
    dx_m: f64,
    dy_m: f64,
    unit_m: Option<f64>,
    unit: String,
    /// the layers' names
    names: Vec<String>,
    note: String,
}

/// Bytes of one value of an Igor number type (complex is refused).
fn value_size(kind: u16) -> Result<usize, FormatError> {
    match kind & !0x40 {
        2 => Ok(4),
        4 => Ok(8),
        8 => Ok(1),
        0x10 => Ok(2),
        0x20 => Ok(4),
        _ => Err(FORMAT.unsupported(format!(
            "byte {TYPE}: wave type {kind:#x} (real numbers are read, not complex or text)"
        ))),
    }
}

fn wave(bytes: &Bytes, max_points: usize) -> Result<Wave, FormatError> {
    let size = |at: usize, what: &str| -> Result<usize, FormatError> {
        let value = bytes.read::<i32>(at, what)?;
        usize::try_from(value)
            .ok()
            .filter(|&v| v <= bytes.len())
            .ok_or_else(|| {
                FORMAT.invalid(format!("byte {at}: {what} {value} does not fit the file"))
            })
    };
    let kind = bytes.read::<u16>(TYPE, "the wave type")?;
    let item = value_size(kind)?;
    let mut dims = [0usize; 4];
    for (k, dim) in dims.iter_mut().enumerate() {
        *dim = size(N_DIM + 4 * k, "a dimension's size")?;
    }
    let [nx, ny, layers, _] = dims;
    let layers = layers.max(1);
    let points = grid_points(FORMAT.name(), nx, ny, "nDim", max_points)?;
    let values = points.saturating_mul(layers).saturating_mul(item);
    let data_end = BIN_HEADER + size(WFM_SIZE, "the wave size")?;
    if BIN_HEADER + WAVE_HEADER + values > data_end {
        return Err(FORMAT.invalid(format!(
            "byte {N_DIM}: {nx} × {ny} × {layers} values do not fit the wave size"
        )));
    }
    let unit = |at: usize| latin1(bytes.slice(at, 4, "a unit").unwrap_or_default());
    let mut at = data_end + size(FORMULA_SIZE, "the formula size")?;
    let note_len = size(NOTE_SIZE, "the note size")?;
    let note = bytes.text(at, note_len, "the note").unwrap_or_default();
    at += note_len;
    let data_unit = match size(DATA_E_UNITS_SIZE, "the extended unit size")? {
        0 => unit(DATA_UNITS),
        len => bytes.text(at, len, "the extended data unit")?,
    };
    at += size(DATA_E_UNITS_SIZE, "the extended unit size")?;
    for k in 0..4 {
        at += size(DIM_E_UNITS_SIZE + 4 * k, "an extended dimension unit size")?;
    }
    for k in 0..2 {
        at += size(DIM_LABELS_SIZE + 4 * k, "a label size")?;
    }
    let labels_len = size(DIM_LABELS_SIZE + 8, "the channel labels' size")?;
    let labels = bytes
        .slice(at, labels_len, "the channel labels")
        .unwrap_or_default();
    let mut names: Vec<String> = labels
        .chunks_exact(LABEL_LEN)
        .skip(1)
        .take(layers)
        .map(latin1)
        .collect();
    while names.len() < layers {
        names.push(format!("no name ({})", names.len() + 1));
    }
    let spacing = |axis: usize| -> Result<f64, FormatError> {
        let sf = bytes.read::<f64>(SF_A + 8 * axis, "a spacing")?;
        let unit = unit(DIM_UNITS + 4 * axis);
        let m = metres_per(&unit).ok_or_else(|| {
            FORMAT.unsupported(format!("dimension {axis} is in \"{unit}\", not a length"))
        })?;
        Ok(sf * m)
    };
    Ok(Wave {
        nx,
        ny,
        kind,
        dx_m: spacing(0)?,
        dy_m: spacing(1)?,
        unit_m: metres_per(&data_unit),
        unit: data_unit,
        names,
        note,
    })
}

/// One layer's values as f64.
fn layer(bytes: &Bytes, wave: &Wave, index: usize) -> Result<Vec<f64>, FormatError> {
    let n = wave.nx * wave.ny;
    let item = value_size(wave.kind)?;
    let at = BIN_HEADER + WAVE_HEADER + index * n * item;
    let what = format!("channel {} at byte {at}", wave.names[index]);
    let unsigned = wave.kind & 0x40 != 0;
    Ok(match (wave.kind & !0x40, unsigned) {
        (2, _) => bytes
            .values::<f32>(at, n, &what)?
            .into_iter()
            .map(f64::from)
            .collect(),
        (4, _) => bytes.values::<f64>(at, n, &what)?,
        (kind, unsigned) => {
            let bits = match kind {
                8 => 8,
                0x10 => 16,
                _ => 32,
            };
            bytes.integers(at, n, (bits, !unsigned), &what)?
        }
    })
}

/// Reads the channel `asked` for.
pub(crate) fn read(
    data: &[u8],
    asked: &Channel,
    max_points: usize,
) -> Result<Topography, FormatError> {
    let order = order(data).ok_or_else(|| {
        FORMAT.invalid("the headers' checksum or version (5) is wrong: not an Igor wave read here")
    })?;
    let bytes = Bytes::new(data, FORMAT.name(), order);
    let wave = wave(&bytes, max_points)?;
    let index = channel::pick(FORMAT, &wave.names, 0, asked)?;
    let unit_m = wave.unit_m.ok_or_else(|| {
        FORMAT.unsupported(format!(
            "the wave's values are in \"{}\", not a length",
            wave.unit
        ))
    })?;
    FORMAT.check_spacings(wave.dx_m, wave.dy_m, format_args!("the sfA at byte {SF_A}"))?;
    let values = layer(&bytes, &wave, index)?;
    let (nx, ny) = (wave.nx, wave.ny);
    let heights_m =
        Array2::from_shape_fn((nx, ny), |(i, j)| values[i + nx * (ny - 1 - j)] * unit_m);
    let mut metadata = vec![
        ("vendor".to_string(), "Asylum Research".to_string()),
        ("wave".into(), bytes.text(NAME, 32, "the wave name")?),
    ];
    let mut scan_points = None;
    for line in crate::text::lines(&wave.note) {
        if let Some((key, value)) = line.split_once(':') {
            let name = match key.trim() {
                "MicroscopeModel" => "instrument",
                "Date" => "date",
                "Time" => "time",
                "IgorFileVersion" => "igor_version",
                "ScanPoints" => {
                    scan_points = scan_points.or(value.trim().parse::<usize>().ok());
                    continue;
                }
                _ => continue,
            };
            metadata.push((name.into(), value.trim().to_string()));
        }
    }
    // An Asylum image's `ScanPoints` are the points of a scan line: where
    // they are the wave's first dimension, its rows (x) are the scan lines.
    if scan_points == Some(nx) {
        metadata.push((crate::FAST_AXIS.into(), "x".into()));
    }
    let map = Topography::new(FORMAT, heights_m, wave.dx_m, wave.dy_m, metadata);
    Ok(channel::with_channels(map, &wave.names, index))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2 × 2 × 2 f32 wave in m with labels for its two layers.
    fn wave_file() -> Vec<u8> {
        let mut f = vec![0u8; BIN_HEADER + WAVE_HEADER];
        f[0..2].copy_from_slice(&5u16.to_le_bytes());
        let wfm = (WAVE_HEADER + 8 * 4) as i32;
        f[WFM_SIZE..WFM_SIZE + 4].copy_from_slice(&wfm.to_le_bytes());
        f[DIM_LABELS_SIZE + 8..DIM_LABELS_SIZE + 12].copy_from_slice(&96i32.to_le_bytes());
        f[TYPE..TYPE + 2].copy_from_slice(&2u16.to_le_bytes());
        for (k, n) in [2i32, 2, 2].iter().enumerate() {
            f[N_DIM + 4 * k..N_DIM + 4 * k + 4].copy_from_slice(&n.to_le_bytes());
        }
        for k in 0..2 {
            f[SF_A + 8 * k..SF_A + 8 * k + 8].copy_from_slice(&1e-6f64.to_le_bytes());
            f[DIM_UNITS + 4 * k] = b'm';
        }
        f[DATA_UNITS] = b'm';
        let sum = (0..f.len() / 2)
            .map(|k| u16::from_le_bytes([f[2 * k], f[2 * k + 1]]))
            .fold(0u16, u16::wrapping_add);
        f[2..4].copy_from_slice(&0u16.wrapping_sub(sum).to_le_bytes());
        for v in [1.0f32, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0] {
            f.extend(v.to_le_bytes());
        }
        for label in ["", "HeightTrace", "Amplitude"] {
            let mut l = label.as_bytes().to_vec();
            l.resize(LABEL_LEN, 0);
            f.extend(l);
        }
        f
    }

    #[test]
    fn layers_are_channels_x_fastest_y_flipped() {
        let f = wave_file();
        assert!(matches(&f));
        let map = read(&f, &Channel::Default, crate::DEFAULT_MAX_POINTS).unwrap();
        assert_eq!(map.heights_m[[0, 0]], 3.0);
        assert_eq!(map.heights_m[[1, 1]], 2.0);
        assert_eq!(map.metadata[1].1, "0: HeightTrace; 1: Amplitude");
        let second = read(
            &f,
            &Channel::Name("amplitude".into()),
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap();
        assert_eq!(second.heights_m[[0, 0]], 7.0);
    }

    #[test]
    fn a_wrong_checksum_is_not_a_wave() {
        let mut f = wave_file();
        f[100] ^= 1;
        assert!(!matches(&f));
        assert!(read(&f, &Channel::Default, crate::DEFAULT_MAX_POINTS).is_err());
    }
}
