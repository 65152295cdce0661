//! Height maps as instruments write them.
//!
//! Every reader returns a [`Topography`]: heights in metres with axis 0 = x
//! (the convention of SurfaceTopography and of hypercontact's `.npy` maps),
//! NaN where the instrument recorded no point, and the grid spacing read from
//! the file. [`detect`] names the format from the bytes, so a file with the
//! wrong extension is still read by the right reader. [`write_x3p`] writes
//! any map as X3P, the open exchange format (e.g. to build tile sets, the
//! tile positions as the axes' offsets).
//!
//! Files that hold several channels (AFM trace and retrace, height and
//! phase) are read one channel at a time: [`read_bytes_channel`] takes a
//! [`Channel`] by name or index, [`read_bytes`] the default one (the height
//! channel SurfaceTopography reads by default); the metadata keys `channel`
//! and `channels` name the channel read and list every channel found. A
//! line scan (a stylus profile) is a map of one point along y: shape
//! (n, 1), `dy_m` equal to `dx_m`, and the metadata key `line_scan`.

use std::path::Path;

use ndarray::Array2;

mod al3d;
mod ascii;
mod bytes;
mod cfb;
mod channel;
mod datx;
mod dektak;
mod frt;
mod ibw;
mod metropro;
mod mi;
mod mnt;
mod nanoscope;
mod netcdf;
mod nid;
mod opd;
mod plu;
mod size_bound;
mod sur;
mod text;
mod tmd;
mod units;
mod x3p;

pub use size_bound::{HEADER_ALLOWANCE_BYTES, bytes_per_point, max_file_bytes};

pub use channel::Channel;
pub use x3p::write_x3p;

/// The most points a reader accepts unless the caller raises it
/// (2^26 = 67 108 864 points, 512 MiB of f64): a header claiming more is
/// refused before anything is allocated or inflated, whatever the file's
/// size, so a small compressed file cannot expand into gigabytes.
pub const DEFAULT_MAX_POINTS: usize = 1 << 26;

/// The most `max_points` may be raised to (2^32 points, 32 GiB of f64).
pub const MAX_POINTS_CEILING: usize = bytes::MAX_POINTS;

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
    /// Alicona Imaging `.al3d`
    Al3d,
    /// Bruker / Veeco / Digital Instruments Nanoscope (`.di`, `.spm`, `.001`)
    Nanoscope,
    /// FRT MicroProf `.frt`
    Frt,
    /// Digital Surf MountainsMap document `.mnt`
    Mnt,
    /// Nanosurf easyScan `.nid` / `.ezd`
    Nid,
    /// Igor binary wave `.ibw` (Asylum Research AFMs)
    Ibw,
    /// Molecular Imaging / Agilent PicoView `.mi`
    Mi,
    /// TrueMap / GelSight `.tmd`
    Tmd,
    /// NetCDF classic `.nc` (SurfaceTopography's layout)
    NetCdf,
    /// Plain-text height matrix (`.txt`, `.asc`), with or without a header
    /// (Gwyddion's ASCII export among them)
    AsciiMatrix,
    /// Bruker Dektak stylus profile exported as `.csv`
    DektakCsv,
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
            Format::Al3d => "Alicona .al3d",
            Format::Nanoscope => "Bruker Nanoscope .di",
            Format::Frt => "FRT .frt",
            Format::Mnt => "Digital Surf .mnt",
            Format::Nid => "Nanosurf .nid",
            Format::Ibw => "Igor .ibw",
            Format::Mi => "Molecular Imaging .mi",
            Format::Tmd => "TrueMap .tmd",
            Format::NetCdf => "NetCDF .nc",
            Format::AsciiMatrix => "ASCII matrix",
            Format::DektakCsv => "Dektak .csv",
        }
    }

    /// Every format read here, in the order `detect` tries them.
    pub const ALL: [Format; 18] = [
        Format::Npy,
        Format::X3p,
        Format::Sur,
        Format::Plu,
        Format::MetroPro,
        Format::Datx,
        Format::Opd,
        Format::Al3d,
        Format::Nanoscope,
        Format::Frt,
        Format::Mnt,
        Format::Nid,
        Format::Ibw,
        Format::Mi,
        Format::Tmd,
        Format::NetCdf,
        Format::DektakCsv,
        Format::AsciiMatrix,
    ];

    /// The names of every format read, for messages.
    pub fn all_names() -> String {
        let names: Vec<&str> = Format::ALL.iter().map(|f| f.name()).collect();
        names.join(", ")
    }

    /// An error: the file breaks this format's layout.
    pub(crate) fn invalid(self, message: impl Into<String>) -> FormatError {
        FormatError::Invalid {
            format: self.name(),
            message: message.into(),
        }
    }

    /// Refuses grid spacings that are not positive and finite; `source`
    /// says where in the file they come from.
    pub(crate) fn check_spacings(
        self,
        dx_m: f64,
        dy_m: f64,
        source: impl std::fmt::Display,
    ) -> Result<(), FormatError> {
        if dx_m.is_finite() && dx_m > 0.0 && dy_m.is_finite() && dy_m > 0.0 {
            Ok(())
        } else {
            Err(self.invalid(format!(
                "{source} give the spacings {dx_m} m × {dy_m} m; both must be positive"
            )))
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

impl Topography {
    /// A map whose file records no stage position.
    pub(crate) fn new(
        format: Format,
        heights_m: Array2<f64>,
        dx_m: f64,
        dy_m: f64,
        metadata: Vec<(String, String)>,
    ) -> Self {
        Self {
            heights_m,
            dx_m,
            dy_m,
            format,
            position_m: None,
            metadata,
        }
    }

    /// Whether the map is a line scan (a profile: n × 1, metadata `line_scan`).
    pub fn is_line_scan(&self) -> bool {
        self.heights_m.ncols() == 1
            && self
                .metadata
                .iter()
                .any(|(k, v)| k == "line_scan" && v == "true")
    }

    /// The value of a metadata key (the first, if the file gives it twice).
    pub fn meta(&self, key: &str) -> Option<&str> {
        lookup(&self.metadata, key).map(String::as_str)
    }

    /// The axis, `x` or `y`, along which the instrument scanned each line
    /// (its fast axis), where the file says (metadata [`FAST_AXIS`]).
    pub fn fast_axis(&self) -> Option<&str> {
        self.meta(FAST_AXIS)
            .filter(|axis| matches!(*axis, "x" | "y"))
    }
}

/// Metadata key of the fast (line) scan axis, `x` or `y`, set by the readers
/// whose format says how a line was scanned: the AFM formats store a
/// scan line per row (Nanoscope `Samps/line`, Nanosurf `Points` per line,
/// Asylum `ScanPoints`, PicoView rows of `xPixels`), which is the map's x.
pub const FAST_AXIS: &str = "fast_axis";

/// The value of the first pair named `key` in (name, value) pairs, as
/// headers, attribute lists and metadata hold them.
pub(crate) fn lookup<'a, V>(pairs: &'a [(String, V)], key: &str) -> Option<&'a V> {
    pairs.iter().find(|(k, _)| k == key).map(|(_, v)| v)
}

/// Why a file could not be read. Messages say what was expected and where
/// (byte offset, line, XML element or header key), never only "invalid".
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum FormatError {
    #[error(
        "not a height-map format hypercontact reads (found {0}); the formats read are {formats}",
        formats = Format::all_names()
    )]
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
    /// The channel asked for is not in the file; the message lists those that are.
    #[error("{format}: {message}")]
    NoSuchChannel {
        format: &'static str,
        message: String,
    },
}

/// The format of a file from its bytes; the extension decides only where
/// the bytes alone cannot.
///
/// Every format with a magic number is told by its first 384 bytes (an Igor
/// wave's headers, whose checksum is its magic; the other magics take at
/// most 32). Sensofar `.plu` (and `.apx`, the same layout: SurfaceTopography
/// 1.27's PLU reader takes both) has none: it is recognised only by its
/// extension together with a header that agrees with the whole file (grid
/// sizes, pixel size, measurement type, a first layer that fits in the
/// file), so pass the whole file, not only its first bytes. A plain-text
/// matrix has none either: a `.txt`, `.asc` or `.dat` file whose first lines
/// are text with a row of numbers.
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
        (Format::Al3d, al3d::matches),
        (Format::Nanoscope, nanoscope::matches),
        (Format::Frt, frt::matches),
        (Format::Mnt, mnt::matches),
        (Format::Nid, nid::matches),
        (Format::Ibw, ibw::matches),
        (Format::Mi, mi::matches),
        (Format::Tmd, tmd::matches),
        (Format::NetCdf, netcdf::matches),
        (Format::DektakCsv, dektak::matches),
        (Format::AsciiMatrix, ascii::matches),
    ];
    if let Some((format, _)) = by_bytes.iter().find(|(_, m)| m(bytes)) {
        return Some(*format);
    }
    let extension = path?.extension()?.to_str()?.to_ascii_lowercase();
    match extension.as_str() {
        "plu" | "apx" if plu::plausible(bytes) => Some(Format::Plu),
        "txt" | "asc" | "dat" if ascii::plausible(bytes) => Some(Format::AsciiMatrix),
        _ => None,
    }
}

/// What a file no reader recognises is, for messages: "an empty file",
/// "a PNG image (first bytes …)", or its first bytes (and text).
pub fn describe(bytes: &[u8]) -> String {
    channel::describe_start(bytes)
}

/// The format a file's extension names, if any (what the user meant the
/// file to be, for a message when its bytes say otherwise).
pub fn format_of_extension(path: &Path) -> Option<Format> {
    let extension = path.extension()?.to_str()?.to_ascii_lowercase();
    let format = match extension.as_str() {
        "npy" => Format::Npy,
        "x3p" => Format::X3p,
        "sur" => Format::Sur,
        "plu" | "apx" => Format::Plu,
        "datx" => Format::Datx,
        "opd" => Format::Opd,
        "al3d" => Format::Al3d,
        "di" | "spm" => Format::Nanoscope,
        "frt" => Format::Frt,
        "mnt" => Format::Mnt,
        "nid" | "ezd" => Format::Nid,
        "ibw" => Format::Ibw,
        "mi" => Format::Mi,
        "tmd" => Format::Tmd,
        "nc" => Format::NetCdf,
        "dat" => Format::MetroPro,
        _ => return None,
    };
    Some(format)
}

/// Reads a height map from a file's bytes, the default channel of a
/// multi-channel file; `path` only helps [`detect`]. Never panics, whatever
/// the bytes.
pub fn read_bytes(bytes: &[u8], path: Option<&Path>) -> Result<Topography, FormatError> {
    read_bytes_channel(bytes, path, &Channel::Default)
}

/// [`read_bytes_channel`] with the points limit [`DEFAULT_MAX_POINTS`].
pub fn read_bytes_channel(
    bytes: &[u8],
    path: Option<&Path>,
    channel: &Channel,
) -> Result<Topography, FormatError> {
    read_bytes_limited(bytes, path, channel, DEFAULT_MAX_POINTS)
}

/// Reads one channel of a file's bytes (by name or index; see [`Channel`]);
/// a single-channel file takes [`Channel::Default`], index 0 or its one
/// channel's name. A header claiming more than `max_points` points (at most
/// [`MAX_POINTS_CEILING`]) is refused before its points are allocated or
/// inflated. Never panics, whatever the bytes.
pub fn read_bytes_limited(
    bytes: &[u8],
    path: Option<&Path>,
    channel: &Channel,
    max_points: usize,
) -> Result<Topography, FormatError> {
    let Some(format) = detect(bytes, path) else {
        return Err(FormatError::Unknown(channel::describe_start(bytes)));
    };
    let single = |name: &str, read: fn(&[u8], usize) -> Result<Topography, FormatError>| {
        channel::single(format, name, channel)?;
        read(bytes, max_points).map(|map| channel::named(map, name))
    };
    match format {
        Format::Npy => Err(FormatError::Unsupported {
            format: format.name(),
            message: "holds no grid spacing: read it as a field with pixel_m".into(),
        }),
        Format::X3p => single("heights", x3p::read),
        Format::Sur => single("heights", sur::read),
        Format::Plu => single("heights", plu::read),
        Format::MetroPro => single("phase", metropro::read),
        Format::Datx => single("surface", datx::read),
        Format::Opd => single("heights", opd::read),
        Format::Al3d => single("Default", al3d::read),
        Format::Frt => single("default", frt::read),
        Format::Mnt => single("Default", mnt::read),
        Format::Tmd => single("Default", tmd::read),
        Format::NetCdf => single("heights", netcdf::read),
        Format::DektakCsv => single("default", dektak::read),
        Format::Nanoscope => nanoscope::read(bytes, channel, max_points),
        Format::Nid => nid::read(bytes, channel, max_points),
        Format::Ibw => ibw::read(bytes, channel, max_points),
        Format::Mi => mi::read(bytes, channel, max_points),
        Format::AsciiMatrix => ascii::read(bytes, channel, max_points),
    }
}
