//! Height maps as instruments write them.
//!
//! Every reader returns a [`Topography`]: heights in metres with axis 0 = x
//! (the convention of SurfaceTopography and of hypercontact's `.npy` maps),
//! NaN where the instrument recorded no point, and the grid spacing read from
//! the file. [`detect`] names the format from the bytes, so a file with the
//! wrong extension is still read by the right reader. [`write_x3p`] writes
//! any map as X3P, the open exchange format (e.g. to build tile sets, the
//! tile positions as the axes' offsets).

use std::path::Path;

use ndarray::Array2;

mod bytes;
mod datx;
mod metropro;
mod opd;
mod plu;
mod sur;
mod x3p;

pub use x3p::write_x3p;

/// The formats read here.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// NumPy `.npy` (no units or spacing inside: the caller gives them)
    Npy,
    /// ISO 25178-72 XML 3D surface profile (zip of main.xml + binary data)
    X3p,
    /// Digital Surf `.sur` (MountainsMap)
    Sur,
    /// Sensofar `.plu` (and `.apx`)
    Plu,
    /// Zygo MetroPro `.dat`
    MetroPro,
    /// Zygo Mx `.datx` (HDF5)
    Datx,
    /// Wyko / Veeco Vision `.opd`
    Opd,
}

impl Format {
    /// The usual name of the format, for messages.
    pub const fn name(self) -> &'static str {
        match self {
            Format::Npy => "NumPy .npy",
            Format::X3p => "ISO 25178-72 X3P",
            Format::Sur => "Digital Surf .sur",
            Format::Plu => "Sensofar .plu",
            Format::MetroPro => "Zygo MetroPro .dat",
            Format::Datx => "Zygo .datx",
            Format::Opd => "Wyko .opd",
        }
    }

    /// An error: the file breaks this format's layout.
    pub(crate) fn invalid(self, message: impl Into<String>) -> FormatError {
        FormatError::Invalid {
            format: self.name(),
            message: message.into(),
        }
    }

    /// An error: the file is this format's, but holds what is not read here.
    pub(crate) fn unsupported(self, message: impl Into<String>) -> FormatError {
        FormatError::Unsupported {
            format: self.name(),
            message: message.into(),
        }
    }
}

/// A height map read from an instrument file.
#[derive(Clone, Debug, PartialEq)]
pub struct Topography {
    /// heights in metres, axis 0 = x, NaN = not measured
    pub heights_m: Array2<f64>,
    /// grid spacing along x (axis 0)
    pub dx_m: f64,
    /// grid spacing along y (axis 1)
    pub dy_m: f64,
    /// the format it was read as
    pub format: Format,
    /// the stage position of the map's first point (x, y), where the file records one
    pub position_m: Option<(f64, f64)>,
    /// what else the file says (instrument, date, objective …), as key–value text
    pub metadata: Vec<(String, String)>,
}

/// Why a file could not be read. Messages say what was expected and where
/// (byte offset or XML element), never only "invalid".
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum FormatError {
    #[error("not a height-map format hypercontact reads (first bytes {0})")]
    Unknown(String),
    #[error("{format}: {message}")]
    Invalid {
        format: &'static str,
        message: String,
    },
    #[error("{format}: {message}")]
    Unsupported {
        format: &'static str,
        message: String,
    },
}

/// The format of a file from its bytes; the extension decides only where
/// the bytes alone cannot.
///
/// Every format with a magic number is told by its first 18 bytes (the
/// name of a Wyko `.opd` directory ends at byte 18; the other magics take at
/// most 12). Sensofar `.plu` (and `.apx`, the same layout: SurfaceTopography
/// 1.27's PLU reader takes both) has none: it is recognised only by its
/// extension together with a header that agrees with the whole file (grid
/// sizes, pixel size, measurement type, a first layer that fits in the
/// file), so pass the whole file, not only its first bytes.
pub fn detect(bytes: &[u8], path: Option<&Path>) -> Option<Format> {
    if bytes.starts_with(b"\x93NUMPY") {
        return Some(Format::Npy);
    }
    let by_bytes = [
        (Format::X3p, x3p::matches as fn(&[u8]) -> bool),
        (Format::Sur, sur::matches),
        (Format::MetroPro, metropro::matches),
        (Format::Datx, datx::matches),
        (Format::Opd, opd::matches),
        (Format::Plu, plu::matches),
    ];
    if let Some((format, _)) = by_bytes.iter().find(|(_, m)| m(bytes)) {
        return Some(*format);
    }
    let extension = path?.extension()?.to_str()?.to_ascii_lowercase();
    match extension.as_str() {
        "plu" | "apx" if plu::plausible(bytes) => Some(Format::Plu),
        _ => None,
    }
}

/// Reads a height map from a file's bytes; `path` only helps [`detect`].
/// Never panics, whatever the bytes.
pub fn read_bytes(bytes: &[u8], path: Option<&Path>) -> Result<Topography, FormatError> {
    let Some(format) = detect(bytes, path) else {
        let shown: Vec<String> = bytes.iter().take(8).map(|b| format!("{b:02x}")).collect();
        return Err(FormatError::Unknown(shown.join(" ")));
    };
    match format {
        Format::Npy => Err(FormatError::Unsupported {
            format: format.name(),
            message: "holds no grid spacing: read it as a field with pixel_m".into(),
        }),
        Format::X3p => x3p::read(bytes),
        Format::Sur => sur::read(bytes),
        Format::Plu => plu::read(bytes),
        Format::MetroPro => metropro::read(bytes),
        Format::Datx => datx::read(bytes),
        Format::Opd => opd::read(bytes),
    }
}
